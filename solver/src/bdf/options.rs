//! Options of the BDF integrator and of the initial-condition solve.

#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too.

use serde::{Deserialize, Serialize};

use crate::{Real, SolverError};

/// Absolute tolerances at or above this value remove a component from the error test
/// (DASSL/BSQL convention: `ATOL2 = 1e20`).
pub const ATOL_EXCLUDED: Real = 1e20;

/// A contiguous block of components sharing one tolerance pair.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TolerancePartition {
    /// Number of consecutive components in the block (no default).
    pub len: usize,
    /// Relative tolerance of the block (no default).
    pub rtol: Real,
    /// Absolute tolerance of the block; `>= 1e20` excludes it from the error test (no default).
    pub atol: Real,
}

/// How the error weights 1/(rtol_i |y_i| + atol_i) are given.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Tolerances {
    /// One pair for every component.
    Scalar {
        /// Relative tolerance.
        rtol: Real,
        /// Absolute tolerance.
        atol: Real,
    },
    /// Consecutive partitions; their lengths must add up to the system size. The BSQL system
    /// builds `[v: (RTOL1, ATOL1), λ: (RTOL2, ATOL2), u: (RTOL1, ATOL1)]` this way
    /// (see `BsqlSystem::tolerances`).
    Partitions {
        /// The partitions, in component order.
        parts: Vec<TolerancePartition>,
    },
    /// One pair per component.
    Vector {
        /// Relative tolerances.
        rtol: Vec<Real>,
        /// Absolute tolerances.
        atol: Vec<Real>,
    },
}

impl Tolerances {
    /// Fill `rtol`, `atol` (length `n`) from this description.
    pub fn expand(
        &self,
        n: usize,
        rtol: &mut [Real],
        atol: &mut [Real],
    ) -> Result<(), SolverError> {
        match self {
            Tolerances::Scalar { rtol: r, atol: a } => {
                rtol.fill(*r);
                atol.fill(*a);
            }
            Tolerances::Partitions { parts } => {
                let total: usize = parts.iter().map(|p| p.len).sum();
                if total != n {
                    return Err(SolverError::DimensionMismatch {
                        what: "tolerance partitions (sum of lengths)",
                        expected: n,
                        got: total,
                    });
                }
                let mut i0 = 0;
                for p in parts {
                    rtol[i0..i0 + p.len].fill(p.rtol);
                    atol[i0..i0 + p.len].fill(p.atol);
                    i0 += p.len;
                }
            }
            Tolerances::Vector { rtol: r, atol: a } => {
                for (what, v) in [("rtol vector", r), ("atol vector", a)] {
                    if v.len() != n {
                        return Err(SolverError::DimensionMismatch {
                            what,
                            expected: n,
                            got: v.len(),
                        });
                    }
                }
                rtol.copy_from_slice(r);
                atol.copy_from_slice(a);
            }
        }
        for i in 0..n {
            if !(rtol[i] >= 0.0 && rtol[i].is_finite()) {
                return Err(SolverError::InvalidOption {
                    field: "tolerances.rtol",
                    value: format!("{} (component {i})", rtol[i]),
                    reason: "must be finite and >= 0",
                });
            }
            if !(atol[i] > 0.0) {
                return Err(SolverError::InvalidOption {
                    field: "tolerances.atol",
                    value: format!("{} (component {i})", atol[i]),
                    reason: "must be > 0 (use 1e20 to exclude a component)",
                });
            }
        }
        Ok(())
    }
}

/// BDF integrator options (IDA's defaults unless stated). [Paper eq. (17)]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BdfOptions {
    /// Highest BDF order used, 1..=5 (default: 2; orders 3–5 add energy to lightly damped modes).
    pub max_order: usize,
    /// Error-test tolerances (default: scalar rtol = 1e-4, atol = 1e-6).
    pub tolerances: Tolerances,
    /// First step size (default: None = IDA's choice, 0.001·|tout − t0| limited by 0.5/‖y0'‖).
    pub h0: Option<Real>,
    /// Largest step size (default: None = unlimited).
    pub h_max: Option<Real>,
    /// Smallest step size before `Status::StepSizeTooSmall` (default: 0; a round-off floor of
    /// 100·ε·|t| always applies).
    pub h_min: Real,
    /// Maximum number of steps in one `step_to` call (default: 500 000).
    pub max_steps: usize,
    /// Fixed step size: no error control, order raised by one per step up to `max_order` and
    /// then held (default: None = variable step and order).
    pub fixed_step: Option<Real>,
    /// Newton convergence coefficient (IDA's epcon) relative to the error test (default: 0.33).
    pub newton_tol_coef: Real,
    /// Maximum Newton iterations per attempt (IDA's maxcor, default: 4).
    pub max_newton_iters: usize,
    /// Maximum error-test failures on one step (IDA's maxnef, default: 10).
    pub max_error_test_failures: usize,
    /// Maximum Newton convergence failures on one step (IDA's maxncf, default: 10).
    pub max_convergence_failures: usize,
    /// Stop with `Status::StepCollapse` once `collapse_steps` consecutive accepted steps were
    /// all shorter than this (default: None = never). A caller that knows the shortest step
    /// its question needs (a frequency band) sets it well below that: a run that keeps
    /// stepping there resolves something else, and says so at once instead of crawling.
    pub h_collapse: Option<Real>,
    /// Consecutive accepted steps shorter than `h_collapse` that make a collapse (default: 200).
    pub collapse_steps: usize,
}

