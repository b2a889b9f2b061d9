//! Verification of the BDF integrator on problems with analytic references.

mod common;

use common::Oscillator;
use squeal_solver::bdf::{
    consistent_initial_conditions, Bdf, BdfOptions, DaeSystem, InitialConditionOptions, Status,
    Tolerances,
};
use squeal_solver::{Real, SolverError};

/// Numerical damping ratio of constant-step BDF-k on y' = iω y at ωh = wh, from its
/// characteristic polynomial ρ(ξ) − iωh ξ^k = 0 (principal root, found by Newton from
/// e^{iωh}): s = ln ξ / h, ζ = −Re s / |s|.
///
/// BDF2: (3/2 − z) ξ² − 2ξ + 1/2 = 0; BDF3: (11/6 − z) ξ³ − 3ξ² + 3/2 ξ − 1/3 = 0, z = iωh.
/// At ωh = 0.1 this gives ζ = 2.4471e-4 (BDF2) and −2.4786e-4 (BDF3); numpy.roots on the
/// same polynomials gives the same digits.
fn bdf_zeta_theory(order: usize, wh: Real) -> Real {
    use num_complex::Complex64 as C;
    let z = C::new(0.0, wh);
    let coef: Vec<C> = match order {
        2 => vec![C::from(1.5) - z, C::from(-2.0), C::from(0.5)],
        3 => vec![
            C::from(11.0 / 6.0) - z,
            C::from(-3.0),
            C::from(1.5),
            C::from(-1.0 / 3.0),
        ],
        _ => unreachable!(),
    };
    let p = |x: C| coef.iter().fold(C::from(0.0), |acc, c| acc * x + c);
    let dp = |x: C| {
        let k = coef.len() - 1;
        coef.iter()
            .take(k)
            .enumerate()
            .fold(C::from(0.0), |acc, (i, c)| acc * x + c * (k - i) as Real)
    };
    let mut xi = C::new(0.0, wh).exp();
    for _ in 0..50 {
        xi -= p(xi) / dp(xi);
    }
    let s = xi.ln(); // per unit h
    -s.re / s.norm()
}

/// Run the oscillator with fixed step and order; measure ζ from the decay of
/// z_n = x_n − i v_n/ω, which for the principal root is exactly c·ξⁿ.
fn measured_zeta(order: usize, omega: Real, wh: Real, periods: Real) -> (Real, Status) {
    let h = wh / omega;
    let opts = BdfOptions {
        max_order: order,
        fixed_step: Some(h),
        tolerances: Tolerances::Scalar {
            rtol: 1e-8,
            atol: 1e-10,
        },
        ..Default::default()
    };
    let mut sys = Oscillator::new(omega);
    let y0 = [1.0, 0.0];
    let yp0 = [0.0, -omega * omega];
    let mut bdf = Bdf::new(opts, 0.0, &y0, &yp0).unwrap();
    let mut zs: Vec<(Real, num_complex::Complex64)> = Vec::new();
    let t_end = periods * 2.0 * std::f64::consts::PI / omega;
    let status = bdf
        .step_to(&mut sys, t_end, |_, t, y, _| {
            zs.push((t, num_complex::Complex64::new(y[0], -y[1] / omega)));
            Ok(true)
        })
        .unwrap();
    // Skip the start-up (BDF1 steps, spurious roots |ξ₂| ≈ 1/3 decay within ~40 steps).
    let skip = 200;
    let (t_a, z_a) = zs[skip];
    let (t_b, z_b) = *zs.last().unwrap();
    let steps = (zs.len() - 1 - skip) as Real;
    let re = (z_b.norm() / z_a.norm()).ln() / (t_b - t_a);
    // Unwrapped phase advance.
    let mut phase = 0.0;
    for w in zs[skip..].windows(2) {
        phase += (w[1].1 / w[0].1).arg();
    }
    let im = phase / (steps * h);
    let zeta = -re / (re * re + im * im).sqrt();
    (zeta, status)
}

#[test]
fn bdf2_numerical_damping_matches_characteristic_roots() {
    let theory = bdf_zeta_theory(2, 0.1);
    assert!((theory - 2.4471e-4).abs() < 1e-7, "theory {theory}");
    let (zeta, status) = measured_zeta(2, 3.0, 0.1, 200.0);
    assert!(status.is_success(), "{status:?}");
    let rel = (zeta - theory).abs() / theory;
    println!("BDF2 ωh=0.1: measured ζ = {zeta:.6e}, theory {theory:.6e}, rel. diff {rel:.2e}");
    assert!(rel < 0.01, "measured {zeta} vs theory {theory}");
}

