//! Verification of the generalized-α integrator (Chung–Hulbert 1993 in the Arnold–Brüls 2007
//! form, `squeal_solver::galpha`) against analytic references and against the BDF.

mod common;

use common::{Belt, BeltFriction};
use faer::Mat;
use num_complex::Complex64;
use squeal_solver::bdf::Tolerances;
use squeal_solver::bdf::{consistent_initial_conditions, Bdf, BdfOptions, InitialConditionOptions};
use squeal_solver::bsql::{BsqlOptions, BsqlSystem, FrictionForces, LoadHistory, NoFriction};
use squeal_solver::galpha::{
    algorithmic_damping, spectral_radius, Galpha, GalphaCoeffs, GalphaOptions, GalphaStats,
    GalphaSystem,
};
use squeal_solver::Real;

use std::f64::consts::PI;

/// Tight Newton tolerances: in fixed-step mode they only set the Newton test.
fn tight() -> Tolerances {
    Tolerances::Scalar {
        rtol: 1e-10,
        atol: 1e-13,
    }
}

/// 1-DOF undamped oscillator x'' + ω² x = 0 without constraints (ng = 0).
fn oscillator(omega: Real) -> GalphaSystem<NoFriction> {
    GalphaSystem::new(
        Mat::identity(1, 1),
        Mat::zeros(1, 1),
        Mat::from_fn(1, 1, |_, _| omega * omega),
        Mat::zeros(0, 1),
        LoadHistory::default(),
        NoFriction,
    )
    .unwrap()
}

/// Fixed-step run of the oscillator from x = 1, v = 0; returns (t, x, v) at every step.
fn run_oscillator(rho_inf: Real, omega: Real, h: Real, t_end: Real) -> Vec<(Real, Real, Real)> {
    let mut sys = oscillator(omega);
    let opts = GalphaOptions {
        rho_inf,
        h,
        tolerances: tight(),
        ..Default::default()
    };
    // y = {v, u}, y' = {q̈, v}; q̈0 is solved for by `new`.
    let mut ga = Galpha::new(opts, &mut sys, 0.0, &[0.0, 1.0], &[0.0, 0.0]).unwrap();
    assert!(
        (ga.yp()[0] + omega * omega).abs() < 1e-12,
        "q̈0 = {}",
        ga.yp()[0]
    );
    let mut out = vec![(0.0, 1.0, 0.0)];
    let st = ga
        .step_to(&mut sys, t_end, |_, t, y, _| {
            out.push((t, y[1], y[0]));
            Ok(true)
        })
        .unwrap();
    assert!(st.is_success(), "{st:?}");
    out
}

#[test]
fn second_order_convergence_on_undamped_oscillator() {
    // Exact solution x = cos ωt, v = −ω sin ωt; error at t = 2 periods (a step point for
    // every h below) in the energy norm.
    let omega = 2.0 * PI;
    let t_end = 2.0;
    let mut errs = Vec::new();
    for h in [0.02, 0.01, 0.005, 0.0025] {
        let out = run_oscillator(0.9, omega, h, t_end);
        let &(t, x, v) = out.last().unwrap();
        assert!((t - t_end).abs() < 1e-12, "last step at {t}");
        let e = ((x - (omega * t).cos()).powi(2)
            + ((v + omega * (omega * t).sin()) / omega).powi(2))
        .sqrt();
        errs.push(e);
    }
    let ratios: Vec<Real> = errs.windows(2).map(|w| w[0] / w[1]).collect();
    println!("oscillator errors {errs:?}, ratios {ratios:?}");
    // Second order: halving h divides the error by 4.
    for r in ratios {
        assert!((r - 4.0).abs() < 0.1, "ratio {r}");
    }
}

/// Measured damping ratio and frequency from z_n = x_n − i v_n/ω, which for the principal
/// root is c·ξⁿ after the spurious root (|ξ₃| ≈ α_m/(1−α_m) ≤ 0.73) has decayed.
fn measured_root(rho_inf: Real, omega: Real, wh: Real, periods: Real) -> (Real, Real) {
    let h = wh / omega;
    let out = run_oscillator(rho_inf, omega, h, periods * 2.0 * PI / omega);
    let zs: Vec<(Real, Complex64)> = out
        .iter()
        .map(|&(t, x, v)| (t, Complex64::new(x, -v / omega)))
        .collect();
    let skip = 200;
    let (t_a, z_a) = zs[skip];
    let (t_b, z_b) = *zs.last().unwrap();
    let re = (z_b.norm() / z_a.norm()).ln() / (t_b - t_a);
    let mut phase = 0.0;
    for w in zs[skip..].windows(2) {
        phase += (w[1].1 / w[0].1).arg();
    }
    let im = phase / (t_b - t_a);
    (-re / (re * re + im * im).sqrt(), im)
}

