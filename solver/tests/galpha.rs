//! Verification of the generalized-α integrator (Chung–Hulbert 1993 in the Arnold–Brüls 2007
//! form, `squeal_solver::galpha`) against analytic references and against the BDF.

mod common;

use common::{BeltFriction, Belt};
use faer::Mat;
use num_complex::Complex64;
use squeal_solver::bdf::{consistent_initial_conditions, Bdf, BdfOptions, InitialConditionOptions};
use squeal_solver::bsql::{BsqlOptions, BsqlSystem, FrictionForces, LoadHistory, NoFriction};
use squeal_solver::galpha::{
    algorithmic_damping, spectral_radius, Galpha, GalphaCoeffs, GalphaOptions, GalphaSystem,
};
use squeal_solver::bdf::Tolerances;
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
    assert!((ga.yp()[0] + omega * omega).abs() < 1e-12, "q̈0 = {}", ga.yp()[0]);
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
        let e = ((x - (omega * t).cos()).powi(2) + ((v + omega * (omega * t).sin()) / omega).powi(2))
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
        assert!((im - im_theory).abs() < 1e-7 * omega, "frequency {im} vs {im_theory}");
        if rho == 1.0 {
            // Trapezoidal rule: |ξ| = 1 exactly, no numerical damping.
            assert!(th.zeta.abs() < 1e-14, "theory {}", th.zeta);
            assert!(zeta.abs() < 1e-9, "measured {zeta}");
        } else {
            assert!((th.zeta - lead).abs() < 0.01 * lead, "{} vs {lead}", th.zeta);
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
