//! Dense generalized symmetric eigen-solve for small problems: L Lᵀ = M, C = L⁻¹ K L⁻ᵀ.

use crate::{FeError, Real};
use faer::sparse::SparseColMatRef;
use faer::Mat;
use nalgebra::DMatrix;

fn to_dense(a: SparseColMatRef<'_, usize, Real>) -> DMatrix<Real> {
    let mut d = DMatrix::<Real>::zeros(a.nrows(), a.ncols());
    for j in 0..a.ncols() {
        for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
            d[(i, j)] += v;
        }
    }
    d
}

/// All eigenpairs (ascending ω², M-orthonormal shapes) of a small problem.
pub(crate) fn dense_eigen(
    k: SparseColMatRef<'_, usize, Real>,
    m: SparseColMatRef<'_, usize, Real>,
) -> Result<(Vec<Real>, Mat<Real>), FeError> {
    let n = k.nrows();
    let kd = to_dense(k);
    let md = to_dense(m);
    let chol = md.cholesky().ok_or_else(|| FeError::Factorisation {
        what: "dense mass matrix (Cholesky)".to_string(),
        reason: "M is not positive definite".to_string(),
    })?;
    let l = chol.l();
    let z = l
        .solve_lower_triangular(&kd)
        .ok_or_else(|| FeError::NonFinite {
            what: "L^-1 K".to_string(),
        })?;
    let c = l
        .solve_lower_triangular(&z.transpose())
        .ok_or_else(|| FeError::NonFinite {
            what: "L^-1 K L^-T".to_string(),
        })?;
    let c = (&c + c.transpose()) * 0.5;
    let e = c.symmetric_eigen();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| e.eigenvalues[a].total_cmp(&e.eigenvalues[b]));
    let lt = l.transpose();
    let phi = lt
        .solve_upper_triangular(&e.eigenvectors)
        .ok_or_else(|| FeError::NonFinite {
            what: "L^-T U".to_string(),
        })?;
    let lam = order.iter().map(|&i| e.eigenvalues[i]).collect();
    let out = Mat::<Real>::from_fn(n, n, |r, c| phi[(r, order[c])]);
    Ok((lam, out))
}
