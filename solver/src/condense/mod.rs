//! The band-limited model: a reduced model condensed to its in-band contact-linearised modes
//! plus the static correction of everything above the cut-off, with the contact nonlinearity
//! kept exact at the gap DOFs.
//!
//! # The model
//! About a steady sliding state (u⁰, λ'⁰) under the load P_ref, the BSQL equations
//! [Paper eqs. (8), (12), (9)] read exactly (no approximation yet)
//! ```text
//! M ü + C ũ̇ + K_c ũ + A_r Ñ = ΔP(t) + r(λ', v),      G_r ũ = 0,
//! C = B − C_f⁰,  A_r = G_rᵀ − D⁰_r,  K_c = K + Σ_compliant (Gᵀ − D⁰)_k G_k / c_k,
//! r = F_f(λ'_true, v) − F_f⁰ − C_f⁰ v − D⁰ (q − λ'⁰) − Gᵀ (λ'_true − q),
//! ```
//! with ũ = u − u⁰, Ñ the rigid rows' multiplier increments, q the linear normal force of every
//! row (rigid: λ'⁰ + Ñ; compliant: G_k u / c_k, [`crate::bsql::compliance`]), λ'_true the force
//! the contact carries (q, or min(q, λ'_open) for a unilateral compliant row) and D⁰ = ∂F_f/∂λ',
//! C_f⁰ = ∂F_f/∂v the friction tangents at the reference (the CEA's, [`crate::cea`]). The left
//! side is the CEA's linear operator; `r`, the *remainder*, is zero with zero derivative at the
//! reference and acts at the contact DOFs only. So the model is a linear, time-invariant
//! system driven by two inputs — the load change ΔP(t) = (ramp(t) − ramp_ref)·p_brake and the
//! remainder at the contact DOFs — and read at the contact DOFs (their velocities and the
//! normal forces q), closed by the exact friction law.
//!
//! # The condensation
//! The linear part is diagonalised in first-order form (the constraint eliminated as in
//! [`crate::cea::reduce`]): with right eigenvectors ψ_j, left eigenvectors and eigenvalues
//! λ_j of the contact-linearised, constrained operator, its transfer function from a force f
//! to the displacement is H(s) = Σ_j c_j b_j/(s − λ_j) (all 2(n − ng_r) roots). The band-limited
//! model keeps the roots with |Im λ|/2π ≤ the cut-off (real roots: |λ|/2π ≤ it) as states,
//! ξ̇_j = λ_j ξ_j + b_j f, and replaces the others by their static response — the *static
//! correction* (Craig's mode-acceleration / residual-flexibility form, the state-space
//! counterpart of Rubin–MacNeal's residual flexibility, without residual mass):
//! ```text
//! u = u⁰ + Σ_kept c_j ξ_j + D_u f,     D_u = H(0) − Σ_kept c_j b_j (−1/λ_j)
//! v =      Σ_kept λ_j c_j ξ_j + D_v f,  D_v = Σ_kept c_j b_j      (v = d/dt of the modal u)
//! Ñ =      Σ_kept ν_j ξ_j + D_N f,      D_N = N(0) − Σ_kept ν_j b_j (−1/λ_j)
//! ```
//! H(0), N(0) from one static solve of the bordered operator [K_c, A_r; G_r, 0]. Hence:
//! - the kept roots are the full model's own (the same eigenvalues, not approximations), and
//!   the removed ones — the interface flutter far above the band among them — are gone by
//!   construction: their dynamics is replaced by a static response, so they cannot grow;
//! - every static response is exact: the condensed model's equilibria (any load, any friction
//!   state) are the full model's, and its linearisation at the reference has exactly the kept
//!   roots;
//! - the contact rows and the friction are evaluated exactly as in the full model, on the
//!   condensed model's contact velocities and normal forces;
//! - the error is the removed roots' dynamic part, H − H_band = Σ_removed c_j b_j s/(λ_j (s −
//!   λ_j)) (× s for velocities): [`BandModel::build`] estimates it over the band on probe
//!   inputs and a tolerance decides it ([`BandOptions::tolerance`]).
//!
//! # Reference
//! Craig & Kurdila, *Fundamentals of Structural Dynamics* (2006), §10.4 (mode-acceleration
//! method) and ch. 17 (residual flexibility, Rubin and MacNeal's methods); Rubin, AIAA J. 13
//! (1975) 995–1006; MacNeal, Computers & Structures 1 (1971) 581–601. The reduced-order
//! transient of a brake with its contact kept nonlinear: Sinou, Besset, *Double modal synthesis*
//! and *complex interface modes* (Mech. Syst. Signal Process. 2017); Coudeyras, Sinou,
//! Nacivet, J. Sound Vib. 319 (2009) 1175–1199.
//!
//! - [`spectrum`]: the full first-order eigendecomposition, right vectors and the left rows.
//! - [`build`]: the kept roots, input and output maps, the static correction ([`BandModel`]).
//! - [`estimate`]: the error estimate over the band.
//! - [`system`]: the band-limited transient as a [`crate::bdf::DaeSystem`] ([`BandSystem`]).

