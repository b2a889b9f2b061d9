//! Verification of the BSQL system (paper eqs. (8)–(18)) on a 2-DOF mass on a moving belt
//! with falling friction μ(v_rel) = μ0 − a·v_rel and one contact constraint G = [0, 1].

mod common;

use common::{peaks, slope, Belt};
use squeal_solver::bdf::{
    consistent_initial_conditions, Bdf, BdfOptions, BdfState, InitialConditionOptions, Status,
};
use squeal_solver::bsql::{steady_state, BsqlOptions, EnergyBalance, SteadyOptions};
use squeal_solver::Real;

/// Belt with growth (c < N a) or decay (c > N a); ω = 2π, N = 10, a = 0.05, V = 1.
fn belt(c: Real) -> Belt {
    Belt {
        m: 1.0,
        k: (2.0 * std::f64::consts::PI).powi(2),
        c,
        n_load: 10.0,
        mu0: 0.5,
        a: 0.05,
        v_belt: 1.0,
    }
}

/// Steady sliding state, then a velocity kick of 0.05 on the tangential DOF, then consistent
/// initial derivatives. Returns (y0, y0').
fn initial(
    sys: &mut squeal_solver::bsql::BsqlSystem<common::BeltFriction>,
    b: &Belt,
) -> (Vec<Real>, Vec<Real>) {
    let ss = steady_state(sys, 0.0, &SteadyOptions::default()).unwrap();
    // Reference: K u + Gᵀλ' = P + F_f(λ', 0) → λ' = N, x = N(μ0 − aV)/k, z = 0.
    assert!((ss.lambda_dot[0] - b.n_load).abs() < 1e-9 * b.n_load);
    let x_eq = b.n_load * (b.mu0 - b.a * b.v_belt) / b.k;
    assert!(
        (ss.u[0] - x_eq).abs() < 1e-10 && ss.u[1].abs() < 1e-12,
        "{ss:?}"
    );
    let (mut y0, mut yp0) = ss.initial_values();
    y0[0] = 0.05;
    consistent_initial_conditions(
        sys,
        0.0,
        &mut y0,
        &mut yp0,
        None,
        &InitialConditionOptions::default(),
    )
    .unwrap();
    // F_v = 0 at the kick: m v' = −c·0.05 + N·a·0.05 (friction change) with λ' = N.
    let vp_ref = (-b.c * 0.05 + b.n_load * b.a * 0.05) / b.m;
    assert!(
        (yp0[0] - vp_ref).abs() < 1e-9,
        "v'0 = {} vs {vp_ref}",
        yp0[0]
    );
    assert!((yp0[2] - b.n_load).abs() < 1e-9);
    (y0, yp0)
}

fn options(sys: &squeal_solver::bsql::BsqlSystem<common::BeltFriction>) -> BdfOptions {
    BdfOptions {
        tolerances: sys.tolerances(1e-7, 1e-9, 1e-7, 1e-9),
        ..Default::default()
    }
}

/// Integrate 12 periods, sample v_x every 1/200 s, fit log(peaks) → growth rate.
fn measured_sigma(c: Real, damping_in_jacobian: bool) -> (Real, Real) {
    let b = belt(c);
    let mut sys = b.system(BsqlOptions {
        include_friction_damping: damping_in_jacobian,
        ..Default::default()
    });
    let (y0, yp0) = initial(&mut sys, &b);
    let mut bdf = Bdf::new(options(&sys), 0.0, &y0, &yp0).unwrap();
    let (mut ts, mut vs) = (vec![0.0], vec![y0[0]]);
    for i in 1..=2400 {
        let t = i as Real / 200.0;
        assert!(bdf.integrate_to(&mut sys, t).unwrap().is_success());
        ts.push(t);
        vs.push(bdf.y()[0]);
    }
    let pk = peaks(&ts, &vs);
    assert!(pk.len() >= 10, "{} peaks", pk.len());
    let (pt, pv): (Vec<Real>, Vec<Real>) = pk.iter().map(|&(t, v)| (t, v.ln())).unzip();
    let s = slope(&pt, &pv);
    let st = bdf.stats();
    println!(
        "belt c = {c}: σ measured {s:.6}, theory {:.6}; steps {}, newton {}, setups {}, residuals {}, etf {}, ncf {}, orders {:?}",
        b.sigma(),
        st.steps,
        st.newton_iterations,
        st.jacobian_setups,
        st.residual_evals,
        st.error_test_failures,
        st.convergence_failures,
        st.order_histogram
    );
    (s, b.sigma())
}

