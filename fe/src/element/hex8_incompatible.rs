//! Hex8 with Wilson's nine incompatible (bubble) modes and Taylor's correction.
//!
//! The displacement is enriched with u_inc = Σ_k P_k(ξ) α_k, P = (1−ξ², 1−η², 1−ζ²), α_k ∈ ℝ³.
//! Taylor's correction evaluates the incompatible-mode gradients with the centroid Jacobian J0
//! and scales them by det(J0)/det(J): ∇_x P_k = det(J0)/det(J) · J0^{-T} ∇_ξ P_k. Then
//! ∫ ∇_x P_k dV = det(J0) J0^{-T} ∫ ∇_ξ P_k dξ = 0 under 2×2×2 Gauss, so constant strain states
//! are reproduced on any (distorted) element and the patch test passes. The 9 internal DOFs are
//! condensed statically: K = K_uu − K_uα K_αα⁻¹ K_αu.

use super::rules::hexahedron;
use super::solid::{add_point, Law};
use super::{gradients, jacobian, shape};
use crate::{FeError, Material, Real};
use nalgebra::SMatrix;

pub use super::hex8::Mat24;

/// Stiffness of the incompatible-mode hex8 (2×2×2 Gauss), condensed to the 24 nodal DOFs.
pub fn stiffness(x: &[[Real; 3]; 8], mat: &Material) -> Result<Mat24, FeError> {
    let (lambda, mu) = mat.lame();
    stiffness_law(x, &Law::Isotropic { lambda, mu })
}

/// [`stiffness`] under any constitutive law (anisotropic materials).
pub(crate) fn stiffness_law(x: &[[Real; 3]; 8], law: &Law) -> Result<Mat24, FeError> {
    condense(&full_stiffness_law(x, law, true)?)
}

/// Static condensation K = K_uu − K_uα K_αα⁻¹ K_αu of the 9 incompatible DOFs.
fn condense(k: &SMatrix<Real, 33, 33>) -> Result<Mat24, FeError> {
    let kuu: SMatrix<Real, 24, 24> = k.fixed_view::<24, 24>(0, 0).into_owned();
    let kua: SMatrix<Real, 24, 9> = k.fixed_view::<24, 9>(0, 24).into_owned();
    let kaa: SMatrix<Real, 9, 9> = k.fixed_view::<9, 9>(24, 24).into_owned();
    // A positive-Jacobian element has a positive definite K_αα; failure is reported with a
    // positive det so that assembly names it as a singular incompatible block.
    let chol = kaa.cholesky().ok_or(FeError::ElementJacobian {
        det: 1.0,
        xi: [0.0; 3],
    })?;
    let kc = kuu - kua * chol.solve(&kua.transpose());
    // Restore exact symmetry lost to rounding in the condensation.
    Ok((kc + kc.transpose()) * 0.5)
}

/// Uncondensed 33×33 stiffness (24 nodal + 9 incompatible DOFs); `taylor = false` drops
/// Taylor's correction (Wilson's original element, which fails the patch test when distorted).
#[cfg(test)]
pub(crate) fn full_stiffness(
    x: &[[Real; 3]; 8],
    mat: &Material,
    taylor: bool,
) -> Result<SMatrix<Real, 33, 33>, FeError> {
    let (lambda, mu) = mat.lame();
    full_stiffness_law(x, &Law::Isotropic { lambda, mu }, taylor)
}

fn full_stiffness_law(
    x: &[[Real; 3]; 8],
    law: &Law,
    taylor: bool,
) -> Result<SMatrix<Real, 33, 33>, FeError> {
    let (_, dn0) = shape::hex8([0.0; 3]);
    let (j0, det0) = jacobian(x, &dn0, [0.0; 3])?;
    let j0_inv = j0.try_inverse().ok_or(FeError::ElementJacobian {
        det: det0,
        xi: [0.0; 3],
    })?;
    // 8 nodal functions + 3 bubble functions → 33 DOFs.
    let mut k = SMatrix::<Real, 33, 33>::zeros();
    for &(xi, w) in hexahedron(2) {
        let (n, dn) = shape::hex8(xi);
        let (j, det) = jacobian(x, &dn, xi)?;
        let gn = gradients(&j, det, &dn);
        let mut g = [[0.0; 3]; 11];
        g[..8].copy_from_slice(&gn);
        // Taylor: J0 and det(J0)/det(J); Wilson's original: the local J.
        let (jinv, scale) = if taylor {
            (j0_inv, det0 / det)
        } else {
            (j.try_inverse().unwrap_or(j0_inv), 1.0)
        };
        for kk in 0..3 {
            // ∂P_k/∂ξ_k = −2 ξ_k, other derivatives zero.
            let dp = -2.0 * xi[kk];
            for i in 0..3 {
                g[8 + kk][i] = scale * jinv[(kk, i)] * dp;
            }
        }
        add_point(&mut k, &g, w * det, law, || {
            std::array::from_fn(|i| (0..8).map(|a| n[a] * x[a][i]).sum())
        })?;
    }
    Ok(k)
}

/// Consistent mass (the incompatible modes carry no mass): the hex8 2×2×2 mass.
pub fn mass(x: &[[Real; 3]; 8], mat: &Material) -> Result<Mat24, FeError> {
    super::hex8::mass(x, mat)
}