pub mod build;
pub mod estimate;
pub(crate) mod spectrum;
pub mod system;

pub use build::{BandModel, Condenser, Inputs};
pub use system::{BandContact, BandReference, BandSystem, BandSystemStats};

use crate::cea::{CeaError, Cplx};
use crate::{Real, SolverError};
use serde::{Deserialize, Serialize};

/// Options of the condensation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BandOptions {
    /// Cut-off frequency, Hz: roots with |Im λ|/2π above it (real roots: |λ|/2π) are replaced
    /// by their static response (default: infinity, every root kept).
    pub cutoff_hz: Real,
    /// Top of the band the error estimate covers, Hz (default: none: the cut-off, or the
    /// highest kept frequency when the cut-off is infinite).
    pub band_hz: Option<Real>,
    /// Largest admissible error estimate (relative, see [`BandStats::error_estimate`])
    /// (default: 0.01).
    pub tolerance: Real,
    /// Frequencies of the estimate's grid on [0, band] (default: 64; the kept roots'
    /// frequencies in the band are added).
    pub estimate_points: usize,
    /// Random probe inputs of the estimate, besides the brake load (default: 4).
    pub probes: usize,
    /// A root is unstable when Re λ > `unstable_tol` × max|λ| (default: 1e-8, as the CEA's).
    pub unstable_tol: Real,
}

impl Default for BandOptions {
    fn default() -> Self {
        Self {
            cutoff_hz: Real::INFINITY,
            band_hz: None,
            tolerance: 0.01,
            estimate_points: 64,
            probes: 4,
            unstable_tol: 1e-8,
        }
    }
}

#[allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too.
impl BandOptions {
    /// Checks every field; the error names it.
    pub fn validate(&self) -> Result<(), BandError> {
        let bad = |field: &'static str, value: Real, reason: &'static str| BandError::Option {
            field,
            value: value.to_string(),
            reason,
        };
        if !(self.cutoff_hz > 0.0) {
            return Err(bad("cutoff_hz", self.cutoff_hz, "must be > 0"));
        }
        if let Some(b) = self.band_hz {
            if !(b > 0.0 && b.is_finite()) {
                return Err(bad("band_hz", b, "must be finite and > 0"));
            }
        }
        if !(self.tolerance > 0.0 && self.tolerance.is_finite()) {
            return Err(bad("tolerance", self.tolerance, "must be finite and > 0"));
        }
        if self.estimate_points < 2 {
            return Err(bad(
                "estimate_points",
                self.estimate_points as Real,
                "must be >= 2",
            ));
        }
        if !(self.unstable_tol >= 0.0 && self.unstable_tol < 1.0) {
            return Err(bad("unstable_tol", self.unstable_tol, "must be in [0, 1)"));
        }
        Ok(())
    }
}

/// A root of the linearised model (one of each conjugate pair: Im ≥ 0).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Root {
    /// |Im λ|/2π, Hz.
    pub frequency_hz: Real,
    /// Re λ, 1/s (> 0: growing).
    pub real_part: Real,
}

impl Root {
    pub(crate) fn of(p: Cplx) -> Self {
        Self {
            frequency_hz: p.im.abs() / (2.0 * std::f64::consts::PI),
            real_part: p.re,
        }
    }
}