#[test]
fn belt_falling_friction_grows_at_linearised_rate() {
    // c = 0.3 < N a = 0.5: σ = −(c − N a)/(2m) = +0.1 (negative effective damping).
    let (s, sigma) = measured_sigma(0.3, true);
    assert!(sigma > 0.0);
    assert!((s - sigma).abs() < 0.01 * sigma.abs(), "σ = {s} vs {sigma}");
}

#[test]
fn belt_with_enough_damping_decays_at_linearised_rate() {
    // c = 0.7 > N a = 0.5: σ = −0.1. Friction damping left out of J (paper's default).
    let (s, sigma) = measured_sigma(0.7, false);
    assert!(sigma < 0.0);
    assert!((s - sigma).abs() < 0.01 * sigma.abs(), "σ = {s} vs {sigma}");
}

#[test]
fn energy_balance_closes_on_damped_friction_driven_belt() {
    // Decaying, damped, friction-driven case; 30 periods.
    let b = belt(0.7);
    let mut sys = b.system(BsqlOptions::default());
    let (y0, yp0) = initial(&mut sys, &b);
    let opts = options(&sys);
    let mut bdf = Bdf::new(opts, 0.0, &y0, &yp0).unwrap();
    let mut bal = EnergyBalance::new();
    let p0 = sys.observe(0.0, &y0, &yp0).unwrap();
    bal.push(&p0);
    let drift0 = sys.stats().constraint_drift;
    let mut v_max: Real = 0.0;
    let st = bdf
        .step_to(&mut sys, 30.0, |s, t, y, yp| {
            let p = s.observe(t, y, yp)?;
            v_max = v_max.max(y[0].abs());
            bal.push(&p);
            Ok(true)
        })
        .unwrap();
    assert!(st.is_success());
    println!(
        "balance {bal:?}; residual {:e}; drift {drift0:e}, v_max {v_max}",
        bal.residual()
    );
    // Energy: friction work in, damping out. The exact solution satisfies
    // d(T + V)/dt = P·v + F_f·v − (Gᵀλ')·v − vᵀBv; the powers are integrated with the
    // trapezoidal rule over the accepted steps, whose error the accumulator estimates
    // (Σ h³/12·|f''|). The balance must close within that estimate, and far below the
    // work terms themselves.
    assert!(bal.friction_work > 0.0 && bal.damping_dissipated > 0.0);
    let work = bal.friction_work + bal.damping_dissipated;
    assert!(
        bal.residual().abs() <= bal.quadrature_error,
        "residual {:e} > quadrature estimate {:e}",
        bal.residual(),
        bal.quadrature_error
    );
    assert!(
        bal.residual().abs() < 1e-3 * work,
        "residual {:e} vs work {work:e}",
        bal.residual()
    );
}