impl Default for BdfOptions {
    fn default() -> Self {
        Self {
            max_order: 2,
            tolerances: Tolerances::Scalar {
                rtol: 1e-4,
                atol: 1e-6,
            },
            h0: None,
            h_max: None,
            h_min: 0.0,
            max_steps: 500_000,
            fixed_step: None,
            newton_tol_coef: 0.33,
            max_newton_iters: 4,
            max_error_test_failures: 10,
            max_convergence_failures: 10,
            h_collapse: None,
            collapse_steps: 200,
        }
    }
}

impl BdfOptions {
    /// Check ranges; the error names the field.
    pub fn validate(&self) -> Result<(), SolverError> {
        let bad = |field: &'static str, value: String, reason: &'static str| {
            Err(SolverError::InvalidOption {
                field,
                value,
                reason,
            })
        };
        if !(1..=5).contains(&self.max_order) {
            return bad("max_order", self.max_order.to_string(), "must be in 1..=5");
        }
        if let Some(h0) = self.h0 {
            if !(h0 > 0.0 && h0.is_finite()) {
                return bad("h0", h0.to_string(), "must be finite and > 0");
            }
        }
        let h_max = self.h_max.unwrap_or(Real::INFINITY);
        if !(h_max > 0.0) {
            return bad("h_max", h_max.to_string(), "must be > 0");
        }
        if !(self.h_min >= 0.0 && self.h_min < h_max) {
            return bad("h_min", self.h_min.to_string(), "must be >= 0 and < h_max");
        }
        if self.max_steps == 0 {
            return bad("max_steps", "0".into(), "must be >= 1");
        }
        if let Some(h) = self.fixed_step {
            if !(h > 0.0 && h.is_finite()) {
                return bad("fixed_step", h.to_string(), "must be finite and > 0");
            }
        }
        if !(self.newton_tol_coef > 0.0 && self.newton_tol_coef.is_finite()) {
            return bad(
                "newton_tol_coef",
                self.newton_tol_coef.to_string(),
                "must be finite and > 0",
            );
        }
        if self.max_newton_iters == 0 {
            return bad("max_newton_iters", "0".into(), "must be >= 1");
        }
        if self.max_error_test_failures == 0 {
            return bad("max_error_test_failures", "0".into(), "must be >= 1");
        }
        if self.max_convergence_failures == 0 {
            return bad("max_convergence_failures", "0".into(), "must be >= 1");
        }
        if let Some(h) = self.h_collapse {
            if !(h > 0.0 && h.is_finite()) {
                return bad("h_collapse", h.to_string(), "must be finite and > 0");
            }
        }
        if self.collapse_steps == 0 {
            return bad("collapse_steps", "0".into(), "must be >= 1");
        }
        Ok(())
    }
}

/// Options of the consistent-initial-condition solve (see [`super::initial`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct InitialConditionOptions {
    /// Convergence tolerance TOLINT on ‖F(t0, y0, y0')‖∞ relative to max(1, ‖F(t0, y0, 0)‖∞)
    /// (default: 1e-10).
    pub tol: Real,
    /// Maximum Newton iterations (default: 30).
    pub max_iters: usize,
    /// Initial value of the large cj used when the system has no exact ∂F/∂y' factorisation
    /// (default: 1e8); multiplied by 1e3 whenever the contraction is slower than 0.1.
    pub cj: Real,
}

impl Default for InitialConditionOptions {
    fn default() -> Self {
        Self {
            tol: 1e-10,
            max_iters: 30,
            cj: 1e8,
        }
    }
}

impl InitialConditionOptions {
    /// Check ranges; the error names the field.
    pub fn validate(&self) -> Result<(), SolverError> {
        if !(self.tol > 0.0) {
            return Err(SolverError::InvalidOption {
                field: "tol",
                value: self.tol.to_string(),
                reason: "must be > 0",
            });
        }
        if self.max_iters == 0 {
            return Err(SolverError::InvalidOption {
                field: "max_iters",
                value: "0".into(),
                reason: "must be >= 1",
            });
        }
        if !(self.cj > 0.0 && self.cj.is_finite()) {
            return Err(SolverError::InvalidOption {
                field: "cj",
                value: self.cj.to_string(),
                reason: "must be finite and > 0",
            });
        }
        Ok(())
    }
}
