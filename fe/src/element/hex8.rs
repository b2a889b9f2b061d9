//! Plain trilinear hex8, full 2×2×2 Gauss integration (locks in bending).

use super::rules::hexahedron;
use super::{add_stiffness, expand_mass, gradients, jacobian, shape};
use crate::{FeError, Material, Real};
use nalgebra::SMatrix;

/// 24×24 element matrix.
pub type Mat24 = SMatrix<Real, 24, 24>;

/// Stiffness of a plain hex8 (2×2×2 Gauss).
pub fn stiffness(x: &[[Real; 3]; 8], mat: &Material) -> Result<Mat24, FeError> {
    let (lambda, mu) = mat.lame();
    let mut k = Mat24::zeros();
    for &(xi, w) in hexahedron(2) {
        let (_, dn) = shape::hex8(xi);
        let (j, det) = jacobian(x, &dn, xi)?;
        let g = gradients(&j, det, &dn);
        add_stiffness(&mut k, &g, w * det, lambda, mu);
    }
    Ok(k)
}

/// Scalar consistent mass m_ab = ∫ ρ N_a N_b dV (2×2×2 Gauss).
pub(crate) fn mass_scalar(x: &[[Real; 3]; 8], rho: Real) -> Result<SMatrix<Real, 8, 8>, FeError> {
    let mut m = SMatrix::<Real, 8, 8>::zeros();
    for &(xi, w) in hexahedron(2) {
        let (n, dn) = shape::hex8(xi);
        let (_, det) = jacobian(x, &dn, xi)?;
        let s = rho * w * det;
        for a in 0..8 {
            for b in 0..8 {
                m[(a, b)] += s * n[a] * n[b];
            }
        }
    }
    Ok(m)
}

/// Consistent mass of a hex8 (2×2×2 Gauss), 24×24.
pub fn mass(x: &[[Real; 3]; 8], mat: &Material) -> Result<Mat24, FeError> {
    Ok(expand_mass::<8, 24>(&mass_scalar(x, mat.density)?))
}
