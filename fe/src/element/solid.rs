//! The isoparametric solid element, generic over its shape functions and quadrature rule,
//! with isotropic or anisotropic (material-axes) elasticity.
//!
//! K = Σ_q w_q det J_q B_qᵀ D_q B_q and m_ab = Σ_q w_q det J_q ρ N_a N_b over the rule's
//! points q; B from ∇_x N = J⁻ᵀ ∇_ξ N. Everything lives on the stack (nalgebra `SMatrix`):
//! no heap allocation per element.

use super::{add_stiffness, gradients, jacobian};
use crate::elasticity::{cylindrical_frame, rotate, Matrix6};
use crate::{FeError, Real, SolidMaterial};
use nalgebra::SMatrix;

/// Shape functions: N_a and ∂N_a/∂ξ_j at a natural point.
pub(crate) type ShapeFn<const N: usize> = fn([Real; 3]) -> ([Real; N], [[Real; 3]; N]);

/// The constitutive law of one element.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Law {
    /// Isotropic, Lamé constants (λ, μ): the fast path.
    Isotropic { lambda: Real, mu: Real },
    /// A constant D in global axes.
    Matrix(Matrix6),
    /// D in cylindrical material axes, rotated at each integration point.
    Cylindrical {
        local: Matrix6,
        origin: [Real; 3],
        axis: [Real; 3],
    },
}

/// A block's material prepared once: the per-cell [`Law`] is then cheap.
#[derive(Debug, Clone)]
pub(crate) struct BlockLaw<'a> {
    material: &'a SolidMaterial,
    local: Matrix6,
    fixed: Option<Law>,
}

impl<'a> BlockLaw<'a> {
    pub(crate) fn new(material: &'a SolidMaterial) -> Self {
        use crate::elasticity::MaterialAxes as A;
        let local = material.elasticity.matrix();
        let fixed = if let Some((lambda, mu)) = material.isotropic_lame() {
            Some(Law::Isotropic { lambda, mu })
        } else {
            match &material.axes {
                A::Global => Some(Law::Matrix(local)),
                A::Rectangular { e1, e2 } => {
                    crate::elasticity::frame_from(*e1, *e2).map(|f| Law::Matrix(rotate(&local, &f)))
                }
                A::Cylindrical { origin, axis } => Some(Law::Cylindrical {
                    local,
                    origin: *origin,
                    axis: *axis,
                }),
                A::PerCell(_) => None,
            }
        };
        BlockLaw {
            material,
            local,
            fixed,
        }
    }

    /// Mass density.
    pub(crate) fn density(&self) -> Real {
        self.material.density
    }

    /// The law of cell `c`.
    pub(crate) fn cell(&self, c: usize) -> Result<Law, FeError> {
        if let Some(l) = &self.fixed {
            return Ok(l.clone());
        }
        match &self.material.axes {
            crate::elasticity::MaterialAxes::PerCell(frames) => frames
                .get(c)
                .map(|f| Law::Matrix(rotate(&self.local, f)))
                .ok_or(FeError::Dimension {
                    what: "material frames per cell",
                    got: frames.len(),
                    expected: c + 1,
                }),
            _ => Err(FeError::InvalidValue {
                field: "material.axes".into(),
                value: Real::NAN,
                reason: "invalid material axes (validate the material first)",
            }),
        }
    }
}

