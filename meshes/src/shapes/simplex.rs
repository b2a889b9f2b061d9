//! Shape functions of the simplices: tet4, tet10 and the faces tri3, tri6.
//!
//! Natural coordinates (ξ, η, ζ) with barycentric L0 = 1 − ξ − η − ζ, L1 = ξ, L2 = η, L3 = ζ
//! (triangles: L0 = 1 − ξ − η, L1 = ξ, L2 = η). Node order as in `squeal_meshes::mesh`.
//!
//! # Reference
//! Linear: N_a = L_a. Quadratic (Lagrange P2): corners N_a = L_a (2 L_a − 1), mid-edge nodes
//! N_(p,q) = 4 L_p L_q; Zienkiewicz & Taylor, *The Finite Element Method*, vol. 1, §8.8.

use crate::Real;

/// Edges (p, q) of the tet10 mid-edge nodes 4..10.
const TET_EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]];
/// Edges (p, q) of the tri6 mid-edge nodes 3..6.
const TRI_EDGES: [[usize; 2]; 3] = [[0, 1], [1, 2], [2, 0]];

/// ∂L_a/∂ξ_j of the tetrahedron's barycentric coordinates.
const DL_TET: [[Real; 3]; 4] = [
    [-1.0, -1.0, -1.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
];
/// ∂L_a/∂ξ_j of the triangle's barycentric coordinates.
const DL_TRI: [[Real; 2]; 3] = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];

fn tet_l(xi: [Real; 3]) -> [Real; 4] {
    [1.0 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]]
}

/// Linear tetrahedron: N_a = L_a.
pub fn tet4(xi: [Real; 3]) -> ([Real; 4], [[Real; 3]; 4]) {
    (tet_l(xi), DL_TET)
}

/// Quadratic tetrahedron (10 nodes).
pub fn tet10(xi: [Real; 3]) -> ([Real; 10], [[Real; 3]; 10]) {
    let l = tet_l(xi);
    let mut n = [0.0; 10];
    let mut d = [[0.0; 3]; 10];
    for a in 0..4 {
        n[a] = l[a] * (2.0 * l[a] - 1.0);
        let f = 4.0 * l[a] - 1.0;
        d[a] = DL_TET[a].map(|g| f * g);
    }
    for (e, &[p, q]) in TET_EDGES.iter().enumerate() {
        n[4 + e] = 4.0 * l[p] * l[q];
        d[4 + e] = std::array::from_fn(|j| 4.0 * (DL_TET[p][j] * l[q] + l[p] * DL_TET[q][j]));
    }
    (n, d)
}

fn tri_l(xi: [Real; 2]) -> [Real; 3] {
    [1.0 - xi[0] - xi[1], xi[0], xi[1]]
}

/// Linear triangle: N_a = L_a.
pub fn tri3(xi: [Real; 2]) -> ([Real; 3], [[Real; 2]; 3]) {
    (tri_l(xi), DL_TRI)
}

/// Quadratic triangle (6 nodes).
pub fn tri6(xi: [Real; 2]) -> ([Real; 6], [[Real; 2]; 6]) {
    let l = tri_l(xi);
    let mut n = [0.0; 6];
    let mut d = [[0.0; 2]; 6];
    for a in 0..3 {
        n[a] = l[a] * (2.0 * l[a] - 1.0);
        let f = 4.0 * l[a] - 1.0;
        d[a] = DL_TRI[a].map(|g| f * g);
    }
    for (e, &[p, q]) in TRI_EDGES.iter().enumerate() {
        n[3 + e] = 4.0 * l[p] * l[q];
        d[3 + e] = std::array::from_fn(|j| 4.0 * (DL_TRI[p][j] * l[q] + l[p] * DL_TRI[q][j]));
    }
    (n, d)
}