#[test]
fn numerical_damping_matches_amplification_matrix() {
    let (omega, wh) = (3.0, 0.1);
    for rho in [0.9, 0.5, 1.0] {
        let co = GalphaCoeffs::from_rho_inf(rho);
        let th = algorithmic_damping(&co, wh);
        // Definition of ρ∞: the spectral radius as ωh → ∞.
        let r_inf = spectral_radius(&co, 1e7);
        assert!((r_inf - rho).abs() < 1e-4, "ρ(∞) = {r_inf} for ρ∞ = {rho}");
        // Leading-order expansion ζ ≈ ½((1−ρ∞)/(1+ρ∞))³(ωh)³ (numpy on the same
        // amplification matrix: 7.2769e-8 at ρ∞ = 0.9, 1.8419e-5 at ρ∞ = 0.5).
        let lead = 0.5 * ((1.0 - rho) / (1.0 + rho)).powi(3) * wh.powi(3);
        let (zeta, im) = measured_root(rho, omega, wh, 200.0);
        let im_theory = th.omega_h / (1.0 + th.period_error) / (wh / omega);
        println!(
            "ρ∞ = {rho}: ζ measured {zeta:.6e}, theory {:.6e}, leading order {lead:.6e}; \
             period error {:.4e}; ω̂ measured {im:.9}, theory {im_theory:.9}; BDF2 2.4471e-4",
            th.zeta, th.period_error
        );
        assert!(
            (im - im_theory).abs() < 1e-7 * omega,
            "frequency {im} vs {im_theory}"
        );
        if rho == 1.0 {
            // Trapezoidal rule: |ξ| = 1 exactly, no numerical damping.
            assert!(th.zeta.abs() < 1e-14, "theory {}", th.zeta);
            assert!(zeta.abs() < 1e-9, "measured {zeta}");
        } else {
            assert!(
                (th.zeta - lead).abs() < 0.01 * lead,
                "{} vs {lead}",
                th.zeta
            );
            assert!(
                (zeta - th.zeta).abs() < 0.01 * th.zeta,
                "measured {zeta} vs theory {}",
                th.zeta
            );
        }
    }
    // The default ρ∞ = 0.9 damps 3 000× less than BDF2 (2.4471e-4) at ωh = 0.1.
    let z9 = algorithmic_damping(&GalphaCoeffs::from_rho_inf(0.9), 0.1).zeta;
    assert!(z9 < 2.4471e-4 / 3000.0, "{z9}");
}

/// The matrices of `common::Belt::system` (DOF 0 tangential, DOF 1 normal with m_z = 2,
/// k_z = 50, G = [0, 1], preload N on DOF 1) as a generalized-α system.
fn belt_galpha(b: &Belt) -> GalphaSystem<BeltFriction> {
    let mm = Mat::from_fn(2, 2, |i, j| [[b.m, 0.0], [0.0, 2.0]][i][j]);
    let bb = Mat::from_fn(2, 2, |i, j| if i == 0 && j == 0 { b.c } else { 0.0 });
    let kk = Mat::from_fn(2, 2, |i, j| [[b.k, 0.0], [0.0, 50.0]][i][j]);
    let g = Mat::from_fn(1, 2, |_, j| j as Real);
    let load = LoadHistory {
        p_pre: vec![0.0, b.n_load],
        ..Default::default()
    };
    let fr = BeltFriction {
        mu0: b.mu0,
        a: b.a,
        v_belt: b.v_belt,
    };
    GalphaSystem::new(mm, bb, kk, g, load, fr).unwrap()
}

/// Belt with ω = 2π, N = 10, a = 0.05, V = 1 and damping c (as in bsql_verification.rs).
fn belt(c: Real) -> Belt {
    Belt {
        m: 1.0,
        k: (2.0 * PI).powi(2),
        c,
        n_load: 10.0,
        mu0: 0.5,
        a: 0.05,
        v_belt: 1.0,
    }
}

/// Initial state of the belt runs: steady sliding (x = N(μ0 − aV)/k, λ' = N) plus a
/// velocity kick 0.05, as y = {v, λ, u} and a guess for y'.
fn belt_initial(b: &Belt) -> (Vec<Real>, Vec<Real>) {
    let x_eq = b.n_load * (b.mu0 - b.a * b.v_belt) / b.k;
    let y0 = vec![0.05, 0.0, 0.0, x_eq, 0.0];
    let yp0 = vec![0.0, 0.0, b.n_load, 0.05, 0.0];
    (y0, yp0)
}

