//! Rotor faces for surface pairing: quad4/quad8 faces given as node ids + coordinates, their
//! shape functions, and the projection of a point onto one face (Newton on the face
//! parametrisation).

use crate::Real;
use serde::{Deserialize, Serialize};

/// The kind of a rotor face: the quad faces of hex8 and hex20 elements.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FaceKind {
    /// Bilinear 4-node quadrilateral (face of a hex8).
    Quad4,
    /// Serendipity 8-node quadrilateral (face of a hex20).
    Quad8,
}

/// Reference coordinates (ξ_a, η_a) of the face nodes: corners counterclockwise, then the
/// mid-sides 0–1, 1–2, 2–3, 3–0 (VTK order, as squeal's meshes store faces).
const NODES_REF: [[Real; 2]; 8] = [
    [-1.0, -1.0],
    [1.0, -1.0],
    [1.0, 1.0],
    [-1.0, 1.0],
    [0.0, -1.0],
    [1.0, 0.0],
    [0.0, 1.0],
    [-1.0, 0.0],
];

impl FaceKind {
    /// Number of nodes (4 or 8).
    pub fn n_nodes(self) -> usize {
        match self {
            FaceKind::Quad4 => 4,
            FaceKind::Quad8 => 8,
        }
    }

    /// Kind from a node count (4 → quad4, 8 → quad8).
    pub fn from_n_nodes(n: usize) -> Option<Self> {
        match n {
            4 => Some(FaceKind::Quad4),
            8 => Some(FaceKind::Quad8),
            _ => None,
        }
    }

    /// Shape functions N_a(ξ, η) and their derivatives ∂N_a/∂ξ, ∂N_a/∂η (first `n_nodes`
    /// entries used). They sum to 1 for every (ξ, η) (partition of unity).
    pub fn shape(self, xi: [Real; 2]) -> ([Real; 8], [[Real; 2]; 8]) {
        let (x, y) = (xi[0], xi[1]);
        let mut n = [0.0; 8];
        let mut d = [[0.0; 2]; 8];
        match self {
            FaceKind::Quad4 => {
                for a in 0..4 {
                    let [xa, ya] = NODES_REF[a];
                    n[a] = 0.25 * (1.0 + xa * x) * (1.0 + ya * y);
                    d[a] = [0.25 * xa * (1.0 + ya * y), 0.25 * ya * (1.0 + xa * x)];
                }
            }
            FaceKind::Quad8 => {
                for a in 0..4 {
                    let [xa, ya] = NODES_REF[a];
                    let (p, q) = (1.0 + xa * x, 1.0 + ya * y);
                    let s = xa * x + ya * y - 1.0;
                    n[a] = 0.25 * p * q * s;
                    d[a] = [0.25 * xa * q * (s + p), 0.25 * ya * p * (s + q)];
                }
                for a in 4..8 {
                    let [xa, ya] = NODES_REF[a];
                    if xa == 0.0 {
                        n[a] = 0.5 * (1.0 - x * x) * (1.0 + ya * y);
                        d[a] = [-x * (1.0 + ya * y), 0.5 * ya * (1.0 - x * x)];
                    } else {
                        n[a] = 0.5 * (1.0 + xa * x) * (1.0 - y * y);
                        d[a] = [0.5 * xa * (1.0 - y * y), -y * (1.0 + xa * x)];
                    }
                }
            }
        }
        (n, d)
    }
}

/// One face of the rotor's friction surface, as the caller knows it (no mesh needed).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RotorFace {
    /// Face id chosen by the caller (reported in errors and stored in the gap), e.g. its index
    /// in the face set.
    pub id: u64,
    /// quad4 or quad8.
    pub kind: FaceKind,
    /// Node ids in the face's order (corners counterclockwise, then the mid-sides 0–1, 1–2,
    /// 2–3, 3–0).
    pub nodes: Vec<u64>,
    /// Node coordinates, same order.
    pub coords: Vec<[Real; 3]>,
}