#[test]
fn restart_from_saved_state_reproduces_uninterrupted_run() {
    let b = belt(0.3);
    let t_end = 4.0;
    // Uninterrupted.
    let mut sys = b.system(BsqlOptions::default());
    let (y0, yp0) = initial(&mut sys, &b);
    let mut bdf = Bdf::new(options(&sys), 0.0, &y0, &yp0).unwrap();
    assert!(bdf.integrate_to(&mut sys, t_end).unwrap().is_success());
    let y_ref = bdf.y().to_vec();
    let steps_ref = bdf.stats().steps;
    // Interrupted at T/2, saved as JSON, restored into a fresh system and integrator.
    let mut sys1 = b.system(BsqlOptions::default());
    let (y0, yp0) = initial(&mut sys1, &b);
    let mut bdf1 = Bdf::new(options(&sys1), 0.0, &y0, &yp0).unwrap();
    assert!(bdf1
        .integrate_to(&mut sys1, 0.5 * t_end)
        .unwrap()
        .is_success());
    let json = serde_json::to_string(bdf1.state()).unwrap();
    drop((bdf1, sys1));
    let state: BdfState = serde_json::from_str(&json).unwrap();
    let mut sys2 = b.system(BsqlOptions::default());
    let mut bdf2 = Bdf::from_state(options(&sys2), state).unwrap();
    assert!(bdf2.integrate_to(&mut sys2, t_end).unwrap().is_success());
    let diff = y_ref
        .iter()
        .zip(bdf2.y())
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    println!(
        "restart: max |Δy| = {diff:e}, steps {steps_ref} vs {}",
        bdf2.stats().steps
    );
    assert!(diff <= 1e-10, "restart differs by {diff}");
    assert_eq!(bdf2.stats().steps, steps_ref);
    // An in-memory copy of the state (no decimal round trip) reproduces the run bit for bit.
    let mut sys3 = b.system(BsqlOptions::default());
    let (y0, yp0) = initial(&mut sys3, &b);
    let mut bdf3 = Bdf::new(options(&sys3), 0.0, &y0, &yp0).unwrap();
    assert!(bdf3
        .integrate_to(&mut sys3, 0.5 * t_end)
        .unwrap()
        .is_success());
    let state = bdf3.state().clone();
    let mut sys4 = b.system(BsqlOptions::default());
    let mut bdf4 = Bdf::from_state(options(&sys4), state).unwrap();
    assert!(bdf4.integrate_to(&mut sys4, t_end).unwrap().is_success());
    assert_eq!(bdf4.y(), &y_ref[..]);
}

#[test]
fn rank_deficient_constraints_give_clean_failure() {
    use faer::Mat;
    use squeal_solver::bsql::{BsqlSystem, LoadHistory, NoFriction};
    // Two identical constraint rows: the saddle matrix is singular for every cj.
    let mut g = Mat::zeros(2, 2);
    g[(0, 1)] = 1.0;
    g[(1, 1)] = 1.0;
    let mut sys = BsqlSystem::new(
        Mat::identity(2, 2),
        Mat::zeros(2, 2),
        Mat::identity(2, 2),
        g,
        LoadHistory {
            p_pre: vec![1.0, 0.0],
            ..Default::default()
        },
        NoFriction,
        BsqlOptions::default(),
    )
    .unwrap();
    let e = steady_state(&mut sys, 0.0, &SteadyOptions::default()).unwrap_err();
    assert!(e.to_string().contains("singular"), "{e}");
    let y0 = vec![0.0; 6];
    let mut bdf = Bdf::new(BdfOptions::default(), 0.0, &y0, &y0).unwrap();
    let st = bdf.integrate_to(&mut sys, 1.0).unwrap();
    assert!(
        matches!(st, Status::ConvergenceFailures { t, h, order: 1, .. } if t == 0.0 && h > 0.0),
        "{st:?}"
    );
}