/// Growth rate from the envelope |w(t)| with w = v − s̄ (x − x_eq), s = σ + iω_d the exact
/// root of m s² + (c − N a) s + k = 0: for the exact solution w = C e^{st}, so ln|w| is a
/// straight line of slope σ; for a numerical solution with root ŝ it has slope Re ŝ plus a
/// ripple of relative size |ŝ − s|/(2ω_d). Least-squares slope over t ≥ 1 s.
fn envelope_rate(b: &Belt, samples: &[(Real, Real, Real)]) -> Real {
    let sigma = b.sigma();
    let wd = (b.k / b.m - sigma * sigma).sqrt();
    let s_conj = Complex64::new(sigma, -wd);
    let x_eq = b.n_load * (b.mu0 - b.a * b.v_belt) / b.k;
    let (ts, ls): (Vec<Real>, Vec<Real>) = samples
        .iter()
        .filter(|s| s.0 >= 1.0)
        .map(|&(t, v, x)| (t, (Complex64::from(v) - s_conj * (x - x_eq)).norm().ln()))
        .unzip();
    common::slope(&ts, &ls)
}

/// Fixed-step generalized-α on the belt: the measured growth rate.
fn belt_galpha_rate(b: &Belt, h: Real, t_end: Real) -> Real {
    let mut sys = belt_galpha(b);
    let (y0, yp0) = belt_initial(b);
    let opts = GalphaOptions {
        h,
        tolerances: tight(),
        ..Default::default()
    };
    let mut ga = Galpha::new(opts, &mut sys, 0.0, &y0, &yp0).unwrap();
    // Consistent start: m v' = −c·0.05 + N a·0.05, λ' = N (see bsql_verification.rs).
    let vp_ref = (-b.c * 0.05 + b.n_load * b.a * 0.05) / b.m;
    assert!((ga.yp()[0] - vp_ref).abs() < 1e-10 && (ga.yp()[2] - b.n_load).abs() < 1e-10);
    let mut samples = vec![(0.0, y0[0], y0[3])];
    let st = ga
        .step_to(&mut sys, t_end, |_, t, y, _| {
            samples.push((t, y[0], y[3]));
            Ok(true)
        })
        .unwrap();
    assert!(st.is_success(), "{st:?}");
    println!("generalized-α belt h = {h}: {:?}", ga.stats());
    envelope_rate(b, &samples)
}

/// Fixed-step BDF2 on the same belt (BsqlSystem, same matrices).
fn belt_bdf2_rate(b: &Belt, h: Real, t_end: Real) -> Real {
    let mut sys = b.system(BsqlOptions {
        include_friction_damping: true,
        ..Default::default()
    });
    let (mut y0, mut yp0) = belt_initial(b);
    consistent_initial_conditions(
        &mut sys,
        0.0,
        &mut y0,
        &mut yp0,
        None,
        &InitialConditionOptions::default(),
    )
    .unwrap();
    let opts = BdfOptions {
        max_order: 2,
        fixed_step: Some(h),
        tolerances: tight(),
        ..Default::default()
    };
    let mut bdf = Bdf::new(opts, 0.0, &y0, &yp0).unwrap();
    let mut samples = vec![(0.0, y0[0], y0[3])];
    let st = bdf
        .step_to(&mut sys, t_end, |_, t, y, _| {
            samples.push((t, y[0], y[3]));
            Ok(true)
        })
        .unwrap();
    assert!(st.is_success(), "{st:?}");
    envelope_rate(b, &samples)
}

#[test]
fn belt_growth_rate_within_half_percent_and_closer_than_bdf2() {
    // m x'' + c x' + k x = N(μ0 − a(V − x')): σ = −(c − N a)/(2m) = +0.1 for c = 0.3
    // (linear in x since λ' = N exactly: the normal DOF is held by G = [0, 1]).
    let b = belt(0.3);
    let sigma = b.sigma();
    let omega = (b.k / b.m).sqrt();
    let h = 0.1 / omega; // ωh = 0.1, 63 steps per period
    let t_end = 12.0;
    let s_ga = belt_galpha_rate(&b, h, t_end);
    let s_bdf = belt_bdf2_rate(&b, h, t_end);
    // Expected from the principal root of each scheme at ζ_phys = −σ/ω: generalized-α
    // adds ≈ ζ̄ω = 7.3e-8·2π (negligible), BDF2 ≈ 2.44e-4·2π = 1.5e-3 (1.5 % of σ).
    let co = GalphaCoeffs::from_rho_inf(0.9);
    let zeta_phys = -sigma / omega;
    let xi = squeal_solver::galpha::principal_root(&co, omega * h, zeta_phys);
    let s_ga_theory = xi.ln().re / h;
    let (e_ga, e_bdf) = ((s_ga - sigma) / sigma, (s_bdf - sigma) / sigma);
    println!(
        "belt σ = {sigma}: generalized-α {s_ga:.7} (rel. err {e_ga:.3e}, root theory {s_ga_theory:.7}), \
         BDF2 {s_bdf:.7} (rel. err {e_bdf:.3e})"
    );
    assert!(e_ga.abs() < 0.005, "generalized-α σ = {s_ga} vs {sigma}");
    assert!(
        (s_ga - s_ga_theory).abs() < 1e-3 * sigma,
        "{s_ga} vs {s_ga_theory}"
    );
    assert!(e_ga.abs() < e_bdf.abs(), "GA {e_ga} vs BDF2 {e_bdf}");
    // BDF2's numerical damping lowers the growth rate by about ζ_BDF2·ω.
    assert!(e_bdf < -0.01, "BDF2 rel. err {e_bdf}");
}

