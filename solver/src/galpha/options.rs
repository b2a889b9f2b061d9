//! Options, method coefficients and statistics of the generalized-α integrator.

#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too.

use serde::{Deserialize, Serialize};

use crate::bdf::Tolerances;
use crate::{Real, SolverError};

/// Generalized-α options.
///
/// # Choice of the default ρ∞ = 0.9
/// The algorithmic damping ratio of a mode at ωh ≪ 1 is, to leading order (expansion of the
/// principal root of the amplification matrix, see [`super::spectral`]),
/// $$ζ_{num} ≈ \tfrac12\Big(\frac{1-ρ_∞}{1+ρ_∞}\Big)^3 (ωh)^3,$$
/// i.e. 7.3e-8 at ωh = 0.1 for ρ∞ = 0.9 (BDF2: 2.44e-4, 3 300× more), while modes near
/// the Nyquist limit (ωh → ∞: stiff contact, constraint transients) lose 10 % of their
/// amplitude per step. ρ∞ = 1 (trapezoidal rule) keeps all high-frequency noise;
/// ρ∞ ≤ 0.8 costs ≥ 10× more low-frequency damping than 0.9 (6.8e-7 at ωh = 0.1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GalphaOptions {
    /// Spectral radius at infinite frequency ρ∞ ∈ [0, 1] (default: 0.9; 1 = no numerical
    /// damping, the trapezoidal rule; see the type's documentation).
    pub rho_inf: Real,
    /// Step size: the fixed step, or the first step when `adaptive` (default: 1e-4).
    pub h: Real,
    /// Adapt the step size with the local error estimate of [`super::step`] (default: false =
    /// fixed step `h`; the tolerances then only set the Newton convergence test).
    pub adaptive: bool,
    /// Error weights 1/(rtol|y_i| + atol_i) on y = {v, λ, u} for the error test and the
    /// Newton test (default: scalar rtol = 1e-6, atol = 1e-9; build partitions with
    /// `BsqlSystem::tolerances`-style `Tolerances::Partitions`).
    pub tolerances: Tolerances,
    /// Newton convergence coefficient: stop when ρ/(1−ρ)·‖δy‖_wrms ≤ this (default: 0.01).
    pub newton_tol_coef: Real,
    /// Maximum (modified) Newton iterations per attempt (default: 8).
    pub max_newton_iters: usize,
    /// Include the friction damping C_f = ∂F_f/∂v in the iteration matrix (default: true; it
    /// is cheap with dense matrices and keeps Newton quadratic in the v-dependence of friction).
    pub include_friction_damping: bool,
    /// Smallest step size (default: 1e-14): adaptive steps below it end with
    /// `Status::StepSizeTooSmall`; fixed steps are not halved below it.
    pub h_min: Real,
    /// Largest step size when adaptive (default: None = unlimited).
    pub h_max: Option<Real>,
    /// Maximum number of steps in one `step_to` call (default: 10 000 000).
    pub max_steps: usize,
    /// Maximum failures on one step (default: 10): error-test plus Newton failures when
    /// adaptive; Newton failures, i.e. halvings of the substep, with fixed steps.
    pub max_failures: usize,
    /// Tolerance of the initial solve for q̈₀, λ'₀ on ‖F(t0, y0, y0')‖∞ relative to
    /// max(1, ‖F(t0, y0, 0)‖∞) (default: 1e-12).
    pub initial_tol: Real,
}

impl Default for GalphaOptions {
    fn default() -> Self {
        Self {
            rho_inf: 0.9,
            h: 1e-4,
            adaptive: false,
            tolerances: Tolerances::Scalar {
                rtol: 1e-6,
                atol: 1e-9,
            },
            newton_tol_coef: 0.01,
            max_newton_iters: 8,
            include_friction_damping: true,
            h_min: 1e-14,
            h_max: None,
            max_steps: 10_000_000,
            max_failures: 10,
            initial_tol: 1e-12,
        }
    }
}

