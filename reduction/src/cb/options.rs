//! Options of the Craig–Bampton reduction.

use crate::error::ReductionError;
use serde::{Deserialize, Serialize};
use squeal_meshes::Real;

/// Craig–Bampton options: which fixed-interface modes to keep and how to compute them.
///
/// The kept modes are those of the fixed-interface problem (K_ii, M_ii) below the cutoff
/// frequency; the cutoff is `cutoff_hz` if given, else `cutoff_factor × frequency_of_interest_hz`
/// (DESIGN.md: about 2× the highest frequency of interest). `n_modes` alone keeps that many of
/// the lowest modes; with a cutoff it caps their number.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CbOptions {
    /// Highest frequency the reduced model must reproduce, Hz (default: none).
    pub frequency_of_interest_hz: Option<Real>,
    /// Cutoff of the fixed-interface modes, Hz (default: none = `cutoff_factor × frequency_of_interest_hz`).
    pub cutoff_hz: Option<Real>,
    /// Cutoff over frequency of interest when `cutoff_hz` is not given (default: 2.0).
    pub cutoff_factor: Real,
    /// Number of fixed-interface modes to keep, or at most to keep with a cutoff (default: none).
    pub n_modes: Option<usize>,
    /// Interior size up to which the fixed-interface eigenproblem is solved densely (default: 1500).
    pub dense_max: usize,
    /// Columns per block when solving for the constraint modes in parallel (default: 0 =
    /// the boundary DOFs split evenly over the rayon threads: one pass over the factor each).
    pub constraint_block: usize,
    /// Block size of the shift-invert block Lanczos used above `dense_max` (default: 16; each
    /// block costs one pass over the factor, which dominates on large models).
    pub lanczos_block: usize,
    /// Largest Krylov dimension of the block Lanczos before it gives up (default: 600).
    pub lanczos_max_dim: usize,
    /// Relative residual below which a Lanczos Ritz pair counts as converged (default: 1e-9).
    pub lanczos_tol: Real,
    /// Asked between the phases of the reduction, at every block of constraint modes, every
    /// Lanczos step and every block of the reduced products; when set the reduction returns
    /// [`ReductionError::Interrupted`] (default: never). Not hashed, not serialised.
    #[serde(skip)]
    pub interrupt: squeal_fe::Interrupt,
    /// Substructured reduction of large components (default: off, `above_dofs` = none).
    pub substructures: super::multilevel::SubstructureOptions,
}

impl Default for CbOptions {
    fn default() -> Self {
        Self {
            frequency_of_interest_hz: None,
            cutoff_hz: None,
            cutoff_factor: 2.0,
            n_modes: None,
            dense_max: 1500,
            constraint_block: 0,
            lanczos_block: 16,
            lanczos_max_dim: 600,
            lanczos_tol: 1e-9,
            interrupt: squeal_fe::Interrupt::never(),
            substructures: Default::default(),
        }
    }
}

fn bad(field: &'static str, value: impl std::fmt::Display, reason: &str) -> ReductionError {
    ReductionError::InvalidOption {
        field,
        value: value.to_string(),
        reason: reason.to_string(),
    }
}

impl CbOptions {
    /// Options keeping the modes below `2 × frequency_of_interest_hz`.
    pub fn with_frequency_of_interest(frequency_of_interest_hz: Real) -> Self {
        Self {
            frequency_of_interest_hz: Some(frequency_of_interest_hz),
            ..Self::default()
        }
    }

    /// Options keeping the `n` lowest fixed-interface modes.
    pub fn with_n_modes(n: usize) -> Self {
        Self {
            n_modes: Some(n),
            ..Self::default()
        }
    }

    /// Checks every field; the error names the field and its value.
    pub fn validate(&self) -> Result<(), ReductionError> {
        if let Some(f) = self.frequency_of_interest_hz {
            if !(f.is_finite() && f > 0.0) {
                return Err(bad("frequency_of_interest_hz", f, "must be finite and > 0"));
            }
        }
        if let Some(f) = self.cutoff_hz {
            if !(f.is_finite() && f > 0.0) {
                return Err(bad("cutoff_hz", f, "must be finite and > 0"));
            }
        }
        if !(self.cutoff_factor.is_finite() && self.cutoff_factor >= 1.0) {
            return Err(bad(
                "cutoff_factor",
                self.cutoff_factor,
                "must be finite and >= 1",
            ));
        }
        if self.cutoff_hz.is_none()
            && self.frequency_of_interest_hz.is_none()
            && self.n_modes.is_none()
        {
            return Err(bad(
                "cutoff_hz",
                "none",
                "give cutoff_hz, frequency_of_interest_hz or n_modes",
            ));
        }
        if self.lanczos_block == 0 {
            return Err(bad("lanczos_block", 0, "must be >= 1"));
        }
        if self.lanczos_max_dim < 2 * self.lanczos_block {
            return Err(bad(
                "lanczos_max_dim",
                self.lanczos_max_dim,
                "must be >= 2 × lanczos_block",
            ));
        }
        if !(self.lanczos_tol > 0.0 && self.lanczos_tol < 1e-2) {
            return Err(bad("lanczos_tol", self.lanczos_tol, "must be in (0, 1e-2)"));
        }
        self.substructures.validate()
    }

    /// `Err(ReductionError::Interrupted)` when the caller asked to stop.
    pub(crate) fn check_interrupt(&self, during: &'static str) -> Result<(), ReductionError> {
        if self.interrupt.is_set() {
            Err(ReductionError::Interrupted { during })
        } else {
            Ok(())
        }
    }

    /// The cutoff frequency in Hz, if any (explicit, or factor × frequency of interest).
    pub fn resolved_cutoff_hz(&self) -> Option<Real> {
        self.cutoff_hz.or(self
            .frequency_of_interest_hz
            .map(|f| f * self.cutoff_factor))
    }
}
