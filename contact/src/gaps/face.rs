//! Faces for surface pairing: quad4/quad8/tri3/tri6 faces given as node ids + coordinates,
//! the projection of a point onto one face (Newton on the face parametrisation), and the
//! point where a line meets a face (the mortar pairing's map from its plane to the faces).

pub use super::shape::FaceKind;
use super::vec3::{cross, dot, sub};
use crate::Real;
use serde::{Deserialize, Serialize};

/// One face of a contact surface (the rotor's, or the pad's for the mortar pairing), as the
/// caller knows it (no mesh needed).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RotorFace {
    /// Face id chosen by the caller (reported in errors and stored in the gap), e.g. its index
    /// in the face set.
    pub id: u64,
    /// quad4, quad8, tri3 or tri6.
    pub kind: FaceKind,
    /// Node ids in the face's order (corners counterclockwise, then the mid-sides 0–1, 1–2,
    /// …, as gmsh and VTK number them).
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
    /// How far outside the face the point projects, 0 inside ([`FaceKind::outside`]: on a
    /// quad max(|ξ|, |η|) − 1).
    pub outside: Real,
    /// Newton iterations used.
    pub iterations: usize,
}

/// Face coordinates within this distance of a node coordinate (−1, 0, 1 on quads; 0, ½, 1 on
/// triangles) are set to it, so that a pad node coincident with a rotor node (or on an edge)
/// gets weights exactly 1 and 0.
pub const SNAP: Real = 1e-9;

impl RotorFace {
    /// x(ξ, η) and the tangents ∂x/∂ξ, ∂x/∂η.
    pub(crate) fn point(&self, xi: [Real; 2]) -> ([Real; 3], [[Real; 3]; 2]) {
        let (r, t) = self.relative(xi);
        let c = self.coords[0];
        ([0, 1, 2].map(|k| c[k] + r[k]), t)
    }

    /// x(ξ, η) − x_0 (relative to the first node, without the cancellation of absolute
    /// coordinates far from the origin) and the tangents.
    fn relative(&self, xi: [Real; 2]) -> ([Real; 3], [[Real; 3]; 2]) {
        let (n, d) = self.kind.shape(xi);
        let c0 = self.coords[0];
        let mut x = [0.0; 3];
        let mut t = [[0.0; 3]; 2];
        for (a, c) in self.coords.iter().enumerate().take(self.kind.n_nodes()) {
            for k in 0..3 {
                let ck = c[k] - c0[k];
                x[k] += n[a] * ck;
                t[0][k] += d[a][0] * ck;
                t[1][k] += d[a][1] * ck;
            }
        }
        (x, t)
    }

    /// Mean length of the face's corner-to-corner edges.
    pub(crate) fn edge_length(&self) -> Real {
        let nc = self.kind.n_corners();
        (0..nc)
            .map(|a| {
                let e = sub(self.coords[(a + 1) % nc], self.coords[a]);
                dot(e, e).sqrt()
            })
            .sum::<Real>()
            / nc as Real
    }

    /// Projects `p` on the face: Gauss–Newton on min ½|x(ξ) − p|² from the closest of the
    /// nodes and the centre, steps limited to 0.5 in each coordinate, until the step is below
    /// 1e-13 (at most 50 iterations). None when it does not converge or the tangents are
    /// degenerate.
    ///
    /// # Derivation
    /// The stationarity conditions are r_i = (x(ξ) − p)·∂x/∂ξ_i = 0. Gauss–Newton drops the
    /// curvature term (x − p)·∂²x/∂ξ_i∂ξ_j of the Hessian: on a flat face that term vanishes
    /// (x − p is normal to the face, the second derivatives lie in it), so the iteration is
    /// Newton's; on a curved face it converges linearly at a rate proportional to the
    /// distance times the curvature, small for a point on the surface.
    pub(crate) fn project(&self, p: [Real; 3]) -> Option<Projection> {
        // Relative to the first node (no cancellation of far-off absolute coordinates).
        let p = sub(p, self.coords[0]);
        let mut xi = self.kind.center_ref();
        let mut best = Real::INFINITY;
        let starts = self
            .kind
            .nodes_ref()
            .iter()
            .copied()
            .chain([self.kind.center_ref()]);
        // The quads' nine-point lattice (corners, mid-sides, centre) also for quad4 faces.
        let lattice = (!self.kind.is_triangle())
            .then_some(super::shape::QUAD_REF)
            .into_iter()
            .flatten();
        for s in starts.chain(lattice) {
            let (x, _) = self.relative(s);
            let r = sub(x, p);
            let d = dot(r, r);
            if d < best {
                best = d;
                xi = s;
            }
        }
        let mut converged = false;
        let mut iterations = 0;
        for it in 1..=50 {
            iterations = it;
            let (x, t) = self.relative(xi);
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
        self.kind.snap(&mut xi, SNAP);
        let (x, _) = self.relative(xi);
        let r = sub(x, p);
        Some(Projection {
            xi,
            distance: dot(r, r).sqrt(),
            outside: self.kind.outside(xi),
            iterations,
        })
    }

    /// The face coordinates where the line q + t·dir meets the face, by Newton on
    /// x(ξ, η) − t·dir = q (three unknowns) from `start` (and, failing that, from the face's
    /// centre), until the step is below 1e-14 in (ξ, η) (at most 30 iterations), with t.
    /// None when it does not converge or the line is parallel to the face. On a face x(ξ)
    /// affine in ξ one step is exact.
    pub(crate) fn along(
        &self,
        q: [Real; 3],
        dir: [Real; 3],
        start: [Real; 2],
    ) -> Option<([Real; 2], Real)> {
        let qr = sub(q, self.coords[0]);
        self.along_from(qr, dir, start)
            .or_else(|| self.along_from(qr, dir, self.kind.center_ref()))
    }

    fn along_from(
        &self,
        qr: [Real; 3],
        dir: [Real; 3],
        start: [Real; 2],
    ) -> Option<([Real; 2], Real)> {
        let mut xi = start;
        let mut t = 0.0;
        for _ in 0..30 {
            let (x, tg) = self.relative(xi);
            // Residual r = x(ξ) − t·dir − q; Jacobian columns t_ξ, t_η, −dir.
            let r = [0, 1, 2].map(|k| x[k] - t * dir[k] - qr[k]);
            let c = [tg[0], tg[1], dir.map(|v| -v)];
            let det = dot(c[0], cross(c[1], c[2]));
            let scale = dot(c[0], c[0]).sqrt() * dot(c[1], c[1]).sqrt() * dot(dir, dir).sqrt();
            if !(det.is_finite() && det.abs() > 1e-12 * scale) {
                return None;
            }
            // Cramer's rule for c·Δ = −r.
            let mr = r.map(|v| -v);
            let d0 = dot(mr, cross(c[1], c[2])) / det;
            let d1 = dot(c[0], cross(mr, c[2])) / det;
            let d2 = dot(c[0], cross(c[1], mr)) / det;
            xi = [xi[0] + d0, xi[1] + d1];
            t += d2;
            if !(xi[0].is_finite() && xi[1].is_finite()) || xi[0].abs() > 4.0 || xi[1].abs() > 4.0 {
                return None;
            }
            if d0.abs().max(d1.abs()) <= 1e-14 {
                return Some((xi, t));
            }
        }
        None
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
            coords: kind.nodes_ref().iter().map(|&r| f(r)).collect(),
        }
    }

