//! Local topology of every cell kind: edges, faces and the natural coordinates of the nodes.
//!
//! The tables follow the node order documented in [`crate::mesh`]. Each face lists its corners
//! counter-clockwise seen from outside the cell (its right-hand normal points out), then its
//! mid-edge nodes in the face kind's order (quad8: (0,1) (1,2) (2,3) (3,0); tri6: (0,1) (1,2)
//! (2,0) of the face's corners). The unit tests derive every mid-edge entry from the edge
//! table and every orientation from the natural coordinates.

use crate::{CellKind, Real};

/// One face of a volume cell: its kind and its local node indices.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LocalFace {
    pub kind: CellKind,
    pub nodes: &'static [usize],
}

const fn q4(nodes: &'static [usize]) -> LocalFace {
    LocalFace {
        kind: CellKind::Quad4,
        nodes,
    }
}
const fn q8(nodes: &'static [usize]) -> LocalFace {
    LocalFace {
        kind: CellKind::Quad8,
        nodes,
    }
}
const fn t3(nodes: &'static [usize]) -> LocalFace {
    LocalFace {
        kind: CellKind::Tri3,
        nodes,
    }
}
const fn t6(nodes: &'static [usize]) -> LocalFace {
    LocalFace {
        kind: CellKind::Tri6,
        nodes,
    }
}

const HEX_EDGES: [[usize; 2]; 12] = [
    [0, 1],
    [1, 2],
    [2, 3],
    [3, 0],
    [4, 5],
    [5, 6],
    [6, 7],
    [7, 4],
    [0, 4],
    [1, 5],
    [2, 6],
    [3, 7],
];
const TET_EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]];
const WEDGE_EDGES: [[usize; 2]; 9] = [
    [0, 1],
    [1, 2],
    [2, 0],
    [3, 4],
    [4, 5],
    [5, 3],
    [0, 3],
    [1, 4],
    [2, 5],
];
const PYRAMID_EDGES: [[usize; 2]; 8] = [
    [0, 1],
    [1, 2],
    [2, 3],
    [3, 0],
    [0, 4],
    [1, 4],
    [2, 4],
    [3, 4],
];
const QUAD_EDGES: [[usize; 2]; 4] = [[0, 1], [1, 2], [2, 3], [3, 0]];
const TRI_EDGES: [[usize; 2]; 3] = [[0, 1], [1, 2], [2, 0]];

/// Edges as corner pairs (see [`CellKind::edges`]).
pub(crate) fn edges(kind: CellKind) -> &'static [[usize; 2]] {
    match kind.linear() {
        CellKind::Hex8 => &HEX_EDGES,
        CellKind::Tet4 => &TET_EDGES,
        CellKind::Wedge6 => &WEDGE_EDGES,
        CellKind::Pyramid5 => &PYRAMID_EDGES,
        CellKind::Quad4 => &QUAD_EDGES,
        _ => &TRI_EDGES,
    }
}