#[test]
fn bdf3_adds_energy_to_undamped_oscillator() {
    // DESIGN.md: BDF3 has ζ_num ≈ −2.5e-4 at ωh = 0.1 (negative: it adds energy).
    let theory = bdf_zeta_theory(3, 0.1);
    assert!(theory < 0.0);
    let (zeta, status) = measured_zeta(3, 3.0, 0.1, 200.0);
    assert!(status.is_success(), "{status:?}");
    println!("BDF3 ωh=0.1: measured ζ = {zeta:.6e}, theory {theory:.6e}");
    assert!(zeta < 0.0);
    assert!(
        (zeta - theory).abs() < 0.01 * theory.abs(),
        "measured {zeta} vs theory {theory}"
    );
}

#[test]
fn variable_step_oscillator_is_accurate_to_tolerance() {
    // Exact solution x = cos ωt; global error should be a small multiple of rtol.
    let omega = 2.0;
    let opts = BdfOptions {
        tolerances: Tolerances::Scalar {
            rtol: 1e-6,
            atol: 1e-8,
        },
        ..Default::default()
    };
    let mut sys = Oscillator::new(omega);
    let mut bdf = Bdf::new(opts, 0.0, &[1.0, 0.0], &[0.0, -omega * omega]).unwrap();
    let mut max_err: Real = 0.0;
    for i in 1..=20 {
        let t = 0.25 * i as Real;
        let st = bdf.integrate_to(&mut sys, t).unwrap();
        assert_eq!(st, Status::Reached { t });
        max_err = max_err.max((bdf.y()[0] - (omega * t).cos()).abs());
        max_err = max_err.max((bdf.yp()[0] + omega * (omega * t).sin()).abs() / omega);
    }
    let stats = bdf.stats().clone();
    println!("variable-step oscillator: max error {max_err:.2e}, stats {stats:?}");
    // Global error of a 5-time-unit run at rtol 1e-6: well under 1e-3, far above round-off.
    assert!(max_err < 1e-3 && max_err > 1e-12, "max error {max_err}");
    assert_eq!(stats.order_histogram.len(), 3);
    assert!(stats.order_histogram[2] > stats.order_histogram[1]);
}

/// x' = −x + z, 0 = z − 2x: a semi-explicit index-1 DAE with z algebraic.
struct SemiExplicit {
    cj: Real,
}

impl DaeSystem for SemiExplicit {
    fn len(&self) -> usize {
        2
    }
    fn residual(
        &mut self,
        _t: Real,
        y: &[Real],
        yp: &[Real],
        r: &mut [Real],
    ) -> Result<(), SolverError> {
        r[0] = yp[0] + y[0] - y[1];
        r[1] = y[1] - 2.0 * y[0];
        Ok(())
    }
    fn setup_jacobian(
        &mut self,
        _t: Real,
        _y: &[Real],
        _yp: &[Real],
        cj: Real,
    ) -> Result<(), SolverError> {
        self.cj = cj;
        Ok(())
    }
    fn solve_jacobian(&mut self, b: &mut [Real]) -> Result<(), SolverError> {
        // J = [[cj + 1, −1], [−2, 1]]
        let (a, bb, c, d) = (self.cj + 1.0, -1.0, -2.0, 1.0);
        let det = a * d - bb * c;
        let x0 = (d * b[0] - bb * b[1]) / det;
        let x1 = (a * b[1] - c * b[0]) / det;
        b[0] = x0;
        b[1] = x1;
        Ok(())
    }
}

