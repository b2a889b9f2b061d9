//! A stored reduced model given in memory (`model.from = "arrays"`): what `reduced.op4`,
//! `dofmap.json` and a gap table hold, as arrays a library caller (the Python package) passes
//! without writing files.

use squeal_contact::Gap;
use squeal_reduction::superelement::ReducedDofMap;
use std::sync::Arc;

use squeal_solver::Real;

/// The matrices, DOF map and gaps of a stored model in memory. Checked when the model is
/// built (`model::build`), as the files of a stored model are: shapes against the DOF
/// map, finite entries, symmetry, M positive definite, gap values.
#[derive(Debug, Clone)]
pub struct StoredArrays {
    /// KR (n × n, column-major as faer holds it).
    pub k: faer::Mat<Real>,
    /// MR (n × n).
    pub m: faer::Mat<Real>,
    /// BR (n × n), element damping (default: none).
    pub b: Option<faer::Mat<Real>>,
    /// PBRAKE (n), the unit brake load (default: none = zero).
    pub p_brake: Option<Vec<Real>>,
    /// Row/column i of the matrices is `dofs.dofs[i]`.
    pub dofs: ReducedDofMap,
    /// The gap table (DOF indices are assigned from the map when the model is built).
    pub gaps: Vec<Gap>,
}

/// A shared handle on [`StoredArrays`] held by the scene (`model.arrays`): cloning a scene
/// (e.g. for each value of a sweep) shares the arrays. Two handles are equal when they share
/// the same arrays.
#[derive(Clone)]
pub struct ArraysRef(pub Arc<StoredArrays>);

impl PartialEq for ArraysRef {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

impl std::fmt::Debug for ArraysRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "StoredArrays({} DOFs, {} gaps)",
            self.0.dofs.len(),
            self.0.gaps.len()
        )
    }
}
