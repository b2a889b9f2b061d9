//! Dense generalized symmetric eigen-solve for small problems: L Lᵀ = M, C = L⁻¹ K L⁻ᵀ.

use crate::{FeError, Real};
use faer::linalg::triangular_solve::{solve_lower_triangular_in_place, solve_upper_triangular_in_place};
use faer::sparse::SparseColMatRef;
use faer::{Mat, Par, Side};

/// All eigenpairs (ascending ω², M-orthonormal shapes) of a small problem.
pub(crate) fn dense_eigen(
    k: SparseColMatRef<'_, usize, Real>,
    m: SparseColMatRef<'_, usize, Real>,
) -> Result<(Vec<Real>, Mat<Real>), FeError> {
    let par = Par::Seq;
    let kd = k.to_dense();
    let md = m.to_dense();
    let llt = md.llt(Side::Lower).map_err(|e| FeError::Factorisation {
        what: "dense mass matrix (Cholesky)".to_string(),
        reason: format!("{e:?}"),
    })?;
    let l = llt.L();
    let mut z = kd.clone();
    solve_lower_triangular_in_place(l, z.as_mut(), par);
    let mut c = z.transpose().to_owned();
    solve_lower_triangular_in_place(l, c.as_mut(), par);
    let cs = Mat::<Real>::from_fn(c.nrows(), c.ncols(), |i, j| 0.5 * (c[(i, j)] + c[(j, i)]));
    let e = cs.self_adjoint_eigen(Side::Lower).map_err(|e| FeError::Factorisation {
        what: "dense eigen-decomposition".to_string(),
        reason: format!("{e:?}"),
    })?;
    let lam: Vec<Real> = (0..cs.nrows()).map(|i| e.S()[i]).collect();
    let mut phi = e.U().to_owned();
    solve_upper_triangular_in_place(l.transpose(), phi.as_mut(), par);
    Ok((lam, phi))
}