#[test]
fn consistent_initial_conditions_differential_and_algebraic() {
    let opts = InitialConditionOptions::default();
    // Oscillator: y0' must become (v0, −ω² x0) = (0.5, −4·1).
    let mut osc = Oscillator::new(2.0);
    let mut y0 = [1.0, 0.5];
    let mut yp0 = [7.0, -3.0];
    let st = consistent_initial_conditions(&mut osc, 0.0, &mut y0, &mut yp0, None, &opts).unwrap();
    assert!(
        (yp0[0] - 0.5).abs() < 1e-10 && (yp0[1] + 4.0).abs() < 1e-10,
        "{yp0:?} {st:?}"
    );
    assert_eq!(y0, [1.0, 0.5]);
    // Semi-explicit DAE: z0 = 2 x0 = 2, x0' = −x0 + z0 = 1.
    let mut sys = SemiExplicit { cj: 0.0 };
    let mut y0 = [1.0, 0.0];
    let mut yp0 = [0.0, 0.0];
    consistent_initial_conditions(
        &mut sys,
        0.0,
        &mut y0,
        &mut yp0,
        Some(&[false, true]),
        &opts,
    )
    .unwrap();
    assert!(
        (y0[1] - 2.0).abs() < 1e-10 && (yp0[0] - 1.0).abs() < 1e-10,
        "{y0:?} {yp0:?}"
    );
    // And the DAE integrates: x(t) = e^{t}, z = 2x.
    let mut bdf = Bdf::new(
        BdfOptions {
            tolerances: Tolerances::Scalar {
                rtol: 1e-7,
                atol: 1e-9,
            },
            ..Default::default()
        },
        0.0,
        &y0,
        &yp0,
    )
    .unwrap();
    assert!(bdf.integrate_to(&mut sys, 1.0).unwrap().is_success());
    let e = std::f64::consts::E;
    assert!((bdf.y()[0] - e).abs() < 1e-4 * e, "{:?}", bdf.y());
    assert!((bdf.y()[1] - 2.0 * bdf.y()[0]).abs() < 1e-9);
}

/// y' = −y whose residual is NaN for t > 0.5 and whose matrix is singular for t > t_sing.
struct Breaks {
    t_sing: Real,
    cj: Real,
}

impl DaeSystem for Breaks {
    fn len(&self) -> usize {
        1
    }
    fn residual(
        &mut self,
        t: Real,
        y: &[Real],
        yp: &[Real],
        r: &mut [Real],
    ) -> Result<(), SolverError> {
        r[0] = if t > 0.5 { Real::NAN } else { yp[0] + y[0] };
        Ok(())
    }
    fn setup_jacobian(
        &mut self,
        t: Real,
        _y: &[Real],
        _yp: &[Real],
        cj: Real,
    ) -> Result<(), SolverError> {
        if t > self.t_sing {
            return Err(SolverError::SingularMatrix {
                what: "test",
                t,
                index: 0,
                pivot: 0.0,
                max_pivot: 0.0,
            });
        }
        self.cj = cj;
        Ok(())
    }
    fn solve_jacobian(&mut self, b: &mut [Real]) -> Result<(), SolverError> {
        b[0] /= self.cj + 1.0;
        Ok(())
    }
}

#[test]
fn step_size_collapse_on_nan_residual_is_a_clean_status() {
    let mut sys = Breaks {
        t_sing: Real::INFINITY,
        cj: 0.0,
    };
    let opts = BdfOptions {
        h_min: 1e-6,
        ..Default::default()
    };
    let mut bdf = Bdf::new(opts, 0.0, &[1.0], &[-1.0]).unwrap();
    let st = bdf.integrate_to(&mut sys, 1.0).unwrap();
    println!("{st:?}");
    match st {
        Status::StepSizeTooSmall {
            t,
            h,
            order,
            residual_norm,
        } => {
            assert!(t <= 0.5 && t > 0.5 - 1e-3, "t = {t}");
            assert!(h < 1e-6 && h > 0.0);
            assert!((1..=2).contains(&order));
            assert!(residual_norm.is_nan());
        }
        other => panic!("expected StepSizeTooSmall, got {other:?}"),
    }
    // The solution up to the failure is intact: y(t) = e^{−t}.
    assert!((bdf.state().phi[0][0] - (-bdf.t()).exp()).abs() < 1e-3);
    // Default h_min: the step-size floor is never reached; the convergence-failure limit is.
    let mut sys = Breaks {
        t_sing: Real::INFINITY,
        cj: 0.0,
    };
    let mut bdf = Bdf::new(BdfOptions::default(), 0.0, &[1.0], &[-1.0]).unwrap();
    let st = bdf.integrate_to(&mut sys, 1.0).unwrap();
    assert!(
        matches!(st, Status::ConvergenceFailures { t, .. } | Status::StepSizeTooSmall { t, .. } if t <= 0.5 && t > 0.49),
        "{st:?}"
    );
}