#[test]
fn belt_with_enough_damping_decays_at_linearised_rate() {
    // c = 0.7 > N a: σ = −0.1.
    let b = belt(0.7);
    let h = 0.1 / (b.k / b.m).sqrt();
    let s = belt_galpha_rate(&b, h, 12.0);
    assert!(
        (s - b.sigma()).abs() < 0.005 * b.sigma().abs(),
        "σ = {s} vs {}",
        b.sigma()
    );
}

/// The 3-DOF coupled model of bsql_verification.rs: one oblique contact constraint
/// G = [0.3, 1, −0.5] and the belt friction law on DOF 0 driven by the contact force λ'.
struct Coupled {
    m: Mat<Real>,
    b: Mat<Real>,
    k: Mat<Real>,
    g: Mat<Real>,
    load: LoadHistory,
}

fn coupled() -> Coupled {
    let m = [[1.0, 0.1, 0.0], [0.1, 2.0, 0.2], [0.0, 0.2, 1.5]];
    let k = [[40.0, -10.0, 0.0], [-10.0, 60.0, -15.0], [0.0, -15.0, 30.0]];
    Coupled {
        m: Mat::from_fn(3, 3, |i, j| m[i][j]),
        b: Mat::from_fn(3, 3, |i, j| 0.02 * k[i][j]),
        k: Mat::from_fn(3, 3, |i, j| k[i][j]),
        g: Mat::from_fn(1, 3, |_, j| [0.3, 1.0, -0.5][j]),
        load: LoadHistory {
            p_pre: vec![0.0, 10.0, 0.0],
            ..Default::default()
        },
    }
}

fn friction() -> BeltFriction {
    BeltFriction {
        mu0: 0.5,
        a: 0.05,
        v_belt: 1.0,
    }
}

fn coupled_galpha(c: &Coupled) -> GalphaSystem<BeltFriction> {
    GalphaSystem::new(
        c.m.clone(),
        c.b.clone(),
        c.k.clone(),
        c.g.clone(),
        c.load.clone(),
        friction(),
    )
    .unwrap()
}

fn coupled_bsql(c: &Coupled) -> BsqlSystem<BeltFriction> {
    BsqlSystem::new(
        c.m.clone(),
        c.b.clone(),
        c.k.clone(),
        c.g.clone(),
        c.load.clone(),
        friction(),
        BsqlOptions::default(),
    )
    .unwrap()
}

/// Steady sliding state (from the BSQL steady-state solver) plus a velocity perturbation.
fn coupled_initial(c: &Coupled, v0: [Real; 3]) -> (Vec<Real>, Vec<Real>) {
    let mut sys = coupled_bsql(c);
    let ss = squeal_solver::bsql::steady_state(&mut sys, 0.0, &Default::default()).unwrap();
    let (mut y0, yp0) = ss.initial_values();
    y0[..3].copy_from_slice(&v0);
    (y0, yp0)
}

