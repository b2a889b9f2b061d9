//! Jacobian determinants of hexahedra at their nodes, in squeal (= VTK) node order.
//!
//! A hex can be positive at its centroid and at every Gauss point yet inverted near one corner
//! (a corner pushed past the plane of its neighbours): the element then integrates a folded
//! volume and shifts the frequencies without any error. det J at every corner (and, for hex20,
//! at every mid-edge node) catches it; the msh reader rejects such cells.
//!
//! # Reference
//! Isoparametric map $x(ξ) = \sum_a N_a(ξ) x_a$, $J_{ij} = ∂x_i/∂ξ_j$; hex8 trilinear, hex20
//! serendipity (corner $N = \tfrac18(1+ξξ_a)(1+ηη_a)(1+ζζ_a)(ξξ_a+ηη_a+ζζ_a−2)$, mid-edge
//! with $ξ_a = 0$: $N = \tfrac14(1−ξ^2)(1+ηη_a)(1+ζζ_a)$), e.g. Zienkiewicz & Taylor, *The
//! Finite Element Method*, vol. 1, §8.7. Written here because `squeal-meshes` does not depend
//! on `squeal-fe` (the dependency points the other way).

use crate::{CellKind, Real};

/// Natural coordinates of the hex20 nodes (the first 8: the hex8 corners), VTK order:
/// corners, then mid-edges 8:(0,1) 9:(1,2) 10:(2,3) 11:(3,0) 12:(4,5) 13:(5,6) 14:(6,7)
/// 15:(7,4) 16:(0,4) 17:(1,5) 18:(2,6) 19:(3,7).
pub const HEX_NODES: [[Real; 3]; 20] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
    [0.0, -1.0, -1.0],
    [1.0, 0.0, -1.0],
    [0.0, 1.0, -1.0],
    [-1.0, 0.0, -1.0],
    [0.0, -1.0, 1.0],
    [1.0, 0.0, 1.0],
    [0.0, 1.0, 1.0],
    [-1.0, 0.0, 1.0],
    [-1.0, -1.0, 0.0],
    [1.0, -1.0, 0.0],
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
];

/// ∂N_a/∂ξ at `xi` for the first `n` nodes (8: trilinear hex8, 20: serendipity hex20).
fn shape_derivatives(n: usize, xi: [Real; 3]) -> [[Real; 3]; 20] {
    let mut d = [[0.0; 3]; 20];
    for (a, node) in HEX_NODES.iter().enumerate().take(n) {
        let f = [0, 1, 2].map(|k| 1.0 + xi[k] * node[k]);
        if n == 8 {
            for k in 0..3 {
                let (p, q) = ((k + 1) % 3, (k + 2) % 3);
                d[a][k] = node[k] * f[p] * f[q] / 8.0;
            }
        } else if a < 8 {
            let s: Real = (0..3).map(|k| xi[k] * node[k]).sum();
            for k in 0..3 {
                let (p, q) = ((k + 1) % 3, (k + 2) % 3);
                d[a][k] = node[k] * f[p] * f[q] * (s + xi[k] * node[k] - 1.0) / 8.0;
            }
        } else {
            // The coordinate in which the node is mid-edge (ξ_a = 0).
            let m = (0..3).find(|&k| node[k] == 0.0).unwrap_or(0);
            let (p, q) = ((m + 1) % 3, (m + 2) % 3);
            let g = 1.0 - xi[m] * xi[m];
            d[a][m] = -2.0 * xi[m] * f[p] * f[q] / 4.0;
            d[a][p] = g * node[p] * f[q] / 4.0;
            d[a][q] = g * f[p] * node[q] / 4.0;
        }
    }
    d
}

/// det J at natural coordinates `xi` of the hex with nodes `x` (8 or 20, squeal order).
pub fn hex_jacobian_at(x: &[[Real; 3]], xi: [Real; 3]) -> Real {
    let n = if x.len() >= 20 { 20 } else { 8 };
    let d = shape_derivatives(n, xi);
    let mut j = [[0.0; 3]; 3];
    for a in 0..n {
        for i in 0..3 {
            for k in 0..3 {
                j[i][k] += x[a][i] * d[a][k];
            }
        }
    }
    j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1])
        - j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0])
        + j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0])
}

/// det J at every node of the hex (8 corners of a hex8; 20 nodes of a hex20), the smallest
/// first: (node index in squeal order, det J).
pub fn hex_node_jacobians(x: &[[Real; 3]]) -> Vec<(usize, Real)> {
    let n = if x.len() >= 20 { 20 } else { 8 };
    let mut v: Vec<(usize, Real)> = (0..n)
        .map(|a| (a, hex_jacobian_at(&x[..n], HEX_NODES[a])))
        .collect();
    v.sort_by(|a, b| a.1.total_cmp(&b.1));
    v
}

