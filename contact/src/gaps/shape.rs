//! Face kinds of contact surfaces (quad4, quad8, tri3, tri6): reference nodes, shape
//! functions, and the reference-space facts the pairings need (corners, edges, inside/outside).

use crate::Real;
use serde::{Deserialize, Serialize};

/// The kind of a contact face: the faces of hex8/hex20 (quadrilaterals) and of
/// tet/wedge/pyramid elements (triangles).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FaceKind {
    /// Bilinear 4-node quadrilateral (face of a hex8).
    Quad4,
    /// Serendipity 8-node quadrilateral (face of a hex20).
    Quad8,
    /// Linear 3-node triangle (face of a tet4, wedge6, pyramid5).
    Tri3,
    /// Quadratic 6-node triangle (face of a tet10, wedge15, pyramid13).
    Tri6,
}

/// Reference coordinates (ξ_a, η_a) of the quad nodes: corners counterclockwise, then the
/// mid-sides 0–1, 1–2, 2–3, 3–0 (VTK and gmsh order, as squeal's meshes store faces).
pub(crate) const QUAD_REF: [[Real; 2]; 8] = [
    [-1.0, -1.0],
    [1.0, -1.0],
    [1.0, 1.0],
    [-1.0, 1.0],
    [0.0, -1.0],
    [1.0, 0.0],
    [0.0, 1.0],
    [-1.0, 0.0],
];

/// Reference coordinates (ξ_a, η_a) of the triangle nodes on the unit triangle ξ, η ≥ 0,
/// ξ + η ≤ 1: corners counterclockwise, then the mid-sides 0–1, 1–2, 2–0 (VTK and gmsh).
pub(crate) const TRI_REF: [[Real; 2]; 6] = [
    [0.0, 0.0],
    [1.0, 0.0],
    [0.0, 1.0],
    [0.5, 0.0],
    [0.5, 0.5],
    [0.0, 0.5],
];

/// Shape function values and derivatives of one face (first `n_nodes` entries used).
pub type Shape = ([Real; 8], [[Real; 2]; 8]);

impl FaceKind {
    /// Number of nodes (4, 8, 3 or 6).
    pub fn n_nodes(self) -> usize {
        match self {
            FaceKind::Quad4 => 4,
            FaceKind::Quad8 => 8,
            FaceKind::Tri3 => 3,
            FaceKind::Tri6 => 6,
        }
    }

    /// Number of corner nodes (4 or 3); the mid-side nodes follow them.
    pub fn n_corners(self) -> usize {
        match self {
            FaceKind::Quad4 | FaceKind::Quad8 => 4,
            FaceKind::Tri3 | FaceKind::Tri6 => 3,
        }
    }

    /// True for the quadratic faces (quad8, tri6).
    pub fn is_quadratic(self) -> bool {
        matches!(self, FaceKind::Quad8 | FaceKind::Tri6)
    }

    /// True for the triangles.
    pub fn is_triangle(self) -> bool {
        matches!(self, FaceKind::Tri3 | FaceKind::Tri6)
    }

    /// Kind from a node count (4 → quad4, 8 → quad8, 3 → tri3, 6 → tri6).
    pub fn from_n_nodes(n: usize) -> Option<Self> {
        match n {
            4 => Some(FaceKind::Quad4),
            8 => Some(FaceKind::Quad8),
            3 => Some(FaceKind::Tri3),
            6 => Some(FaceKind::Tri6),
            _ => None,
        }
    }

