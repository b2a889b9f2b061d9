//! Options and statistics of the substructured Craig–Bampton reduction.

use crate::error::ReductionError;
use serde::{Deserialize, Serialize};
use squeal_meshes::Real;

/// Substructured (two-level) Craig–Bampton reduction of a large component
/// ([`super`] module docs): memory bounded by the largest substructure's factor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SubstructureOptions {
    /// Substructure a component whose interior has more DOFs than this (default: none = the
    /// exact Craig–Bampton reduction, one factor of the whole interior).
    pub above_dofs: Option<usize>,
    /// Largest substructure, DOFs (default: 60 000).
    pub max_dofs: usize,
    /// Cut-off of each substructure's fixed-interface modes over the component's cut-off, at the
    /// start (default: 2.0); raised ×1.6 where the error estimate asks for it.
    pub cutoff_factor: Real,
    /// Degree of the polynomial basis of each separator piece at the start (default: 4);
    /// raised by 2 where the error estimate asks for it.
    pub degree: usize,
    /// Highest separator degree (default: 14).
    pub max_degree: usize,
    /// Tolerance on the estimated relative error of the component's fixed-interface
    /// eigenvalues and of its constraint modes' condensed stiffness (default: 1e-3, about
    /// 0.05 % in frequency).
    pub tol: Real,
    /// Rounds of estimate and refinement after the first reduction (default: 3).
    pub max_rounds: usize,
}

impl Default for SubstructureOptions {
    fn default() -> Self {
        Self {
            above_dofs: None,
            max_dofs: 60_000,
            cutoff_factor: 2.0,
            degree: 4,
            max_degree: 14,
            tol: 1e-3,
            max_rounds: 3,
        }
    }
}

impl SubstructureOptions {
    /// Checks every field; the error names the field and its value.
    pub fn validate(&self) -> Result<(), ReductionError> {
        let bad = |field: &'static str, value: String, reason: &str| {
            Err(ReductionError::InvalidOption {
                field,
                value,
                reason: reason.into(),
            })
        };
        if self.max_dofs < 100 {
            return bad(
                "substructures.max_dofs",
                self.max_dofs.to_string(),
                "must be >= 100",
            );
        }
        if !(self.cutoff_factor.is_finite() && self.cutoff_factor >= 1.0) {
            return bad(
                "substructures.cutoff_factor",
                self.cutoff_factor.to_string(),
                "must be finite and >= 1",
            );
        }
        if self.degree < 1 || self.max_degree < self.degree {
            return bad(
                "substructures.degree",
                format!("{} (max_degree {})", self.degree, self.max_degree),
                "must be >= 1 and <= max_degree",
            );
        }
        if !(self.tol > 0.0 && self.tol < 1.0) {
            return bad(
                "substructures.tol",
                self.tol.to_string(),
                "must be in (0, 1)",
            );
        }
        Ok(())
    }
}

/// One substructure: size, modes and error estimate.
#[derive(Debug, Clone, Serialize)]
pub struct SubstructureStats {
    pub n_dofs: usize,
    /// Separator pieces and boundary groups it touches, and their coordinates.
    pub n_neighbours: usize,
    pub n_coupling_coords: usize,
    /// Fixed-interface modes kept and their cut-off, Hz.
    pub n_modes: usize,
    pub cutoff_hz: Real,
    /// Stored entries of its factor (with its separators as border in the second pass).
    pub factor_nnz: usize,
    /// Estimated relative error its mode truncation causes: largest over the component's
    /// fixed-interface eigenvalues, and over its constraint modes' condensed stiffness.
    pub estimate_modes: Real,
    pub estimate_static: Real,
}

/// One separator piece: size, basis and error estimate.
#[derive(Debug, Clone, Serialize)]
pub struct SeparatorStats {
    pub n_dofs: usize,
    /// Depth of its separator in the bisection tree.
    pub depth: usize,
    pub degree: usize,
    pub n_coords: usize,
    /// Estimated relative error its polynomial basis causes (as for substructures).
    pub estimate_modes: Real,
    pub estimate_static: Real,
}

/// Statistics of a substructured reduction.
#[derive(Debug, Clone, Serialize)]
pub struct MultilevelStats {
    pub substructures: Vec<SubstructureStats>,
    pub separators: Vec<SeparatorStats>,
    /// Size of the assembled second-level model: modal coordinates, separator coordinates,
    /// boundary coordinates.
    pub level2_sizes: [usize; 3],
    /// Reductions performed (1 + refinement rounds).
    pub rounds: usize,
    /// The tolerance and the final estimates (largest relative eigenvalue error over the
    /// kept modes, largest relative condensed-stiffness error over the constraint modes: sums
    /// over substructures and separators of their estimates).
    pub tol: Real,
    pub estimate_modes: Real,
    pub estimate_static: Real,
    /// Whether both estimates are within `tol`.
    pub converged: bool,
    /// Seconds: substructuring, first-level reductions, second level, recovery and estimates.
    pub substructuring_s: Real,
    pub level1_s: Real,
    pub level2_s: Real,
    pub recovery_s: Real,
}
