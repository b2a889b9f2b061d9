//! Serendipity hex20, 3×3×3 Gauss integration (2×2×2 would admit spurious modes).

use super::rules::hexahedron;
use super::{add_stiffness, expand_mass, gradients, jacobian, shape};
use crate::{FeError, Material, Real};
use nalgebra::SMatrix;

/// 60×60 element matrix.
pub type Mat60 = SMatrix<Real, 60, 60>;

/// Stiffness of a hex20 (3×3×3 Gauss).
pub fn stiffness(x: &[[Real; 3]; 20], mat: &Material) -> Result<Box<Mat60>, FeError> {
    let (lambda, mu) = mat.lame();
    let mut k = Box::new(Mat60::zeros());
    for &(xi, w) in hexahedron(3) {
        let (_, dn) = shape::hex20(xi);
        let (j, det) = jacobian(x, &dn, xi)?;
        let g = gradients(&j, det, &dn);
        add_stiffness(&mut *k, &g, w * det, lambda, mu);
    }
    Ok(k)
}

/// Scalar consistent mass m_ab = ∫ ρ N_a N_b dV (3×3×3 Gauss).
pub(crate) fn mass_scalar(
    x: &[[Real; 3]; 20],
    rho: Real,
) -> Result<SMatrix<Real, 20, 20>, FeError> {
    let mut m = SMatrix::<Real, 20, 20>::zeros();
    for &(xi, w) in hexahedron(3) {
        let (n, dn) = shape::hex20(xi);
        let (_, det) = jacobian(x, &dn, xi)?;
        let s = rho * w * det;
        for a in 0..20 {
            for b in a..20 {
                let v = s * n[a] * n[b];
                m[(a, b)] += v;
                if b != a {
                    m[(b, a)] += v;
                }
            }
        }
    }
    Ok(m)
}

/// Consistent mass of a hex20 (3×3×3 Gauss), 60×60.
pub fn mass(x: &[[Real; 3]; 20], mat: &Material) -> Result<Box<Mat60>, FeError> {
    Ok(Box::new(expand_mass::<20, 60>(&mass_scalar(
        x,
        mat.density,
    )?)))
}