    /// Reference coordinates of the nodes (first `n_nodes`).
    pub(crate) fn nodes_ref(self) -> &'static [[Real; 2]] {
        if self.is_triangle() {
            &TRI_REF[..self.n_nodes()]
        } else {
            &QUAD_REF[..self.n_nodes()]
        }
    }

    /// Reference centroid: (0, 0) for quads, (1/3, 1/3) for triangles.
    pub(crate) fn center_ref(self) -> [Real; 2] {
        if self.is_triangle() {
            [1.0 / 3.0, 1.0 / 3.0]
        } else {
            [0.0, 0.0]
        }
    }

    /// The mid-side nodes of a quadratic face with the two corners of their edge:
    /// (mid-side, corner, corner); empty for linear faces.
    pub(crate) fn edges(self) -> &'static [(usize, usize, usize)] {
        match self {
            FaceKind::Quad8 => &[(4, 0, 1), (5, 1, 2), (6, 2, 3), (7, 3, 0)],
            FaceKind::Tri6 => &[(3, 0, 1), (4, 1, 2), (5, 2, 0)],
            _ => &[],
        }
    }

    /// The boundary nodes in order around the face: corners, with the mid-side nodes between
    /// them on quadratic faces.
    pub(crate) fn boundary(self) -> &'static [usize] {
        match self {
            FaceKind::Quad4 => &[0, 1, 2, 3],
            FaceKind::Quad8 => &[0, 4, 1, 5, 2, 6, 3, 7],
            FaceKind::Tri3 => &[0, 1, 2],
            FaceKind::Tri6 => &[0, 3, 1, 4, 2, 5],
        }
    }

    /// How far (ξ, η) lies outside the reference face, 0 inside: max(|ξ|, |η|) − 1 on quads
    /// (whose reference width is 2), −2·min(1 − ξ − η, ξ, η) on triangles (reference height
    /// 1, doubled so that the same value means the same fraction of the face's width).
    pub(crate) fn outside(self, xi: [Real; 2]) -> Real {
        let o = if self.is_triangle() {
            -2.0 * (1.0 - xi[0] - xi[1]).min(xi[0]).min(xi[1])
        } else {
            xi[0].abs().max(xi[1].abs()) - 1.0
        };
        o.max(0.0)
    }

    /// Reference coordinates within `tol` of a node coordinate (−1, 0, 1 on quads; 0, ½, 1
    /// on triangles, and the hypotenuse ξ + η = 1) set to it, so that a point on a node or an
    /// edge gets weights exactly 1 and 0.
    pub(crate) fn snap(self, xi: &mut [Real; 2], tol: Real) {
        let marks: &[Real] = if self.is_triangle() {
            &[0.0, 0.5, 1.0]
        } else {
            &[-1.0, 0.0, 1.0]
        };
        for c in xi.iter_mut() {
            for &s in marks {
                if (*c - s).abs() <= tol {
                    *c = s;
                }
            }
        }
        if self.is_triangle() {
            let l0 = 1.0 - xi[0] - xi[1];
            if l0 != 0.0 && l0.abs() <= tol {
                // On the hypotenuse: set one coordinate from the other, from a mark or else
                // from the larger (≥ ½, so 1 − it is exact and 1 − ξ − η is then exactly 0).
                let from_x = marks.contains(&xi[0]) || (!marks.contains(&xi[1]) && xi[0] >= xi[1]);
                if from_x {
                    xi[1] = 1.0 - xi[0];
                } else {
                    xi[0] = 1.0 - xi[1];
                }
            }
        }
    }

    /// Shape functions N_a(ξ, η) and their derivatives ∂N_a/∂ξ, ∂N_a/∂η (first `n_nodes`
    /// entries used). They sum to 1 for every (ξ, η) (partition of unity).
    pub fn shape(self, xi: [Real; 2]) -> Shape {
        let (x, y) = (xi[0], xi[1]);
        let mut n = [0.0; 8];
        let mut d = [[0.0; 2]; 8];
        match self {
            FaceKind::Quad4 => {
                for a in 0..4 {
                    let [xa, ya] = QUAD_REF[a];
                    n[a] = 0.25 * (1.0 + xa * x) * (1.0 + ya * y);
                    d[a] = [0.25 * xa * (1.0 + ya * y), 0.25 * ya * (1.0 + xa * x)];
                }
            }
            FaceKind::Quad8 => {
                for a in 0..4 {
                    let [xa, ya] = QUAD_REF[a];
                    let (p, q) = (1.0 + xa * x, 1.0 + ya * y);
                    let s = xa * x + ya * y - 1.0;
                    n[a] = 0.25 * p * q * s;
                    d[a] = [0.25 * xa * q * (s + p), 0.25 * ya * p * (s + q)];
                }
                for a in 4..8 {
                    let [xa, ya] = QUAD_REF[a];
                    if xa == 0.0 {
                        n[a] = 0.5 * (1.0 - x * x) * (1.0 + ya * y);
                        d[a] = [-x * (1.0 + ya * y), 0.5 * ya * (1.0 - x * x)];
                    } else {
                        n[a] = 0.5 * (1.0 + xa * x) * (1.0 - y * y);
                        d[a] = [0.5 * xa * (1.0 - y * y), -y * (1.0 + xa * x)];
                    }
                }
            }
            FaceKind::Tri3 => {
                n[..3].copy_from_slice(&[1.0 - x - y, x, y]);
                d[..3].copy_from_slice(&[[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]]);
            }
            FaceKind::Tri6 => {
                // Barycentric l0 = 1 − ξ − η, l1 = ξ, l2 = η and their gradients.
                let l = [1.0 - x - y, x, y];
                let g = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
                for a in 0..3 {
                    n[a] = l[a] * (2.0 * l[a] - 1.0);
                    let c = 4.0 * l[a] - 1.0;
                    d[a] = [c * g[a][0], c * g[a][1]];
                }
                for (m, i, j) in [(3, 0, 1), (4, 1, 2), (5, 2, 0)] {
                    n[m] = 4.0 * l[i] * l[j];
                    d[m] = [
                        4.0 * (g[i][0] * l[j] + l[i] * g[j][0]),
                        4.0 * (g[i][1] * l[j] + l[i] * g[j][1]),
                    ];
                }
            }
        }
        (n, d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ALL: [FaceKind; 4] = [
        FaceKind::Quad4,
        FaceKind::Quad8,
        FaceKind::Tri3,
        FaceKind::Tri6,
    ];

    /// Shape functions: partition of unity, Kronecker property at the nodes, derivatives
    /// against central differences, linear fields reproduced (the definitions of the
    /// bilinear, serendipity and Lagrange triangles).
    #[test]
    fn shape_functions() {
        for kind in ALL {
            let nn = kind.n_nodes();
            for xi in [[0.3, -0.7], [-0.9, 0.1], [1.2, 0.4], [0.2, 0.3]] {
                let (n, d) = kind.shape(xi);
                assert!((n[..nn].iter().sum::<Real>() - 1.0).abs() < 1e-14);
                for c in 0..2 {
                    let x: Real = (0..nn).map(|a| n[a] * kind.nodes_ref()[a][c]).sum();
                    assert!((x - xi[c]).abs() < 1e-14, "{kind:?} linear field");
                }
                let e = 1e-6;
                for a in 0..nn {
                    for k in 0..2 {
                        let (mut p, mut m) = (xi, xi);
                        p[k] += e;
                        m[k] -= e;
                        let fd = (kind.shape(p).0[a] - kind.shape(m).0[a]) / (2.0 * e);
                        assert!((fd - d[a][k]).abs() < 1e-8, "{kind:?} a={a} k={k}");
                    }
                }
            }
            for a in 0..nn {
                let (n, _) = kind.shape(kind.nodes_ref()[a]);
                for b in 0..nn {
                    assert_eq!(n[b], if a == b { 1.0 } else { 0.0 }, "{kind:?} {a} {b}");
                }
            }
        }
    }

    /// The outside measure is 0 inside and on the edges, and the same fraction of the width
    /// for a quad and a triangle; snapping puts a hypotenuse point exactly on it.
    #[test]
    fn outside_and_snap() {
        assert_eq!(FaceKind::Quad4.outside([1.0, -0.3]), 0.0);
        assert!((FaceKind::Quad4.outside([1.02, 0.0]) - 0.02).abs() < 1e-15);
        assert_eq!(FaceKind::Tri3.outside([0.5, 0.5]), 0.0);
        assert!((FaceKind::Tri3.outside([-0.01, 0.5]) - 0.02).abs() < 1e-15);
        for start in [[0.3, 0.7 + 1e-12], [0.8 - 3e-11, 0.2], [0.5 + 1e-12, 0.5]] {
            let mut xi = start;
            FaceKind::Tri6.snap(&mut xi, 1e-9);
            assert_eq!(1.0 - xi[0] - xi[1], 0.0, "{start:?} -> {xi:?}");
            let (n, _) = FaceKind::Tri6.shape(xi);
            assert_eq!([n[0], n[3], n[5]], [0.0; 3], "{xi:?}");
        }
    }
}