#[test]
fn constraint_velocity_stays_at_its_initial_value() {
    // G v' = 0 is imposed at every step, so G v must keep its initial (here non-zero) value
    // up to round-off: G v0 = 0.3·0.05 + 0.02 − 0.5·0.03 = 0.02.
    let c = coupled();
    let (y0, yp0) = coupled_initial(&c, [0.05, 0.02, 0.03]);
    let gv0 = 0.3 * 0.05 + 0.02 - 0.5 * 0.03;
    let mut sys = coupled_galpha(&c);
    let opts = GalphaOptions {
        h: 2e-3,
        tolerances: tight(),
        ..Default::default()
    };
    let mut ga = Galpha::new(opts, &mut sys, 0.0, &y0, &yp0).unwrap();
    let (mut drift, mut v_max): (Real, Real) = (0.0, 0.0);
    let st = ga
        .step_to(&mut sys, 20.0, |_, _, y, yp| {
            let gv = 0.3 * y[0] + y[1] - 0.5 * y[2];
            let ga_ = 0.3 * yp[0] + yp[1] - 0.5 * yp[2];
            assert!(ga_.abs() < 1e-12, "G v' = {ga_}");
            drift = drift.max((gv - gv0).abs());
            v_max = v_max.max(y[..3].iter().fold(0.0, |m: Real, x| m.max(x.abs())));
            Ok(true)
        })
        .unwrap();
    assert!(st.is_success(), "{st:?}");
    let stats = ga.stats();
    println!("G v drift {drift:e} (v_max {v_max}), stats {stats:?}");
    // Round-off only: 10 000 steps, each adding O(ε·|v|) to G v.
    assert!(drift < 1e4 * 8.0 * Real::EPSILON * v_max, "drift {drift:e}");
    assert!((stats.max_constraint_drift - drift).abs() < 1e-15);
    // The position constraint then drifts linearly: G u(t) = G u0 + t·G v0 (G u0 = 0).
    let gu = 0.3 * ga.y()[4] + ga.y()[5] - 0.5 * ga.y()[6];
    assert!((gu - 20.0 * gv0).abs() < 1e-9, "G u = {gu}");
}

/// Generalized-α and a tight BDF on the friction-driven coupled model: max over the
/// samples (every 0.01 s to t = 5 s) of |y_GA − y_BDF| per partition, relative to the
/// largest |y_BDF| of that partition; partitions v, λ', u.
fn coupled_difference(h: Real) -> [Real; 3] {
    let c = coupled();
    let (y0, yp0) = coupled_initial(&c, [0.05, 0.0, 0.03]); // G v0 = 0
                                                            // Reference: BDF at rtol 1e-10.
    let mut bs = coupled_bsql(&c);
    let (mut yb, mut ypb) = (y0.clone(), yp0.clone());
    let ic = InitialConditionOptions {
        tol: 1e-13,
        ..Default::default()
    };
    consistent_initial_conditions(&mut bs, 0.0, &mut yb, &mut ypb, None, &ic).unwrap();
    let opts = BdfOptions {
        tolerances: bs.tolerances(1e-10, 1e-12, 1e-10, 1e-12),
        ..Default::default()
    };
    let mut bdf = Bdf::new(opts, 0.0, &yb, &ypb).unwrap();
    let mut gs = coupled_galpha(&c);
    let gopts = GalphaOptions {
        h,
        tolerances: tight(),
        ..Default::default()
    };
    let mut ga = Galpha::new(gopts, &mut gs, 0.0, &y0, &yp0).unwrap();
    let parts = [(0..3, 0), (3..4, 1), (4..7, 2)];
    let (mut diff, mut scale): ([Real; 3], [Real; 3]) = ([0.0; 3], [0.0; 3]);
    for i in 1..=500 {
        let t = i as Real * 0.01;
        assert!(bdf.integrate_to(&mut bs, t).unwrap().is_success());
        assert!(ga.integrate_to(&mut gs, t).unwrap().is_success());
        for (r, p) in parts.iter().cloned() {
            for j in r {
                // λ' (the contact force) from y', the others from y.
                let (a, b) = if p == 1 {
                    (ga.yp()[j], bdf.yp()[j])
                } else {
                    (ga.y()[j], bdf.y()[j])
                };
                diff[p] = diff[p].max((a - b).abs());
                scale[p] = scale[p].max(b.abs());
            }
        }
    }
    println!(
        "h = {h}: GA {:?}\n        BDF {:?}",
        ga.stats(),
        bdf.stats()
    );
    [diff[0] / scale[0], diff[1] / scale[1], diff[2] / scale[2]]
}

#[test]
fn agrees_with_tight_bdf_on_friction_driven_constrained_case() {
    let d1 = coupled_difference(4e-3);
    let d2 = coupled_difference(2e-3);
    let d3 = coupled_difference(1e-3);
    println!("relative max differences (v, λ', u): {d1:?} {d2:?} {d3:?}");
    for p in 0..3 {
        // Second order: the difference (dominated by the GA error) falls 4× per halving.
        for (a, b) in [(d1[p], d2[p]), (d2[p], d3[p])] {
            assert!((a / b - 4.0).abs() < 0.4, "partition {p}: ratio {}", a / b);
        }
        assert!(d3[p] < 1e-4, "partition {p}: {}", d3[p]);
    }
}