#[test]
fn singular_iteration_matrix_is_a_clean_status() {
    let mut sys = Breaks {
        t_sing: 0.3,
        cj: 0.0,
    };
    let mut bdf = Bdf::new(BdfOptions::default(), 0.0, &[1.0], &[-1.0]).unwrap();
    let st = bdf.integrate_to(&mut sys, 1.0).unwrap();
    println!("{st:?}");
    match st {
        Status::ConvergenceFailures { t, h, order, .. }
        | Status::StepSizeTooSmall { t, h, order, .. } => {
            // The matrix formed before t = 0.3 is reused while cj/cj_old stays in [0.6, 1.67];
            // the failure comes at the first step after 0.3 that needs a new one.
            assert!(t > 0.3 - 0.1 && t < 1.0, "t = {t}");
            assert!(h > 0.0 && order >= 1);
        }
        other => panic!("expected a failure status, got {other:?}"),
    }
}

/// A run that keeps stepping far below what its caller needs stops at once with a typed
/// status (the hex20 brake once crawled at 1e-9 s steps to its step cap). An undamped
/// oscillator at ω = 1e4 rad/s needs h ≈ 1e-6 s at rtol 1e-6 (BDF2: h ~ (rtol)^{1/3}/ω);
/// with h_collapse = 1e-4 s (a caller whose band needs 1e-2 s) it stops after exactly
/// `collapse_steps` steps below it, with the solution intact (analytic cos ωt); without
/// h_collapse the same run reaches its end.
#[test]
fn steps_far_below_h_collapse_stop_with_a_typed_status() {
    let omega = 1e4;
    let opts = |h_collapse| BdfOptions {
        tolerances: squeal_solver::bdf::Tolerances::Scalar {
            rtol: 1e-6,
            atol: 1e-9,
        },
        h_collapse,
        collapse_steps: 50,
        ..Default::default()
    };
    let mut sys = Oscillator::new(omega);
    let mut bdf = Bdf::new(opts(Some(1e-4)), 0.0, &[1.0, 0.0], &[0.0, -omega * omega]).unwrap();
    let st = bdf.integrate_to(&mut sys, 0.1).unwrap();
    println!("{st:?}, {} steps", bdf.stats().steps);
    match st {
        Status::StepCollapse {
            t,
            h,
            order,
            h_collapse,
            steps,
        } => {
            assert_eq!((steps, h_collapse), (50, 1e-4));
            assert!(
                h < 1e-4 && h > 0.0 && (1..=2).contains(&order),
                "{h} {order}"
            );
            assert_eq!(bdf.stats().steps, 50, "every step was below h_collapse");
            assert_eq!(t, bdf.t());
            let exact = (omega * t).cos();
            assert!(
                (bdf.y()[0] - exact).abs() < 1e-3,
                "{} vs {exact}",
                bdf.y()[0]
            );
        }
        other => panic!("expected StepCollapse, got {other:?}"),
    }
    let mut bdf = Bdf::new(opts(None), 0.0, &[1.0, 0.0], &[0.0, -omega * omega]).unwrap();
    let st = bdf.integrate_to(&mut sys, 2e-3).unwrap();
    assert!(st.is_success(), "{st:?}");
    assert!(BdfOptions {
        h_collapse: Some(-1.0),
        ..Default::default()
    }
    .validate()
    .is_err());
}

#[test]
fn options_validate_and_round_trip() {
    let bad = BdfOptions {
        max_order: 7,
        ..Default::default()
    };
    let e = bad.validate().unwrap_err();
    assert!(e.to_string().contains("max_order"), "{e}");
    let opts = BdfOptions {
        tolerances: Tolerances::Vector {
            rtol: vec![1e-4; 2],
            atol: vec![1e-6, 1e20],
        },
        ..Default::default()
    };
    let s = serde_json::to_string(&opts).unwrap();
    let back: BdfOptions = serde_json::from_str(&s).unwrap();
    assert_eq!(back, opts);
    let e = serde_json::from_str::<BdfOptions>(r#"{"max_ordr": 2}"#).unwrap_err();
    assert!(e.to_string().contains("max_ordr"), "{e}");
}
