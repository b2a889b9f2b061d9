//! Sparse assembly of the global stiffness and consistent mass over the free DOFs.

mod assemble;
mod pattern;

pub use assemble::assemble;

use crate::Real;
use faer::sparse::SparseColMat;
use serde::{Deserialize, Serialize};

/// Formulation of hex8 cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Hex8Formulation {
    /// Wilson's incompatible modes with Taylor's correction (no shear locking).
    #[default]
    Incompatible,
    /// Plain trilinear, 2×2×2 Gauss (locks in bending: +12 % on NAFEMS FV52).
    Standard,
}

/// Assembly options.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AssemblyOptions {
    /// Formulation of hex8 cells (default: `incompatible`).
    pub hex8: Hex8Formulation,
    /// Asked between chunks of elements; when set the assembly returns
    /// `FeError::Interrupted` (default: never).
    #[serde(skip)]
    pub interrupt: crate::Interrupt,
}

impl AssemblyOptions {
    /// Nothing to check today; kept for the uniform Options interface.
    pub fn validate(&self) -> Result<(), crate::FeError> {
        Ok(())
    }
}

/// Assembly statistics.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct AssemblyStats {
    /// Number of volume cells.
    pub n_elements: usize,
    /// Number of free DOFs (matrix dimension).
    pub n_free: usize,
    /// Stored entries of K (both triangles).
    pub nnz_k: usize,
    /// Stored entries of M (both triangles).
    pub nnz_m: usize,
    /// Seconds building the node graph.
    pub pattern_s: Real,
    /// Seconds computing and scattering element matrices.
    pub elements_s: Real,
    /// Seconds building the free-DOF sparse matrices.
    pub build_s: Real,
    /// Total seconds.
    pub total_s: Real,
}

/// Global matrices over the free DOFs, full symmetric storage (both triangles), sorted rows.
#[derive(Debug, Clone)]
pub struct Assembled {
    /// Stiffness K.
    pub k: SparseColMat<usize, Real>,
    /// Consistent mass M.
    pub m: SparseColMat<usize, Real>,
    /// Statistics.
    pub stats: AssemblyStats,
}
