//! Consistent initial conditions: given y0, find y0' with F(t0, y0, y0') = 0.
//!
//! # Approach
//! Newton's method on the unknowns z_i = y'_i for differential components and z_i = y_i for
//! algebraic ones (IDA's `IDA_YA_YDP_INIT`), with the same factorisation interface as the
//! time stepper:
//!
//! - If the system provides [`DaeSystem::setup_derivative_jacobian`] (the exact ∂F/∂y'),
//!   and there are no algebraic components, the correction is $δy' = (∂F/∂y')^{-1} F$: plain
//!   Newton, quadratic convergence.
//! - Otherwise J = ∂F/∂y + cj ∂F/∂y' is factorised with a large cj and the corrections are
//!   $δy'_i = c_j δ_i$ (differential), $δy_i = δ_i$ (algebraic), $δ = J^{-1}F$. Since
//!   $c_j J^{-1} ∂F/∂y' = (I + (∂F/∂y')^{-1}∂F/∂y / c_j)^{-1}$, the iteration contracts like
//!   $‖(∂F/∂y')^{-1} ∂F/∂y‖/c_j$ (≈ ω²_max/cj for a structure): cj starts at `opts.cj` and
//!   is multiplied by 1e3 whenever a step contracts by less than 10×.
//!
//! The matrix is re-formed every iteration (the system may be nonlinear in y', e.g. friction
//! depending on the contact force). Converged when ‖F‖∞ ≤ tol·max(1, ‖F(t0, y0, 0)‖∞).

#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too.

use serde::{Deserialize, Serialize};

use super::{DaeSystem, InitialConditionOptions};
use crate::{Real, SolverError};

/// Statistics of the initial-condition solve.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct IcStats {
    /// Newton iterations.
    pub iterations: usize,
    /// Residual evaluations.
    pub residual_evals: usize,
    /// Factorisations.
    pub jacobian_setups: usize,
    /// Final ‖F‖∞.
    pub residual_norm: Real,
    /// Final cj (0 when the exact ∂F/∂y' was used).
    pub cj: Real,
}

fn inf_norm(x: &[Real], t: Real) -> Result<Real, SolverError> {
    let mut m: Real = 0.0;
    for (i, v) in x.iter().enumerate() {
        if !v.is_finite() {
            return Err(SolverError::NonFinite {
                what: "residual (initial conditions)",
                t,
                index: i,
                value: *v,
            });
        }
        m = m.max(v.abs());
    }
    Ok(m)
}

/// Make (y0, y0') consistent at t0. `algebraic[i] = true` marks components whose y0 is
/// unknown (y' absent from F); `None` means all differential. Differential y0 are kept.
pub fn consistent_initial_conditions<S: DaeSystem + ?Sized>(
    sys: &mut S,
    t0: Real,
    y0: &mut [Real],
    yp0: &mut [Real],
    algebraic: Option<&[bool]>,
    opts: &InitialConditionOptions,
) -> Result<IcStats, SolverError> {
    opts.validate()?;
    let n = sys.len();
    for (what, l) in [("y0", y0.len()), ("y0'", yp0.len())] {
        if l != n {
            return Err(SolverError::DimensionMismatch {
                what,
                expected: n,
                got: l,
            });
        }
    }
    if let Some(a) = algebraic {
        if a.len() != n {
            return Err(SolverError::DimensionMismatch {
                what: "algebraic flags",
                expected: n,
                got: a.len(),
            });
        }
    }
    let has_alg = algebraic.is_some_and(|a| a.iter().any(|&b| b));
    let mut stats = IcStats::default();
    let mut res = vec![0.0; n];
    let zero = vec![0.0; n];
    // Force scale: the residual with y' = 0.
    sys.residual(t0, y0, &zero, &mut res)?;
    stats.residual_evals += 1;
    let scale = inf_norm(&res, t0)?.max(1.0);
    let tol = opts.tol * scale;
    let mut cj = opts.cj;
    let mut prev = Real::INFINITY;
    for it in 0..=opts.max_iters {
        sys.residual(t0, y0, yp0, &mut res)?;
        stats.residual_evals += 1;
        let rn = inf_norm(&res, t0)?;
        stats.residual_norm = rn;
        if rn <= tol {
            return Ok(stats);
        }
        if it == opts.max_iters {
            break;
        }
        if rn > 0.1 * prev && !stats.cj.eq(&0.0) {
            cj *= 1e3;
        }
        prev = rn;
        stats.iterations += 1;
        stats.jacobian_setups += 1;
        let exact = !has_alg && sys.setup_derivative_jacobian(t0, y0, yp0)?;
        if !exact {
            sys.setup_jacobian(t0, y0, yp0, cj)?;
        }
        stats.cj = if exact { 0.0 } else { cj };
        sys.solve_jacobian(&mut res)?;
        for i in 0..n {
            if exact {
                yp0[i] -= res[i];
            } else if algebraic.is_some_and(|a| a[i]) {
                y0[i] -= res[i];
            } else {
                yp0[i] -= cj * res[i];
            }
        }
    }
    Err(SolverError::NewtonFailed {
        what: "consistent initial conditions",
        iterations: stats.iterations,
        residual: stats.residual_norm,
        tolerance: tol,
    })
}
