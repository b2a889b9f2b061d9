//! Verification of the BSQL system (paper eqs. (8)–(18)) on a 2-DOF mass on a moving belt
//! with falling friction μ(v_rel) = μ0 − a·v_rel and one contact constraint G = [0, 1].

mod common;

use common::{peaks, slope, Belt};
use squeal_solver::bdf::{consistent_initial_conditions, Bdf, BdfOptions, BdfState, InitialConditionOptions, Status};
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
fn initial(sys: &mut squeal_solver::bsql::BsqlSystem<common::BeltFriction>, b: &Belt) -> (Vec<Real>, Vec<Real>) {
    let ss = steady_state(sys, 0.0, &SteadyOptions::default()).unwrap();
    // Reference: K u + Gᵀλ' = P + F_f(λ', 0) → λ' = N, x = N(μ0 − aV)/k, z = 0.
    assert!((ss.lambda_dot[0] - b.n_load).abs() < 1e-9 * b.n_load);
    let x_eq = b.n_load * (b.mu0 - b.a * b.v_belt) / b.k;
    assert!((ss.u[0] - x_eq).abs() < 1e-10 && ss.u[1].abs() < 1e-12, "{ss:?}");
    let (mut y0, mut yp0) = ss.initial_values();
    y0[0] = 0.05;
    consistent_initial_conditions(sys, 0.0, &mut y0, &mut yp0, None, &InitialConditionOptions::default()).unwrap();
    // F_v = 0 at the kick: m v' = −c·0.05 + N·a·0.05 (friction change) with λ' = N.
    let vp_ref = (-b.c * 0.05 + b.n_load * b.a * 0.05) / b.m;
    assert!((yp0[0] - vp_ref).abs() < 1e-9, "v'0 = {} vs {vp_ref}", yp0[0]);
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
fn constraint_drift_stays_at_newton_tolerance_and_energy_balance_closes() {
    // Decaying, damped, friction-driven case; 30 periods.
    let b = belt(0.7);
    let mut sys = b.system(BsqlOptions::default());
    let (y0, yp0) = initial(&mut sys, &b);
    let opts = options(&sys);
    let rtol = 1e-7;
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
    let drift = sys.stats().max_constraint_drift;
    println!("drift: initial {drift0:e}, max {drift:e}; v_max {v_max}; balance {bal:?}; residual {:e}", bal.residual());
    // Drift: G v' = 0 is solved by Newton to 0.33 × the error-test weight (rtol|v| + atol);
    // G v then moves only by the Newton remainder, far below one such unit.
    assert_eq!(drift0, 0.0);
    assert!(drift <= 0.33 * (rtol * v_max + 1e-9), "drift {drift}");
    // Energy: friction work in, damping out; the balance closes to the integration tolerance
    // relative to the largest energy term (trapezoidal quadrature over accepted steps).
    assert!(bal.friction_work > 0.0 && bal.damping_dissipated > 0.0);
    let rel = bal.residual().abs() / bal.scale();
    assert!(rel < 10.0 * rtol, "relative energy balance error {rel:e}");
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
    assert!(bdf1.integrate_to(&mut sys1, 0.5 * t_end).unwrap().is_success());
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
    println!("restart: max |Δy| = {diff:e}, steps {steps_ref} vs {}", bdf2.stats().steps);
    assert!(diff <= 1e-10, "restart differs by {diff}");
    assert_eq!(bdf2.stats().steps, steps_ref);
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
        LoadHistory { p_pre: vec![1.0, 0.0], ..Default::default() },
        NoFriction,
        BsqlOptions::default(),
    )
    .unwrap();
    let e = steady_state(&mut sys, 0.0, &SteadyOptions::default()).unwrap_err();
    assert!(e.to_string().contains("singular"), "{e}");
    let y0 = vec![0.0; 6];
    let mut bdf = Bdf::new(BdfOptions::default(), 0.0, &y0, &y0).unwrap();
    let st = bdf.integrate_to(&mut sys, 1.0).unwrap();
    assert!(matches!(st, Status::ConvergenceFailures { t, h, order: 1, .. } if t == 0.0 && h > 0.0), "{st:?}");
}