#[test]
fn adaptive_steps_follow_the_tolerance() {
    // Local error ∝ h³ held at the tolerance ⇒ h ∝ tol^{1/3}, global error ∝ tol^{2/3}:
    // 100× tighter gives 100^{1/3} ≈ 4.6× more steps and ≈ 21.5× less error.
    let omega = 2.0;
    let mut res = Vec::new();
    for rtol in [1e-4, 1e-6, 1e-8] {
        let mut sys = oscillator(omega);
        let opts = GalphaOptions {
            h: 1e-3,
            adaptive: true,
            tolerances: Tolerances::Scalar {
                rtol,
                atol: 1e-2 * rtol,
            },
            ..Default::default()
        };
        let mut ga = Galpha::new(opts, &mut sys, 0.0, &[0.0, 1.0], &[0.0, 0.0]).unwrap();
        let mut max_err: Real = 0.0;
        for i in 1..=40 {
            let t = 0.25 * i as Real;
            assert!(ga.integrate_to(&mut sys, t).unwrap().is_success());
            max_err = max_err.max((ga.y()[1] - (omega * t).cos()).abs());
            max_err = max_err.max((ga.y()[0] + omega * (omega * t).sin()).abs() / omega);
        }
        println!(
            "adaptive rtol {rtol:e}: max error {max_err:.3e}, {:?}",
            ga.stats()
        );
        res.push((max_err, ga.stats().steps as Real));
    }
    for w in res.windows(2) {
        let (e, s) = (w[0].0 / w[1].0, w[1].1 / w[0].1);
        assert!((10.0..50.0).contains(&e), "error ratio {e}");
        assert!((3.5..6.0).contains(&s), "step ratio {s}");
    }
    assert!(res[1].0 < 1e-3, "{res:?}");
}

/// Friction that turns NaN after t = 0.5 (a broken friction table, say).
struct NanAfter;

impl FrictionForces for NanAfter {
    fn add_forces(
        &mut self,
        t: Real,
        _: &[Real],
        _: &[Real],
        f: &mut [Real],
    ) -> Result<(), squeal_solver::SolverError> {
        if t > 0.5 {
            f[0] = Real::NAN;
        }
        Ok(())
    }
    fn add_tangents(
        &mut self,
        _: Real,
        _: &[Real],
        _: &[Real],
        _: &mut Mat<Real>,
        _: Option<&mut Mat<Real>>,
    ) -> Result<(), squeal_solver::SolverError> {
        Ok(())
    }
}

#[test]
fn failure_is_a_status_naming_t_h_and_residual() {
    use squeal_solver::galpha::Status;
    for adaptive in [false, true] {
        let mut sys = GalphaSystem::new(
            Mat::identity(1, 1),
            Mat::zeros(1, 1),
            Mat::identity(1, 1),
            Mat::zeros(0, 1),
            LoadHistory::default(),
            NanAfter,
        )
        .unwrap();
        let opts = GalphaOptions {
            h: 0.01,
            adaptive,
            ..Default::default()
        };
        let mut ga = Galpha::new(opts, &mut sys, 0.0, &[0.0, 1.0], &[0.0, 0.0]).unwrap();
        let st = ga.integrate_to(&mut sys, 1.0).unwrap();
        println!("{st:?}");
        match st {
            Status::ConvergenceFailures {
                t,
                h,
                order,
                residual_norm,
            }
            | Status::StepSizeTooSmall {
                t,
                h,
                order,
                residual_norm,
            } => {
                assert_eq!(order, 2);
                assert!(t <= 0.5 && t > 0.5 - 0.011, "t = {t}");
                assert!(h > 0.0 && h <= 0.01);
                assert!(residual_norm.is_nan());
            }
            other => panic!("unexpected {other:?}"),
        }
        assert!(!st.is_success());
        assert!(ga.y().iter().all(|x| x.is_finite()));
    }
}