impl GalphaOptions {
    /// Check ranges; the error names the field.
    pub fn validate(&self) -> Result<(), SolverError> {
        let bad = |field: &'static str, value: String, reason: &'static str| {
            Err(SolverError::InvalidOption {
                field,
                value,
                reason,
            })
        };
        if !(self.rho_inf >= 0.0 && self.rho_inf <= 1.0) {
            return bad("rho_inf", self.rho_inf.to_string(), "must be in [0, 1]");
        }
        if !(self.h > 0.0 && self.h.is_finite()) {
            return bad("h", self.h.to_string(), "must be finite and > 0");
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
        if !(self.initial_tol > 0.0) {
            return bad("initial_tol", self.initial_tol.to_string(), "must be > 0");
        }
        if self.max_failures == 0 {
            return bad("max_failures", "0".into(), "must be >= 1");
        }
        Ok(())
    }
}

/// The method parameters derived from ρ∞.
///
/// # Reference
/// Chung & Hulbert (1993), J. Appl. Mech. 60:371–375, eqs. (25), (17):
/// $$α_m = \frac{2ρ_∞ − 1}{ρ_∞ + 1},\quad α_f = \frac{ρ_∞}{ρ_∞ + 1},\quad
/// γ = \tfrac12 − α_m + α_f,\quad β = \tfrac14\big(1 − α_m + α_f\big)^2,$$
/// used in the form of Arnold & Brüls (2007), Multibody Syst. Dyn. 18:185–202, eq. (6):
/// $(1−α_m) a_{n+1} + α_m a_n = (1−α_f) \ddot q_{n+1} + α_f \ddot q_n$.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GalphaCoeffs {
    /// α_m.
    pub alpha_m: Real,
    /// α_f.
    pub alpha_f: Real,
    /// γ.
    pub gamma: Real,
    /// β.
    pub beta: Real,
}

impl GalphaCoeffs {
    /// Optimal (second-order, maximal high-frequency dissipation for the given ρ∞) parameters.
    pub fn from_rho_inf(rho_inf: Real) -> Self {
        let alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
        let alpha_f = rho_inf / (rho_inf + 1.0);
        let gamma = 0.5 - alpha_m + alpha_f;
        let beta = 0.25 * (gamma + 0.5) * (gamma + 0.5);
        Self {
            alpha_m,
            alpha_f,
            gamma,
            beta,
        }
    }

    /// ∂a_{n+1}/∂q̈_{n+1} = (1 − α_f)/(1 − α_m).
    pub fn c_a(&self) -> Real {
        (1.0 - self.alpha_f) / (1.0 - self.alpha_m)
    }

    /// Time shift δ = α_m − α_f of the pseudo-acceleration: a_n ≈ q̈(t_n + δh).
    pub fn delta(&self) -> Real {
        self.alpha_m - self.alpha_f
    }

    /// Local error constants (C_u, C_v): u-error ≈ C_u h³ q⃛, v-error ≈ C_v h³ q⁗.
    ///
    /// # Derivation
    /// With a_n = q̈(t_n + δh) + h² e (e the steady defect of the a-recursion at second
    /// order, e = ½[(1−α_f) − (1−α_m)(1+δ)² − α_m δ²] q⁗), Taylor expansion of the Newmark
    /// updates against the exact solution gives
    /// C_u = β + δ/2 − 1/6 and C_v = ½[(1−γ)δ² + γ(1+δ)²] + ½[(1−α_f) − (1−α_m)(1+δ)² − α_m δ²] − 1/6;
    /// both reduce to the trapezoidal 1/12 at ρ∞ = 1.
    pub fn error_constants(&self) -> (Real, Real) {
        let d = self.delta();
        let (am, af, g) = (self.alpha_m, self.alpha_f, self.gamma);
        let c_u = self.beta + 0.5 * d - 1.0 / 6.0;
        let c_v = 0.5 * ((1.0 - g) * d * d + g * (1.0 + d) * (1.0 + d))
            + 0.5 * ((1.0 - af) - (1.0 - am) * (1.0 + d) * (1.0 + d) - am * d * d)
            - 1.0 / 6.0;
        (c_u, c_v)
    }
}

/// Counters of one integration (written to `summary.json`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct GalphaStats {
    /// Accepted steps.
    pub steps: u64,
    /// Newton iterations (linear solves with the iteration matrix), initial solve included.
    pub newton_iterations: u64,
    /// Residual evaluations.
    pub residual_evals: u64,
    /// Factorisations of the iteration matrix.
    pub factorisations: u64,
    /// Steps rejected by the local error test (adaptive only).
    pub rejected_steps: u64,
    /// Newton convergence failures (each followed by a refactorisation, full Newton or a
    /// smaller step).
    pub convergence_failures: u64,
    /// Fixed steps that were covered by substeps after a Newton failure.
    #[serde(default)]
    pub halved_steps: u64,
    /// Size of the last accepted step.
    pub last_h: Real,
    /// Constraint drift ‖G v − G v₀‖∞ at the last step.
    pub constraint_drift: Real,
    /// Largest constraint drift ‖G v − G v₀‖∞ over the accepted steps.
    pub max_constraint_drift: Real,
    /// Wall-clock seconds spent inside `new` and `step_to` (named cpu_s as in BSQL's table).
    pub cpu_s: Real,
}
