//! Solid elements: element stiffness and consistent mass matrices.
//!
//! - [`hex8_incompatible`]: trilinear hex with Wilson's 9 incompatible modes and Taylor's
//!   correction (default hex8; no shear locking in bending),
//! - [`hex8`]: plain trilinear hex, 2×2×2 Gauss (locks in bending; kept for comparison),
//! - [`hex20`]: serendipity hex, 3×3×3 Gauss;
//! - tet4/tet10 ([`simplex`]), wedge6/wedge15 ([`wedge`]), pyramid5/pyramid13 ([`pyramid`]):
//!   the generic isoparametric element of [`solid`] with the rules of [`rules`], dispatched
//!   per cell kind in [`kinds`] (its table states each element's rule and why it is exact);
//! - anisotropic materials enter every kind through [`crate::elasticity`].
//!
//! DOF order inside an element: node-major, `3 a + i` for node `a`, component `i`.

pub mod hex20;
pub mod hex8;
pub mod hex8_incompatible;
pub mod kinds;
pub mod pyramid;
pub mod quadrature;
pub mod rules;
pub mod shape;
pub mod simplex;
pub(crate) mod solid;
pub mod wedge;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_kinds;

use crate::{FeError, Real};
use nalgebra::{Matrix3, SMatrix};

/// Jacobian J_ij = ∂x_i/∂ξ_j of an isoparametric map, and its determinant (must be > 0).
pub(crate) fn jacobian<const N: usize>(
    x: &[[Real; 3]; N],
    dn: &[[Real; 3]; N],
    xi: [Real; 3],
) -> Result<(Matrix3<Real>, Real), FeError> {
    let mut j = Matrix3::zeros();
    for a in 0..N {
        for r in 0..3 {
            for c in 0..3 {
                j[(r, c)] += x[a][r] * dn[a][c];
            }
        }
    }
    let det: Real = j.determinant();
    if det.is_nan() || det <= 0.0 {
        return Err(FeError::ElementJacobian { det, xi });
    }
    Ok((j, det))
}

/// Spatial gradients ∇_x N_a = J^{-T} ∇_ξ N_a.
pub(crate) fn gradients<const N: usize>(
    j: &Matrix3<Real>,
    det: Real,
    dn: &[[Real; 3]; N],
) -> [[Real; 3]; N] {
    // J^{-1} = adj(J)/det; ∇_x N = J^{-T} ∇_ξ N, i.e. g_i = Σ_k (J^{-1})_{k i} ∂N/∂ξ_k.
    // det > 0 was checked by `jacobian`; the cofactor form avoids a second singularity test.
    let inv = adjugate(j) / det;
    let mut g = [[0.0; 3]; N];
    for a in 0..N {
        for i in 0..3 {
            g[a][i] = inv[(0, i)] * dn[a][0] + inv[(1, i)] * dn[a][1] + inv[(2, i)] * dn[a][2];
        }
    }
    g
}

/// Adjugate (transposed cofactor matrix) of a 3×3 matrix: adj(J) = det(J) J⁻¹.
fn adjugate(j: &Matrix3<Real>) -> Matrix3<Real> {
    let c = |r0: usize, r1: usize, c0: usize, c1: usize| {
        j[(r0, c0)] * j[(r1, c1)] - j[(r0, c1)] * j[(r1, c0)]
    };
    Matrix3::new(
        c(1, 2, 1, 2),
        -c(0, 2, 1, 2),
        c(0, 1, 1, 2),
        -c(1, 2, 0, 2),
        c(0, 2, 0, 2),
        -c(0, 1, 0, 2),
        c(1, 2, 0, 1),
        -c(0, 2, 0, 1),
        c(0, 1, 0, 1),
    )
}

/// Adds the isotropic stiffness of one integration point,
/// K_{ai,bj} += w (λ g_{a,i} g_{b,j} + μ g_{a,j} g_{b,i} + μ δ_ij g_a·g_b),
/// for the scalar functions with gradients `g` (D = 3 · g.len()).
pub(crate) fn add_stiffness<const D: usize>(
    k: &mut SMatrix<Real, D, D>,
    g: &[[Real; 3]],
    w: Real,
    lambda: Real,
    mu: Real,
) {
    let (wl, wm) = (w * lambda, w * mu);
    for a in 0..g.len() {
        let ga = g[a];
        for b in a..g.len() {
            let gb = g[b];
            let dot = wm * (ga[0] * gb[0] + ga[1] * gb[1] + ga[2] * gb[2]);
            for i in 0..3 {
                for jj in 0..3 {
                    let mut v = wl * ga[i] * gb[jj] + wm * ga[jj] * gb[i];
                    if i == jj {
                        v += dot;
                    }
                    k[(3 * a + i, 3 * b + jj)] += v;
                    if b != a {
                        k[(3 * b + jj, 3 * a + i)] += v;
                    }
                }
            }
        }
    }
}

/// Expands a scalar (node × node) mass matrix to the 3-component one, M_{ai,bj} = m_ab δ_ij.
pub(crate) fn expand_mass<const N: usize, const D: usize>(
    m: &SMatrix<Real, N, N>,
) -> SMatrix<Real, D, D> {
    let mut out = SMatrix::<Real, D, D>::zeros();
    for a in 0..N {
        for b in 0..N {
            for i in 0..3 {
                out[(3 * a + i, 3 * b + i)] = m[(a, b)];
            }
        }
    }
    out
}