/// ∂N_a/∂ξ of any volume kind at a natural point (pyramids: collapsed coordinates).
fn derivatives(kind: CellKind, p: [Real; 3]) -> Vec<[Real; 3]> {
    use crate::shapes::{pyramid, simplex, wedge};
    match kind {
        CellKind::Hex8 => shape_derivatives(8, p)[..8].to_vec(),
        CellKind::Hex20 => shape_derivatives(20, p).to_vec(),
        CellKind::Tet4 => simplex::tet4(p).1.to_vec(),
        CellKind::Tet10 => simplex::tet10(p).1.to_vec(),
        CellKind::Wedge6 => wedge::wedge6(p).1.to_vec(),
        CellKind::Wedge15 => wedge::wedge15(p).1.to_vec(),
        CellKind::Pyramid5 => pyramid::pyramid5(p).1.to_vec(),
        CellKind::Pyramid13 => pyramid::pyramid13(p).1.to_vec(),
        _ => Vec::new(),
    }
}

/// det J of the cell `x` (squeal order) of `kind` at natural point `p`.
pub fn jacobian_at(kind: CellKind, x: &[[Real; 3]], p: [Real; 3]) -> Real {
    let d = derivatives(kind, p);
    let mut j = [[0.0; 3]; 3];
    for (a, da) in d.iter().enumerate() {
        for i in 0..3 {
            for k in 0..3 {
                j[i][k] += x[a][i] * da[k];
            }
        }
    }
    j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1])
        - j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0])
        + j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0])
}

/// The points where [`node_jacobians`] evaluates det J, with the node each belongs to:
/// every node in natural coordinates; a pyramid's apex from the four base-corner directions
/// (its rational map has a direction-dependent limit there), pyramid points in collapsed
/// coordinates (x̂, ŷ, ζ).
fn node_points(kind: CellKind) -> Vec<(usize, [Real; 3])> {
    let mut v = Vec::new();
    for a in 0..kind.n_nodes() {
        let p = crate::topology::node_coords(kind, a);
        match kind {
            CellKind::Pyramid5 | CellKind::Pyramid13 => {
                if a == 4 {
                    for q in [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]] {
                        v.push((a, [q[0], q[1], 1.0]));
                    }
                } else {
                    let s = 1.0 - p[2];
                    v.push((a, [p[0] / s, p[1] / s, p[2]]));
                }
            }
            _ => v.push((a, p)),
        }
    }
    v
}

/// det J at every node of a cell of any volume kind (for a linear kind: its corners), the
/// smallest first: (node index in squeal order, det J).
pub fn node_jacobians(kind: CellKind, x: &[[Real; 3]]) -> Vec<(usize, Real)> {
    let mut v: Vec<(usize, Real)> = node_points(kind)
        .into_iter()
        .map(|(a, p)| (a, jacobian_at(kind, x, p)))
        .collect();
    v.sort_by(|a, b| a.1.total_cmp(&b.1));
    v
}

/// det J at the centroid of the cell's corners (its linear kind's map): the orientation test.
pub fn centroid_jacobian(kind: CellKind, x: &[[Real; 3]]) -> Real {
    let lin = kind.linear();
    let p = match lin {
        CellKind::Tet4 => [0.25; 3],
        CellKind::Wedge6 => [1.0 / 3.0, 1.0 / 3.0, 0.0],
        CellKind::Pyramid5 => [0.0, 0.0, 0.25],
        _ => [0.0; 3],
    };
    jacobian_at(lin, &x[..lin.n_nodes()], p)
}