/// Adds one point's anisotropic stiffness, K_ab += w B_aᵀ D B_b.
///
/// B_a (6×3, Voigt (11, 22, 33, 23, 13, 12), engineering shears) has three non-zeros per
/// column: u_x → rows 0, 4, 5 (g_x, g_z, g_y); u_y → rows 1, 3, 5 (g_y, g_z, g_x);
/// u_z → rows 2, 3, 4 (g_z, g_y, g_x).
pub(crate) fn add_stiffness_matrix<const N: usize, const D: usize>(
    k: &mut SMatrix<Real, D, D>,
    g: &[[Real; 3]; N],
    w: Real,
    d: &Matrix6,
) {
    let cols = |ga: &[Real; 3]| -> [[(usize, Real); 3]; 3] {
        [
            [(0, ga[0]), (4, ga[2]), (5, ga[1])],
            [(1, ga[1]), (3, ga[2]), (5, ga[0])],
            [(2, ga[2]), (3, ga[1]), (4, ga[0])],
        ]
    };
    // E_b = w D B_b (6×3 per node).
    let mut e = [[[0.0; 3]; 6]; N];
    for b in 0..N {
        let cb = cols(&g[b]);
        for j in 0..3 {
            for &(r, v) in &cb[j] {
                let wv = w * v;
                for i in 0..6 {
                    e[b][i][j] += d[(i, r)] * wv;
                }
            }
        }
    }
    for a in 0..N {
        let ca = cols(&g[a]);
        for b in a..N {
            for i in 0..3 {
                for j in 0..3 {
                    let mut v = 0.0;
                    for &(r, val) in &ca[i] {
                        v += val * e[b][r][j];
                    }
                    k[(3 * a + i, 3 * b + j)] += v;
                    if b != a {
                        k[(3 * b + j, 3 * a + i)] += v;
                    }
                }
            }
        }
    }
}

/// Adds one point's stiffness under `law` at the point `x_q` (used by cylindrical axes).
pub(crate) fn add_point<const N: usize, const D: usize>(
    k: &mut SMatrix<Real, D, D>,
    g: &[[Real; 3]; N],
    w: Real,
    law: &Law,
    x_q: impl FnOnce() -> [Real; 3],
) -> Result<(), FeError> {
    match law {
        Law::Isotropic { lambda, mu } => add_stiffness(k, g, w, *lambda, *mu),
        Law::Matrix(d) => add_stiffness_matrix(k, g, w, d),
        Law::Cylindrical {
            local,
            origin,
            axis,
        } => {
            let p = x_q();
            let f = cylindrical_frame(*origin, *axis, p).ok_or(FeError::InvalidValue {
                field: format!("cylindrical material axes at point {p:?}"),
                value: 0.0,
                reason: "the point lies on the axis, where the radial direction is undefined",
            })?;
            add_stiffness_matrix(k, g, w, &rotate(local, &f));
        }
    }
    Ok(())
}

/// Stiffness of an isoparametric element, `k` overwritten.
pub(crate) fn stiffness<const N: usize, const D: usize>(
    x: &[[Real; 3]; N],
    shape: ShapeFn<N>,
    rule: &[([Real; 3], Real)],
    law: &Law,
    k: &mut SMatrix<Real, D, D>,
) -> Result<(), FeError> {
    debug_assert_eq!(D, 3 * N);
    k.fill(0.0);
    for &(xi, w) in rule {
        let (n, dn) = shape(xi);
        let (j, det) = jacobian(x, &dn, xi)?;
        let g = gradients(&j, det, &dn);
        add_point(k, &g, w * det, law, || {
            std::array::from_fn(|i| (0..N).map(|a| n[a] * x[a][i]).sum())
        })?;
    }
    Ok(())
}

/// Scalar consistent mass m_ab = ∫ ρ N_a N_b dV, `m` overwritten.
pub(crate) fn mass_scalar<const N: usize>(
    x: &[[Real; 3]; N],
    shape: ShapeFn<N>,
    rule: &[([Real; 3], Real)],
    rho: Real,
    m: &mut SMatrix<Real, N, N>,
) -> Result<(), FeError> {
    m.fill(0.0);
    for &(xi, w) in rule {
        let (n, dn) = shape(xi);
        let (_, det) = jacobian(x, &dn, xi)?;
        let s = rho * w * det;
        for a in 0..N {
            for b in a..N {
                let v = s * n[a] * n[b];
                m[(a, b)] += v;
                if b != a {
                    m[(b, a)] += v;
                }
            }
        }
    }
    Ok(())
}

/// The isotropic law as a matrix (for tests comparing the two paths).
#[cfg(test)]
pub(crate) fn isotropic_law_matrix(lambda: Real, mu: Real) -> Law {
    Law::Matrix(crate::elasticity::isotropic_matrix(lambda, mu))
}