/// Faces ξ = −1, ξ = +1, η = −1, η = +1, ζ = −1, ζ = +1.
const HEX8_FACES: [LocalFace; 6] = [
    q4(&[0, 4, 7, 3]),
    q4(&[1, 2, 6, 5]),
    q4(&[0, 1, 5, 4]),
    q4(&[3, 7, 6, 2]),
    q4(&[0, 3, 2, 1]),
    q4(&[4, 5, 6, 7]),
];
const HEX20_FACES: [LocalFace; 6] = [
    q8(&[0, 4, 7, 3, 16, 15, 19, 11]),
    q8(&[1, 2, 6, 5, 9, 18, 13, 17]),
    q8(&[0, 1, 5, 4, 8, 17, 12, 16]),
    q8(&[3, 7, 6, 2, 19, 14, 18, 10]),
    q8(&[0, 3, 2, 1, 11, 10, 9, 8]),
    q8(&[4, 5, 6, 7, 12, 13, 14, 15]),
];
/// Faces ζ = 0, η = 0, ξ = 0, ξ + η + ζ = 1.
const TET4_FACES: [LocalFace; 4] = [
    t3(&[0, 2, 1]),
    t3(&[0, 1, 3]),
    t3(&[0, 3, 2]),
    t3(&[1, 2, 3]),
];
const TET10_FACES: [LocalFace; 4] = [
    t6(&[0, 2, 1, 6, 5, 4]),
    t6(&[0, 1, 3, 4, 8, 7]),
    t6(&[0, 3, 2, 7, 9, 6]),
    t6(&[1, 2, 3, 5, 9, 8]),
];
/// Faces ζ = −1, ζ = +1, η = 0, ξ + η = 1, ξ = 0.
const WEDGE6_FACES: [LocalFace; 5] = [
    t3(&[0, 2, 1]),
    t3(&[3, 4, 5]),
    q4(&[0, 1, 4, 3]),
    q4(&[1, 2, 5, 4]),
    q4(&[0, 3, 5, 2]),
];
const WEDGE15_FACES: [LocalFace; 5] = [
    t6(&[0, 2, 1, 8, 7, 6]),
    t6(&[3, 4, 5, 9, 10, 11]),
    q8(&[0, 1, 4, 3, 6, 13, 9, 12]),
    q8(&[1, 2, 5, 4, 7, 14, 10, 13]),
    q8(&[0, 3, 5, 2, 12, 11, 14, 8]),
];
/// Faces: the base, then the sides on edges (0,1), (1,2), (2,3), (3,0).
const PYRAMID5_FACES: [LocalFace; 5] = [
    q4(&[0, 3, 2, 1]),
    t3(&[0, 1, 4]),
    t3(&[1, 2, 4]),
    t3(&[2, 3, 4]),
    t3(&[3, 0, 4]),
];
const PYRAMID13_FACES: [LocalFace; 5] = [
    q8(&[0, 3, 2, 1, 8, 7, 6, 5]),
    t6(&[0, 1, 4, 5, 10, 9]),
    t6(&[1, 2, 4, 6, 11, 10]),
    t6(&[2, 3, 4, 7, 12, 11]),
    t6(&[3, 0, 4, 8, 9, 12]),
];

/// Local faces (see [`CellKind::faces`]).
pub(crate) fn faces(kind: CellKind) -> &'static [LocalFace] {
    match kind {
        CellKind::Hex8 => &HEX8_FACES,
        CellKind::Hex20 => &HEX20_FACES,
        CellKind::Tet4 => &TET4_FACES,
        CellKind::Tet10 => &TET10_FACES,
        CellKind::Wedge6 => &WEDGE6_FACES,
        CellKind::Wedge15 => &WEDGE15_FACES,
        CellKind::Pyramid5 => &PYRAMID5_FACES,
        CellKind::Pyramid13 => &PYRAMID13_FACES,
        CellKind::Quad4 | CellKind::Quad8 | CellKind::Tri3 | CellKind::Tri6 => &[],
    }
}

