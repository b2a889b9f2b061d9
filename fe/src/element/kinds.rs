//! Element matrices of any volume cell kind: the shape functions and quadrature rules of each.
//!
//! | kind | stiffness rule | mass rule | why exact on straight-sided elements |
//! |---|---|---|---|
//! | hex8 (incompatible / plain) | 2×2×2 Gauss | 2×2×2 Gauss | trilinear: integrands of degree ≤ 2 per direction on a parallelepiped |
//! | hex20 | 3×3×3 Gauss | 3×3×3 Gauss | degree ≤ 4 per direction |
//! | tet4 | 1 point | 4 points (degree 2) | B constant; N_a N_b of degree 2 |
//! | tet10 | 14 points (degree 5) | 14 points (degree 5) | BᵀDB degree 2, N_a N_b degree 4; degree 3 also integrates the curved element's ∫ Bᵀ dV exactly (patch test) |
//! | wedge6 | triangle degree 2 × 2 Gauss | same | degree ≤ 2 in the triangle and in ζ |
//! | wedge15 | triangle degree 4 (6 points) × 3 Gauss | same | degree ≤ 4 in the triangle and in ζ; also the curved element's ∫ Bᵀ dV (degree 4 × 5) |
//! | pyramid5 | conical 2×2×3 | same | polynomial of degree ≤ (2, 2, 4) in collapsed coordinates |
//! | pyramid13 | conical 3×3×3 | conical 3×3×4 | stiffness ≤ (4, 4, 4), mass ≤ (4, 4, 6); curved ∫ Bᵀ dV ≤ (5, 5, 5) |

use super::rules::{hexahedron, pyramid, tetrahedron, wedge};
use super::solid::{mass_scalar, stiffness, BlockLaw, Law, ShapeFn};
use super::{hex8_incompatible, pyramid as pyr, shape, simplex, wedge as wdg};
use crate::assembly::Hex8Formulation;
use crate::{FeError, Real, SolidMaterial};
use nalgebra::{DMatrix, SMatrix};
use squeal_meshes::CellKind;

fn run<const N: usize, const D: usize>(
    x: &[[Real; 3]; N],
    shape: ShapeFn<N>,
    krule: &[([Real; 3], Real)],
    mrule: &[([Real; 3], Real)],
    law: &Law,
    rho: Real,
    ke: &mut [Real],
    me: &mut [Real],
) -> Result<(), FeError> {
    let mut k = SMatrix::<Real, D, D>::zeros();
    stiffness(x, shape, krule, law, &mut k)?;
    ke.copy_from_slice(k.as_slice());
    let mut m = SMatrix::<Real, N, N>::zeros();
    mass_scalar(x, shape, mrule, rho, &mut m)?;
    me.copy_from_slice(m.as_slice());
    Ok(())
}

fn gather<const N: usize>(nd: &[usize], nodes: &[[Real; 3]]) -> [[Real; 3]; N] {
    std::array::from_fn(|a| nodes[nd[a]])
}