    /// A point placed at known (ξ, η) on a distorted (quad4, tri3) and a curved (quad8, tri6)
    /// face, and lifted off it along the normal by d, projects back to (ξ, η) at distance d;
    /// the line through it along the normal meets the face at (ξ, η) too.
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
        type F<'a> = &'a dyn Fn([Real; 2]) -> [Real; 3];
        let cases: [(FaceKind, F, [[Real; 2]; 3]); 4] = [
            (
                FaceKind::Quad4,
                &warp,
                [[0.25, -0.6], [-0.95, 0.9], [0.0, 0.0]],
            ),
            (
                FaceKind::Quad8,
                &bent,
                [[0.25, -0.6], [-0.95, 0.9], [0.0, 0.0]],
            ),
            (
                FaceKind::Tri3,
                &warp,
                [[0.25, 0.6], [0.05, 0.9], [0.3, 0.3]],
            ),
            (
                FaceKind::Tri6,
                &bent,
                [[0.25, 0.6], [0.05, 0.9], [0.3, 0.3]],
            ),
        ];
        for (kind, f, points) in cases {
            let fc = face(kind, f);
            for xi in points {
                let (x, t) = fc.point(xi);
                let nrm = cross(t[0], t[1]);
                let l = dot(nrm, nrm).sqrt();
                let d = 1e-3;
                let p = [0, 1, 2].map(|k| x[k] + d * nrm[k] / l);
                let pr = fc.project(p).expect("converges");
                assert!((pr.xi[0] - xi[0]).abs() < 1e-10, "{kind:?} {:?}", pr.xi);
                assert!((pr.xi[1] - xi[1]).abs() < 1e-10, "{kind:?} {:?}", pr.xi);
                assert!((pr.distance - d).abs() < 1e-10);
                assert_eq!(pr.outside, 0.0);
                let (xl, tl) = fc.along(p, nrm, kind.center_ref()).expect("meets the face");
                assert!((xl[0] - xi[0]).abs() < 1e-12 && (xl[1] - xi[1]).abs() < 1e-12);
                assert!((tl * l + d).abs() < 1e-12, "{tl}");
            }
        }
    }

    /// A point on a corner or a mid-side node snaps to it exactly.
    #[test]
    fn nodes_snap() {
        let fc = face(FaceKind::Quad8, |r| {
            [3.0 * r[0] + 0.2 * r[1], 2.0 * r[1], 0.0]
        });
        let pr = fc.project(fc.coords[2]).unwrap();
        assert_eq!(pr.xi, [1.0, 1.0]);
        let pr = fc.project(fc.coords[5]).unwrap();
        assert_eq!(pr.xi, [1.0, 0.0]);
        let (n, _) = FaceKind::Quad8.shape(pr.xi);
        assert_eq!(n, [0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
        let tri = face(FaceKind::Tri6, |r| {
            [
                1.0 + 2.0 * r[0] + 0.3 * r[1],
                0.5 + 1.7 * r[1] - 0.2 * r[0],
                0.1,
            ]
        });
        for a in 0..6 {
            let pr = tri.project(tri.coords[a]).unwrap();
            let (n, _) = FaceKind::Tri6.shape(pr.xi);
            for b in 0..6 {
                assert_eq!(
                    n[b],
                    if a == b { 1.0 } else { 0.0 },
                    "node {a}: {:?}",
                    pr.xi
                );
            }
        }
    }
}