#[test]
fn constraint_drift_stays_at_newton_tolerance_on_coupled_model() {
    use faer::Mat;
    use squeal_solver::bsql::{BsqlSystem, LoadHistory};
    // 3 coupled DOFs, one oblique contact constraint G = [0.3, 1, −0.5], friction from the
    // belt law on DOF 0 driven by the contact force λ'.
    let m = [[1.0, 0.1, 0.0], [0.1, 2.0, 0.2], [0.0, 0.2, 1.5]];
    let k = [[40.0, -10.0, 0.0], [-10.0, 60.0, -15.0], [0.0, -15.0, 30.0]];
    let mat = |a: [[Real; 3]; 3]| Mat::from_fn(3, 3, |i, j| a[i][j]);
    let bmat = Mat::from_fn(3, 3, |i, j| 0.02 * k[i][j]);
    let g = Mat::from_fn(1, 3, |_, j| [0.3, 1.0, -0.5][j]);
    let fr = common::BeltFriction {
        mu0: 0.5,
        a: 0.05,
        v_belt: 1.0,
    };
    let load = LoadHistory {
        p_pre: vec![0.0, 10.0, 0.0],
        ..Default::default()
    };
    let mut sys =
        BsqlSystem::new(mat(m), bmat, mat(k), g, load, fr, BsqlOptions::default()).unwrap();
    let ss = steady_state(&mut sys, 0.0, &SteadyOptions::default()).unwrap();
    // G u = 0 at the steady state (position form of the constraint, paper eq. (9)).
    assert!((0.3 * ss.u[0] + ss.u[1] - 0.5 * ss.u[2]).abs() < 1e-12);
    let (mut y0, mut yp0) = ss.initial_values();
    y0[0] = 0.05; // G v = 0.3·0.05 − 0.5·0.03 = 0
    y0[2] = 0.03;
    consistent_initial_conditions(
        &mut sys,
        0.0,
        &mut y0,
        &mut yp0,
        None,
        &InitialConditionOptions::default(),
    )
    .unwrap();
    let (rtol, atol) = (1e-6, 1e-8);
    let opts = BdfOptions {
        tolerances: sys.tolerances(rtol, atol, rtol, atol),
        ..Default::default()
    };
    let mut bdf = Bdf::new(opts, 0.0, &y0, &yp0).unwrap();
    sys.observe(0.0, &y0, &yp0).unwrap();
    let drift0 = sys.stats().constraint_drift;
    let mut v_max: Real = 0.0;
    let st = bdf
        .step_to(&mut sys, 20.0, |s, t, y, yp| {
            s.observe(t, y, yp)?;
            v_max = v_max.max(y[..3].iter().fold(0.0, |m: Real, x| m.max(x.abs())));
            Ok(true)
        })
        .unwrap();
    assert!(st.is_success(), "{st:?}");
    let drift = sys.stats().max_constraint_drift;
    println!(
        "coupled drift: initial {drift0:e}, max {drift:e}, v_max {v_max}, stats {:?}",
        bdf.stats()
    );
    // Reference: G v' = 0 (eq. (11)) is satisfied to the Newton tolerance, 0.33 in the
    // weighted norm, i.e. |δv_i| ≲ 0.33·(rtol|v_i| + atol) per step; G v may move by no more
    // than ‖G‖₁ times that unit over the run.
    assert!(drift0 < 1e-15);
    assert!(
        drift <= 1.8 * 0.33 * (rtol * v_max + atol),
        "drift {drift:e}"
    );
}

#[test]
fn iteration_matrix_solve_inverts_finite_difference_jacobian() {
    use squeal_solver::bdf::DaeSystem;
    // With C_f included, solve_jacobian must invert J = ∂F/∂y + cj ∂F/∂y' (eq. (18)); check
    // J·x by central differences of the residual, then solve back to x.
    let b = belt(0.3);
    let mut sys = b.system(BsqlOptions {
        include_friction_damping: true,
        ..Default::default()
    });
    let (y0, yp0) = initial(&mut sys, &b);
    let cj = 250.0;
    let x: Vec<Real> = (0..5).map(|i| 0.1 + 0.37 * i as Real).collect();
    let eps = 1e-6;
    let mut rp = vec![0.0; 5];
    let mut rm = vec![0.0; 5];
    let shift = |s: Real| -> (Vec<Real>, Vec<Real>) {
        (
            y0.iter().zip(&x).map(|(a, d)| a + s * d).collect(),
            yp0.iter().zip(&x).map(|(a, d)| a + s * cj * d).collect(),
        )
    };
    let (yp_, ypp) = shift(eps);
    sys.residual(0.0, &yp_, &ypp, &mut rp).unwrap();
    let (ym, ypm) = shift(-eps);
    sys.residual(0.0, &ym, &ypm, &mut rm).unwrap();
    let mut jx: Vec<Real> = rp
        .iter()
        .zip(&rm)
        .map(|(a, b)| (a - b) / (2.0 * eps))
        .collect();
    sys.setup_jacobian(0.0, &y0, &yp0, cj).unwrap();
    sys.solve_jacobian(&mut jx).unwrap();
    for (a, b) in jx.iter().zip(&x) {
        assert!((a - b).abs() < 1e-7 * b.abs().max(1.0), "{jx:?} vs {x:?}");
    }
}