/// The projection of a point on one face.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Projection {
    /// Face coordinates (ξ, η) of the closest point (after snapping).
    pub xi: [Real; 2],
    /// Distance from the point to x(ξ, η).
    pub distance: Real,
    /// max(|ξ|, |η|) − 1, clamped below at 0: how far outside the face the point projects.
    pub outside: Real,
    /// Newton iterations used.
    pub iterations: usize,
}

/// Face coordinates within this distance of −1, 0 or 1 are set to it, so that a pad node
/// coincident with a rotor node (or on an edge) gets weights exactly 1 and 0.
pub const SNAP: Real = 1e-9;

fn sub(a: [Real; 3], b: [Real; 3]) -> [Real; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [Real; 3], b: [Real; 3]) -> Real {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl RotorFace {
    /// x(ξ, η) and the tangents ∂x/∂ξ, ∂x/∂η.
    pub(crate) fn point(&self, xi: [Real; 2]) -> ([Real; 3], [[Real; 3]; 2]) {
        let (n, d) = self.kind.shape(xi);
        let mut x = [0.0; 3];
        let mut t = [[0.0; 3]; 2];
        for (a, c) in self.coords.iter().enumerate().take(self.kind.n_nodes()) {
            for k in 0..3 {
                x[k] += n[a] * c[k];
                t[0][k] += d[a][0] * c[k];
                t[1][k] += d[a][1] * c[k];
            }
        }
        (x, t)
    }

    /// Mean length of the face's corner-to-corner edges.
    pub(crate) fn edge_length(&self) -> Real {
        (0..4)
            .map(|a| {
                let e = sub(self.coords[(a + 1) % 4], self.coords[a]);
                dot(e, e).sqrt()
            })
            .sum::<Real>()
            / 4.0
    }

    /// Projects `p` on the face: Gauss–Newton on min ½|x(ξ) − p|² from the closest of the nine
    /// points ξ, η ∈ {−1, 0, 1}, steps limited to 0.5 in each coordinate, until the step is
    /// below 1e-13 (at most 50 iterations). None when it does not converge or the tangents
    /// are degenerate.
    ///
    /// # Derivation
    /// The stationarity conditions are r_i = (x(ξ) − p)·∂x/∂ξ_i = 0. Gauss–Newton drops the
    /// curvature term (x − p)·∂²x/∂ξ_i∂ξ_j of the Hessian: on a flat face that term vanishes
    /// (x − p is normal to the face, the second derivatives lie in it), so the iteration is
    /// Newton's; on a curved face it converges linearly at a rate proportional to the
    /// distance times the curvature, small for a point on the surface.
    pub(crate) fn project(&self, p: [Real; 3]) -> Option<Projection> {
        let mut xi = [0.0, 0.0];
        let mut best = Real::INFINITY;
        for a in [-1.0, 0.0, 1.0] {
            for b in [-1.0, 0.0, 1.0] {
                let (x, _) = self.point([a, b]);
                let r = sub(x, p);
                let d = dot(r, r);
                if d < best {
                    best = d;
                    xi = [a, b];
                }
            }
        }
        let mut converged = false;
        let mut iterations = 0;
        for it in 1..=50 {
            iterations = it;
            let (x, t) = self.point(xi);
            let r = sub(x, p);
            let g = [dot(r, t[0]), dot(r, t[1])];
            let h = [
                [dot(t[0], t[0]), dot(t[0], t[1])],
                [dot(t[1], t[0]), dot(t[1], t[1])],
            ];
            let det = h[0][0] * h[1][1] - h[0][1] * h[1][0];
            if !(det.is_finite() && det > 1e-14 * (h[0][0] * h[1][1])) || h[0][0] <= 0.0 {
                return None;
            }
            let mut dx = [
                -(h[1][1] * g[0] - h[0][1] * g[1]) / det,
                -(h[0][0] * g[1] - h[1][0] * g[0]) / det,
            ];
            let m = dx[0].abs().max(dx[1].abs());
            if m > 0.5 {
                dx = [0.5 * dx[0] / m, 0.5 * dx[1] / m];
            }
            xi = [xi[0] + dx[0], xi[1] + dx[1]];
            if !(xi[0].is_finite() && xi[1].is_finite()) || xi[0].abs() > 4.0 || xi[1].abs() > 4.0 {
                return None;
            }
            if m <= 1e-13 {
                converged = true;
                break;
            }
        }
        if !converged {
            return None;
        }
        for c in &mut xi {
            for s in [-1.0, 0.0, 1.0] {
                if (*c - s).abs() <= SNAP {
                    *c = s;
                }
            }
        }
        let (x, _) = self.point(xi);
        let r = sub(x, p);
        Some(Projection {
            xi,
            distance: dot(r, r).sqrt(),
            outside: (xi[0].abs().max(xi[1].abs()) - 1.0).max(0.0),
            iterations,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn face(kind: FaceKind, f: impl Fn([Real; 2]) -> [Real; 3]) -> RotorFace {
        let n = kind.n_nodes();
        RotorFace {
            id: 7,
            kind,
            nodes: (0..n as u64).collect(),
            coords: NODES_REF[..n].iter().map(|&r| f(r)).collect(),
        }
    }

    /// Shape functions: partition of unity, Kronecker property at the nodes, derivatives
    /// against central differences (the definitions of the bilinear and serendipity quads).
    #[test]
    fn shape_functions() {
        for kind in [FaceKind::Quad4, FaceKind::Quad8] {
            let nn = kind.n_nodes();
            for xi in [[0.3, -0.7], [-0.9, 0.1], [1.2, 0.4]] {
                let (n, d) = kind.shape(xi);
                assert!((n[..nn].iter().sum::<Real>() - 1.0).abs() < 1e-14);
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
                let (n, _) = kind.shape(NODES_REF[a]);
                for b in 0..nn {
                    assert_eq!(n[b], if a == b { 1.0 } else { 0.0 }, "{kind:?} {a} {b}");
                }
            }
        }
    }

    /// A point placed at known (ξ, η) on a distorted (quad4) and a curved (quad8) face, and
    /// lifted off it along the normal by d, projects back to (ξ, η) at distance d.
    #[test]
    fn projection_recovers_face_coordinates() {
        let warp = |r: [Real; 2]| {
            [
                2.0 + 0.6 * r[0] + 0.1 * r[1] + 0.05 * r[0] * r[1],
                1.0 + 0.5 * r[1] - 0.08 * r[0],
                0.0,
            ]
        };
        let bent = |r: [Real; 2]| [r[0], r[1], 0.05 * r[0] * r[0]];
        for (kind, f) in [
            (FaceKind::Quad4, &warp as &dyn Fn([Real; 2]) -> [Real; 3]),
            (FaceKind::Quad8, &bent),
        ] {
            let fc = face(kind, f);
            for xi in [[0.25, -0.6], [-0.95, 0.9], [0.0, 0.0]] {
                let (x, t) = fc.point(xi);
                let nrm = [
                    t[0][1] * t[1][2] - t[0][2] * t[1][1],
                    t[0][2] * t[1][0] - t[0][0] * t[1][2],
                    t[0][0] * t[1][1] - t[0][1] * t[1][0],
                ];
                let l = dot(nrm, nrm).sqrt();
                let d = 1e-3;
                let p = [0, 1, 2].map(|k| x[k] + d * nrm[k] / l);
                let pr = fc.project(p).expect("converges");
                assert!((pr.xi[0] - xi[0]).abs() < 1e-10, "{kind:?} {:?}", pr.xi);
                assert!((pr.xi[1] - xi[1]).abs() < 1e-10, "{kind:?} {:?}", pr.xi);
                assert!((pr.distance - d).abs() < 1e-10);
                assert_eq!(pr.outside, 0.0);
            }
        }
    }

    /// A point on a corner node snaps to the corner exactly.
    #[test]
    fn corner_snaps() {
        let fc = face(FaceKind::Quad8, |r| {
            [3.0 * r[0] + 0.2 * r[1], 2.0 * r[1], 0.0]
        });
        let pr = fc.project(fc.coords[2]).unwrap();
        assert_eq!(pr.xi, [1.0, 1.0]);
        let pr = fc.project(fc.coords[5]).unwrap();
        assert_eq!(pr.xi, [1.0, 0.0]);
        let (n, _) = FaceKind::Quad8.shape(pr.xi);
        assert_eq!(n, [0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
    }
}