/// What the condensation kept, removed and estimated (written to `summary.json`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct BandStats {
    /// DOFs n of the reduced model.
    pub n: usize,
    /// Rigid constraint rows (multipliers) of the linear operator.
    pub n_rigid_rows: usize,
    /// Roots of the full linear operator (conjugate pairs counted once).
    pub n_roots: usize,
    /// Kept roots (conjugate pairs counted once).
    pub kept: usize,
    /// Real states of the band-limited model (2 per kept pair, 1 per kept real root).
    pub n_states: usize,
    /// Removed roots (conjugate pairs counted once).
    pub removed: usize,
    /// Removed unstable roots.
    pub removed_unstable: usize,
    /// The removed unstable root with the largest Re λ.
    pub largest_removed_unstable: Option<Root>,
    /// Every removed unstable root, by frequency.
    pub removed_unstable_roots: Vec<Root>,
    /// Kept unstable roots (in the band or between it and the cut-off).
    pub kept_unstable: Vec<Root>,
    /// Highest kept frequency, Hz.
    pub kept_max_frequency_hz: Real,
    /// Lowest removed frequency, Hz (None: nothing removed).
    pub removed_min_frequency_hz: Option<Real>,
    /// The cut-off used, Hz.
    pub cutoff_hz: Real,
    /// The band the estimate covers, Hz.
    pub band_hz: Real,
    /// The error estimate: over the band's frequency grid and the probe inputs, the largest
    /// ‖(H − H_band)(iω) F‖ over the largest ‖H(iω) F‖, for the contact velocities and for the
    /// normal forces apart, and the larger of the two.
    pub error_estimate: Real,
    /// The same for the contact velocities alone.
    pub error_velocity: Real,
    /// The same for the normal forces alone (0 without contact rows).
    pub error_force: Real,
    /// The frequency of the largest error, Hz.
    pub error_at_hz: Real,
    /// ‖H(0) − Σ_all c_j b_j (−1/λ_j)‖ / ‖H(0)‖ over the inputs at the contact DOFs: the
    /// eigendecomposition's own check (round-off; large when the eigenvectors are nearly
    /// dependent, i.e. near a coalescence).
    pub static_check: Real,
    /// Wall time of the eigendecomposition, s.
    pub time_eigen_s: Real,
    /// Wall time of the maps, the static solve and the estimate, s.
    pub time_maps_s: Real,
}

/// Errors of the condensation: bad input, a failed decomposition, or an estimate above the
/// tolerance (with the numbers to act on).
#[derive(Debug, thiserror::Error)]
pub enum BandError {
    /// An option is out of range.
    #[error("invalid band-limited model option `{field}` = {value}: {reason}")]
    Option {
        /// The field.
        field: &'static str,
        /// Its value.
        value: String,
        /// What was expected.
        reason: &'static str,
    },
    /// The linear operator (the CEA's matrices) was refused.
    #[error(transparent)]
    Cea(#[from] CeaError),
    /// A solve or a callback failed.
    #[error(transparent)]
    Solver(#[from] SolverError),
    /// The static operator [K_c, A_r; G_r, 0] is singular: a root at 0 (a free rigid-body
    /// motion), which no static correction can hold.
    #[error("the static operator of the linearised model is singular (a root at λ = 0): {0}")]
    SingularStatic(String),
    /// The eigendecomposition does not reproduce the static response: the eigenvectors are
    /// (nearly) dependent, e.g. at a coalescence of two roots.
    #[error("the eigenvectors do not reproduce the static response (relative error {error:e} > {limit:e}): a defective or nearly defective root pair (a coalescence)")]
    IllConditioned {
        /// The relative error.
        error: Real,
        /// The limit.
        limit: Real,
    },
    /// The error estimate is above the tolerance.
    #[error("band-limited model: error estimate {estimate:.3e} (at {at_hz:.1} Hz) > tolerance {tolerance:e} with the cut-off at {cutoff_hz:.1} Hz; raise the cut-off (the lowest removed root is at {removed_min_hz:.1} Hz) or the tolerance")]
    EstimateAboveTolerance {
        /// The estimate.
        estimate: Real,
        /// Where it is largest.
        at_hz: Real,
        /// The tolerance.
        tolerance: Real,
        /// The cut-off.
        cutoff_hz: Real,
        /// The lowest removed frequency.
        removed_min_hz: Real,
    },
}