#[test]
fn options_validate_and_round_trip() {
    let o = GalphaOptions::default();
    assert_eq!(o.rho_inf, 0.9);
    o.validate().unwrap();
    let back: GalphaOptions = serde_json::from_str(&serde_json::to_string(&o).unwrap()).unwrap();
    assert_eq!(back, o);
    let e = serde_json::from_str::<GalphaOptions>(r#"{"rho": 0.5}"#).unwrap_err();
    assert!(e.to_string().contains("rho"), "{e}");
    let bad = GalphaOptions {
        rho_inf: 1.2,
        ..Default::default()
    };
    assert!(bad.validate().unwrap_err().to_string().contains("rho_inf"));
    // ρ∞ = 1 is the trapezoidal rule: α_m = α_f = 1/2, γ = 1/2, β = 1/4.
    let c = GalphaCoeffs::from_rho_inf(1.0);
    assert_eq!(
        (c.alpha_m, c.alpha_f, c.gamma, c.beta),
        (0.5, 0.5, 0.5, 0.25)
    );
}

/// Belt friction with the arctangent regularisation of [Paper eq. (5)] (as the contact
/// crate's, normalised by atan(10) so the force is continuous at 10·VTOL): on DOF 0,
/// F = λ'_0·μ(s)·r(s) with slip s = V − v_0, μ = μ0 − a|s|, r = atan(s/VTOL)/atan(10) for
/// |s| < 10·VTOL and sign(s) above. At s = 0 its slope is λ'μ0/(VTOL·atan 10): a stiff
/// damper while the mass sticks to the belt.
struct StickSlip {
    mu0: Real,
    a: Real,
    v_belt: Real,
    vtol: Real,
}

impl StickSlip {
    /// (μ r, d(μ r)/ds) at slip s.
    fn law(&self, s: Real) -> (Real, Real) {
        let mu = self.mu0 - self.a * s.abs();
        let dmu = -self.a * s.signum();
        let zone = 10.0 * self.vtol;
        let (r, dr) = if s.abs() < zone {
            let x = s / self.vtol;
            let n = 10.0_f64.atan();
            (x.atan() / n, 1.0 / (self.vtol * (1.0 + x * x) * n))
        } else {
            (s.signum(), 0.0)
        };
        (mu * r, dmu * r + mu * dr)
    }
}

impl FrictionForces for StickSlip {
    fn add_forces(
        &mut self,
        _: Real,
        v: &[Real],
        lambda_dot: &[Real],
        f: &mut [Real],
    ) -> Result<(), squeal_solver::SolverError> {
        f[0] += self.law(self.v_belt - v[0]).0 * lambda_dot[0];
        Ok(())
    }
    fn add_tangents(
        &mut self,
        _: Real,
        v: &[Real],
        lambda_dot: &[Real],
        d_dlam: &mut Mat<Real>,
        d_dv: Option<&mut Mat<Real>>,
    ) -> Result<(), squeal_solver::SolverError> {
        let (g, dg) = self.law(self.v_belt - v[0]);
        d_dlam[(0, 0)] += g;
        if let Some(d) = d_dv {
            d[(0, 0)] -= dg * lambda_dot[0];
        }
        Ok(())
    }
}

/// The belt of [`belt_galpha`] (m = 1, k = (2π)², c = 0.3, N = 10) on a slow belt
/// (V = 0.2) with the regularised friction of [`StickSlip`] (μ0 = 0.5, a = 0.05,
/// VTOL = 1e-3), kicked to v = 1: the mass's velocity amplitude exceeds V, so every period
/// has a stick phase, entered and left through the stiff zone |s| < 10·VTOL.
fn stick_slip_matrices() -> (Mat<Real>, Mat<Real>, Mat<Real>, Mat<Real>, LoadHistory) {
    let k = (2.0 * PI).powi(2);
    (
        Mat::from_fn(2, 2, |i, j| [[1.0, 0.0], [0.0, 2.0]][i][j]),
        Mat::from_fn(2, 2, |i, j| if i + j == 0 { 0.3 } else { 0.0 }),
        Mat::from_fn(2, 2, |i, j| [[k, 0.0], [0.0, 50.0]][i][j]),
        Mat::from_fn(1, 2, |_, j| j as Real),
        LoadHistory {
            p_pre: vec![0.0, 10.0],
            ..Default::default()
        },
    )
}

fn stick_slip_friction() -> StickSlip {
    StickSlip {
        mu0: 0.5,
        a: 0.05,
        v_belt: 0.2,
        vtol: 1e-3,
    }
}

/// y0 = {v, λ, u} at the steady sliding position with the kick, and a guess for y0'.
fn stick_slip_initial() -> (Vec<Real>, Vec<Real>) {
    let f = stick_slip_friction();
    let x_eq = 10.0 * f.law(f.v_belt).0 / (2.0 * PI).powi(2);
    (
        vec![1.0, 0.0, 0.0, x_eq, 0.0],
        vec![0.0, 0.0, 10.0, 1.0, 0.0],
    )
}

/// BDF at RTOL = 1e-9 on the stick–slip belt, y at t = 1, 2, 3, 4 s.
fn stick_slip_reference() -> Vec<Vec<Real>> {
    let (m, b, k, g, load) = stick_slip_matrices();
    let mut bs = BsqlSystem::new(
        m,
        b,
        k,
        g,
        load,
        stick_slip_friction(),
        BsqlOptions {
            include_friction_damping: true,
            ..Default::default()
        },
    )
    .unwrap();
    let (mut y, mut yp) = stick_slip_initial();
    consistent_initial_conditions(
        &mut bs,
        0.0,
        &mut y,
        &mut yp,
        None,
        &InitialConditionOptions::default(),
    )
    .unwrap();
    let opts = BdfOptions {
        tolerances: bs.tolerances(1e-9, 1e-11, 1e-9, 1e-11),
        ..Default::default()
    };
    let mut bdf = Bdf::new(opts, 0.0, &y, &yp).unwrap();
    (1..=4)
        .map(|s| {
            assert!(bdf.integrate_to(&mut bs, s as Real).unwrap().is_success());
            bdf.y().to_vec()
        })
        .collect()
}

/// Fixed-step (h) generalized-α on the stick–slip belt, with or without C_f in the Newton
/// matrix: the status, the steps taken inside the stick zone |V − v| < 10·VTOL, the
/// largest |Δv| and |Δx| at t = 1..4 s against `reference`, relative to the largest |v|
/// and |x| there, and the statistics.
fn stick_slip_run(
    h: Real,
    with_cf: bool,
    reference: &[Vec<Real>],
) -> (
    squeal_solver::galpha::Status,
    usize,
    Real,
    Real,
    GalphaStats,
) {
    let (m, b, k, g, load) = stick_slip_matrices();
    let mut sys = GalphaSystem::new(m, b, k, g, load, stick_slip_friction()).unwrap();
    let (y0, yp0) = stick_slip_initial();
    let opts = GalphaOptions {
        h,
        tolerances: tight(),
        include_friction_damping: with_cf,
        ..Default::default()
    };
    let mut ga = Galpha::new(opts, &mut sys, 0.0, &y0, &yp0).unwrap();
    let mut in_zone = 0usize;
    let (mut dv, mut dx, mut v_max, mut x_max) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (i, yr) in reference.iter().enumerate() {
        let st = ga
            .step_to(&mut sys, (i + 1) as Real, |_, _, y, _| {
                if (0.2 - y[0]).abs() < 1e-2 {
                    in_zone += 1;
                }
                Ok(true)
            })
            .unwrap();
        if !st.is_success() {
            return (st, in_zone, Real::NAN, Real::NAN, ga.stats().clone());
        }
        let y = ga.y();
        dv = dv.max((y[0] - yr[0]).abs());
        dx = dx.max((y[3] - yr[3]).abs());
        v_max = v_max.max(yr[0].abs());
        x_max = x_max.max(yr[3].abs());
    }
    let st = squeal_solver::galpha::Status::Reached { t: 4.0 };
    (st, in_zone, dv / v_max, dx / x_max, ga.stats().clone())
}

/// Fixed-step generalized-α through stick–slip (the failure of the sample brake at
/// h ≥ 1e-6, in small). Entering the stick zone, the friction's slope jumps from ≈ 0 to
/// λ'μ0/(VTOL·atan 10) = 3.4e3 against m/(γ h c_a) ≈ 400 at h = 5e-3:
/// - without C_f in the Newton matrix (as the pipeline ran it), Newton diverges there
///   (rate ≈ c_v C_f/m ≈ 8); it used to end the run with `ConvergenceFailures`, and must now
///   cover the step with substeps h/2, h/4, … until it converges;
/// - with C_f, the tangents of the predictor (sliding) are wrong for the solution (stuck):
///   the step must be solved with tangents re-formed at the iterates, and never accepted
///   on one correction with a convergence rate carried over from smooth steps (that put v
///   off by 8 % at h = 1e-2).
///
/// Stable: both reach t = 4 s with v and x within 1 % (of their largest values) of a BDF at
/// RTOL = 1e-9 at t = 1, 2, 3, 4 s, and the run passes through the stick zone.
#[test]
fn fixed_step_survives_stick_slip_transitions() {
    let reference = stick_slip_reference();
    for with_cf in [true, false] {
        let (st, in_zone, dv, dx, s) = stick_slip_run(5e-3, with_cf, &reference);
        println!(
            "stick–slip, C_f in the matrix: {with_cf}: {st:?}, {in_zone} steps in the stick zone, \
             |Δv| {dv:.2e}, |Δx| {dx:.2e}, {s:?}"
        );
        assert!(st.is_success(), "C_f {with_cf}: {st:?}");
        assert!(in_zone > 20, "no stick phase: {in_zone} steps in the zone");
        assert!(
            dv < 1e-2 && dx < 1e-2,
            "C_f {with_cf}: |Δv| {dv:e}, |Δx| {dx:e}"
        );
    }
}