/// Stiffness (column-major 3N×3N into `ke`) and scalar mass (N×N into `me`) of the cell with
/// node indices `nd` into `nodes`.
pub(crate) fn element_into(
    kind: CellKind,
    hex8: Hex8Formulation,
    nd: &[usize],
    nodes: &[[Real; 3]],
    law: &Law,
    rho: Real,
    ke: &mut [Real],
    me: &mut [Real],
) -> Result<(), FeError> {
    match kind {
        CellKind::Hex8 => {
            let x = gather::<8>(nd, nodes);
            match hex8 {
                Hex8Formulation::Standard => run::<8, 24>(
                    &x,
                    shape::hex8,
                    hexahedron(2),
                    hexahedron(2),
                    law,
                    rho,
                    ke,
                    me,
                ),
                Hex8Formulation::Incompatible => {
                    let k = hex8_incompatible::stiffness_law(&x, law)?;
                    ke.copy_from_slice(k.as_slice());
                    let mut m = SMatrix::<Real, 8, 8>::zeros();
                    mass_scalar(&x, shape::hex8, hexahedron(2), rho, &mut m)?;
                    me.copy_from_slice(m.as_slice());
                    Ok(())
                }
            }
        }
        CellKind::Hex20 => {
            let x = gather::<20>(nd, nodes);
            let r = hexahedron(3);
            run::<20, 60>(&x, shape::hex20, r, r, law, rho, ke, me)
        }
        CellKind::Tet4 => {
            let x = gather::<4>(nd, nodes);
            run::<4, 12>(
                &x,
                simplex::tet4,
                tetrahedron(1),
                tetrahedron(2),
                law,
                rho,
                ke,
                me,
            )
        }
        CellKind::Tet10 => {
            let x = gather::<10>(nd, nodes);
            let r = tetrahedron(5);
            run::<10, 30>(&x, simplex::tet10, r, r, law, rho, ke, me)
        }
        CellKind::Wedge6 => {
            let x = gather::<6>(nd, nodes);
            let r = wedge(2, 2);
            run::<6, 18>(&x, wdg::wedge6, r, r, law, rho, ke, me)
        }
        CellKind::Wedge15 => {
            let x = gather::<15>(nd, nodes);
            let r = wedge(4, 3);
            run::<15, 45>(&x, wdg::wedge15, r, r, law, rho, ke, me)
        }
        CellKind::Pyramid5 => {
            let x = gather::<5>(nd, nodes);
            let r = pyramid(2, 3);
            run::<5, 15>(&x, pyr::pyramid5, r, r, law, rho, ke, me)
        }
        CellKind::Pyramid13 => {
            let x = gather::<13>(nd, nodes);
            run::<13, 39>(
                &x,
                pyr::pyramid13,
                pyramid(3, 3),
                pyramid(3, 4),
                law,
                rho,
                ke,
                me,
            )
        }
        CellKind::Quad4 | CellKind::Quad8 | CellKind::Tri3 | CellKind::Tri6 => {
            Err(FeError::WrongCellKind {
                block: String::new(),
                kind: kind.name().to_string(),
                expected: "a volume kind",
            })
        }
    }
}

/// Stiffness (3N × 3N) and consistent mass (3N × 3N) of one cell of `kind` with nodes `x`
/// (squeal order) and material `material` (its first frame for per-cell axes). Allocates:
/// for tests and inspection; assembly uses the allocation-free path.
pub fn element_matrices(
    kind: CellKind,
    x: &[[Real; 3]],
    material: &SolidMaterial,
    hex8: Hex8Formulation,
) -> Result<(DMatrix<Real>, DMatrix<Real>), FeError> {
    let n = kind.n_nodes();
    if x.len() != n {
        return Err(FeError::Dimension {
            what: "node coordinates of an element",
            got: x.len(),
            expected: n,
        });
    }
    let block = BlockLaw::new(material);
    let law = block.cell(0)?;
    let nd: Vec<usize> = (0..n).collect();
    let mut ke = vec![0.0; 9 * n * n];
    let mut me = vec![0.0; n * n];
    element_into(kind, hex8, &nd, x, &law, block.density(), &mut ke, &mut me)?;
    let m = DMatrix::from_fn(3 * n, 3 * n, |i, j| {
        if i % 3 == j % 3 {
            me[(j / 3) * n + i / 3]
        } else {
            0.0
        }
    });
    Ok((DMatrix::from_column_slice(3 * n, 3 * n, &ke), m))
}

/// Shape functions N_a and ∂N_a/∂ξ of a volume kind at a natural point (pyramids: collapsed
/// coordinates, see [`super::pyramid`]), as vectors (for tests and inspection).
pub fn shape_functions(kind: CellKind, xi: [Real; 3]) -> (Vec<Real>, Vec<[Real; 3]>) {
    fn v<const N: usize>((n, d): ([Real; N], [[Real; 3]; N])) -> (Vec<Real>, Vec<[Real; 3]>) {
        (n.to_vec(), d.to_vec())
    }
    match kind {
        CellKind::Hex8 => v(shape::hex8(xi)),
        CellKind::Hex20 => v(shape::hex20(xi)),
        CellKind::Tet4 => v(simplex::tet4(xi)),
        CellKind::Tet10 => v(simplex::tet10(xi)),
        CellKind::Wedge6 => v(wdg::wedge6(xi)),
        CellKind::Wedge15 => v(wdg::wedge15(xi)),
        CellKind::Pyramid5 => v(pyr::pyramid5(xi)),
        CellKind::Pyramid13 => v(pyr::pyramid13(xi)),
        _ => (Vec::new(), Vec::new()),
    }
}