const HEX_CORNERS: [[Real; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];
const TET_CORNERS: [[Real; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
];
const WEDGE_CORNERS: [[Real; 3]; 6] = [
    [0.0, 0.0, -1.0],
    [1.0, 0.0, -1.0],
    [0.0, 1.0, -1.0],
    [0.0, 0.0, 1.0],
    [1.0, 0.0, 1.0],
    [0.0, 1.0, 1.0],
];
const PYRAMID_CORNERS: [[Real; 3]; 5] = [
    [-1.0, -1.0, 0.0],
    [1.0, -1.0, 0.0],
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
];
const QUAD_CORNERS: [[Real; 3]; 4] = [
    [-1.0, -1.0, 0.0],
    [1.0, -1.0, 0.0],
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
];
const TRI_CORNERS: [[Real; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

/// Natural coordinates of the corners of `kind` (faces: ζ = 0).
pub fn corner_coords(kind: CellKind) -> &'static [[Real; 3]] {
    match kind.linear() {
        CellKind::Hex8 => &HEX_CORNERS,
        CellKind::Tet4 => &TET_CORNERS,
        CellKind::Wedge6 => &WEDGE_CORNERS,
        CellKind::Pyramid5 => &PYRAMID_CORNERS,
        CellKind::Quad4 => &QUAD_CORNERS,
        _ => &TRI_CORNERS,
    }
}

/// Natural coordinates of node `a` of `kind`: a corner, or the midpoint of its edge.
pub fn node_coords(kind: CellKind, a: usize) -> [Real; 3] {
    let c = corner_coords(kind);
    if a < c.len() {
        return c[a];
    }
    let [p, q] = edges(kind)[a - c.len()];
    std::array::from_fn(|k| 0.5 * (c[p][k] + c[q][k]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sub(a: [Real; 3], b: [Real; 3]) -> [Real; 3] {
        std::array::from_fn(|k| a[k] - b[k])
    }
    fn cross(a: [Real; 3], b: [Real; 3]) -> [Real; 3] {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }
    fn dot(a: [Real; 3], b: [Real; 3]) -> Real {
        (0..3).map(|k| a[k] * b[k]).sum()
    }

    /// Edge `[p, q]` of `kind` (either direction) → its mid-edge node.
    fn mid(kind: CellKind, p: usize, q: usize) -> usize {
        let i = edges(kind)
            .iter()
            .position(|e| *e == [p, q] || *e == [q, p])
            .unwrap_or_else(|| panic!("{kind}: ({p},{q}) is not an edge"));
        kind.n_corners() + i
    }

    /// Every face: corners outward (normal · (face centroid − cell centroid) > 0, in natural
    /// coordinates, where every face is flat), mid-edge entries on the face's edges, face kind
    /// consistent with the cell's order; every edge lies on two faces.
    #[test]
    fn faces_are_outward_and_consistent_with_the_edges() {
        for kind in CellKind::ALL.into_iter().filter(|k| k.is_volume()) {
            let nc = kind.n_corners();
            let centroid: [Real; 3] = std::array::from_fn(|k| {
                (0..nc).map(|a| node_coords(kind, a)[k]).sum::<Real>() / nc as Real
            });
            let mut edge_faces = vec![0; edges(kind).len()];
            for f in kind.faces() {
                assert_eq!(f.nodes.len(), f.kind.n_nodes(), "{kind}");
                assert_eq!(f.kind.is_quadratic(), kind.is_quadratic(), "{kind}");
                let m = f.kind.n_corners();
                let x = |a: usize| node_coords(kind, f.nodes[a]);
                let n = cross(sub(x(1), x(0)), sub(x(m - 1), x(0)));
                let fc: [Real; 3] =
                    std::array::from_fn(|k| (0..m).map(|a| x(a)[k]).sum::<Real>() / m as Real);
                assert!(dot(n, sub(fc, centroid)) > 0.0, "{kind} face {:?}", f.nodes);
                for e in 0..m {
                    let (p, q) = (f.nodes[e], f.nodes[(e + 1) % m]);
                    let i = mid(kind, p, q) - nc;
                    edge_faces[i] += 1;
                    if kind.is_quadratic() {
                        assert_eq!(f.nodes[m + e], nc + i, "{kind} face {:?}", f.nodes);
                    }
                }
            }
            assert!(edge_faces.iter().all(|&c| c == 2), "{kind}: {edge_faces:?}");
            assert_eq!(edges(kind).len() + nc, kind.quadratic().n_nodes());
        }
    }

    /// The faces of each cell enclose its reference volume (divergence theorem:
    /// V = ⅓ Σ_faces ∫ x·n dA, each flat face split into triangles from its first corner):
    /// hex 8, tet 1/6, wedge 1, pyramid 4/3.
    #[test]
    fn faces_enclose_the_reference_volume() {
        for (kind, volume) in [
            (CellKind::Hex8, 8.0),
            (CellKind::Tet4, 1.0 / 6.0),
            (CellKind::Wedge6, 1.0),
            (CellKind::Pyramid5, 4.0 / 3.0),
        ] {
            let mut v = 0.0;
            for f in kind.faces() {
                let x = |a: usize| node_coords(kind, f.nodes[a]);
                for a in 1..f.kind.n_corners() - 1 {
                    v += dot(x(0), cross(x(a), x(a + 1))) / 6.0;
                }
            }
            assert!((v - volume).abs() < 1e-14, "{kind}: {v}");
        }
    }
}