/// The node permutation that mirrors a cell of `kind` (reverses its orientation):
/// `new[k] = old[MIRROR[k]]`. hex: bottom ↔ top; tet: 1 ↔ 2; wedge: 1 ↔ 2, 4 ↔ 5;
/// pyramid: 1 ↔ 3; the mid-edge nodes follow their edges.
pub fn mirror(kind: CellKind) -> &'static [usize] {
    match kind {
        CellKind::Hex8 => &[4, 5, 6, 7, 0, 1, 2, 3],
        CellKind::Hex20 => &[
            4, 5, 6, 7, 0, 1, 2, 3, 12, 13, 14, 15, 8, 9, 10, 11, 16, 17, 18, 19,
        ],
        CellKind::Tet4 => &[0, 2, 1, 3],
        CellKind::Tet10 => &[0, 2, 1, 3, 6, 5, 4, 7, 9, 8],
        CellKind::Wedge6 => &[0, 2, 1, 3, 5, 4],
        CellKind::Wedge15 => &[0, 2, 1, 3, 5, 4, 8, 7, 6, 11, 10, 9, 12, 14, 13],
        CellKind::Pyramid5 => &[0, 3, 2, 1, 4],
        CellKind::Pyramid13 => &[0, 3, 2, 1, 4, 8, 7, 6, 5, 9, 12, 11, 10],
        CellKind::Quad4 => &[0, 3, 2, 1],
        CellKind::Quad8 => &[0, 3, 2, 1, 7, 6, 5, 4],
        CellKind::Tri3 => &[0, 2, 1],
        CellKind::Tri6 => &[0, 2, 1, 5, 4, 3],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The nodes of the reference cube mapped by x = A ξ + b.
    fn affine(n: usize) -> Vec<[Real; 3]> {
        let a = [[2.0, 0.3, 0.1], [0.0, 1.5, -0.2], [0.4, 0.0, 0.5]];
        HEX_NODES[..n]
            .iter()
            .map(|p| [0, 1, 2].map(|i| 1.0 + (0..3).map(|k| a[i][k] * p[k]).sum::<Real>()))
            .collect()
    }

    #[test]
    fn affine_cells_have_det_a_at_every_node() {
        let det_a = 2.0 * (1.5 * 0.5) - 0.3 * (0.0 * 0.5 + 0.2 * 0.4) + 0.1 * (0.0 - 1.5 * 0.4);
        for n in [8, 20] {
            for (_, d) in hex_node_jacobians(&affine(n)) {
                assert!((d - det_a).abs() < 1e-12, "{n}: {d} vs {det_a}");
            }
        }
    }

    /// The derivatives are those of the shape functions: finite differences of the map.
    #[test]
    fn derivatives_match_finite_differences_of_the_map() {
        fn shape(n: usize, xi: [Real; 3]) -> Vec<Real> {
            HEX_NODES[..n]
                .iter()
                .enumerate()
                .map(|(a, p)| {
                    let f = [0, 1, 2].map(|k| 1.0 + xi[k] * p[k]);
                    if n == 8 {
                        f[0] * f[1] * f[2] / 8.0
                    } else if a < 8 {
                        f[0] * f[1] * f[2] * ((0..3).map(|k| xi[k] * p[k]).sum::<Real>() - 2.0)
                            / 8.0
                    } else {
                        (0..3)
                            .map(|k| {
                                if p[k] == 0.0 {
                                    1.0 - xi[k] * xi[k]
                                } else {
                                    f[k]
                                }
                            })
                            .product::<Real>()
                            / 4.0
                    }
                })
                .collect()
        }
        let xi = [0.3, -0.7, 0.45];
        for n in [8, 20] {
            let d = shape_derivatives(n, xi);
            for k in 0..3 {
                let (mut p, mut m) = (xi, xi);
                p[k] += 1e-6;
                m[k] -= 1e-6;
                let (np, nm) = (shape(n, p), shape(n, m));
                for a in 0..n {
                    let fd = (np[a] - nm[a]) / 2e-6;
                    assert!(
                        (fd - d[a][k]).abs() < 1e-8,
                        "n {n} node {a} dir {k}: {fd} vs {}",
                        d[a][k]
                    );
                }
            }
            // Partition of unity.
            assert!((shape(n, xi).iter().sum::<Real>() - 1.0).abs() < 1e-14);
        }
    }

    /// Every kind: an affine image of the reference cell has det J = det A at every node and
    /// at the centroid; the mirror permutation flips the sign, and maps edges onto edges.
    #[test]
    fn every_kind_affine_and_mirrored() {
        let a = [[2.0, 0.3, 0.1], [0.0, 1.5, -0.2], [0.4, 0.0, 0.5]];
        let det_a = 2.0 * (1.5 * 0.5) - 0.3 * (0.0 * 0.5 + 0.2 * 0.4) + 0.1 * (0.0 - 1.5 * 0.4);
        for kind in CellKind::ALL.into_iter().filter(|k| k.is_volume()) {
            let x: Vec<[Real; 3]> = (0..kind.n_nodes())
                .map(|n| {
                    let p = crate::topology::node_coords(kind, n);
                    [0, 1, 2].map(|i| 1.0 + (0..3).map(|k| a[i][k] * p[k]).sum::<Real>())
                })
                .collect();
            for (n, d) in node_jacobians(kind, &x) {
                assert!((d - det_a).abs() < 1e-12, "{kind} node {n}: {d} vs {det_a}");
            }
            assert!(
                (centroid_jacobian(kind, &x) - det_a).abs() < 1e-12,
                "{kind}"
            );
            let m = mirror(kind);
            let y: Vec<[Real; 3]> = m.iter().map(|&k| x[k]).collect();
            assert!(
                node_jacobians(kind, &y)
                    .iter()
                    .all(|&(_, d)| (d + det_a).abs() < 1e-12),
                "{kind}"
            );
            let nc = kind.n_corners();
            for (e, &[p, q]) in kind
                .edges()
                .iter()
                .enumerate()
                .filter(|_| kind.is_quadratic())
            {
                let img = [m[p], m[q]];
                let f = kind
                    .edges()
                    .iter()
                    .position(|&[r, s]| [r, s] == img || [s, r] == img);
                assert_eq!(f.map(|f| nc + f), Some(m[nc + e]), "{kind} edge {e}");
            }
        }
    }
}
