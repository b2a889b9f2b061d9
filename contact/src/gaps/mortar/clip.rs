//! The mortar segments' geometry: the plane of a pad face, the faces' shadows on it as
//! convex polygons, and Sutherland–Hodgman clipping.

use crate::gaps::face::RotorFace;
use crate::gaps::vec3::{cross, dot, norm, sub};
use crate::Real;

/// The plane of a pad face: centre, unit normal (from the face's node order), tangents.
#[derive(Debug, Clone)]
pub(crate) struct Plane {
    pub c: [Real; 3],
    pub n: [Real; 3],
    t1: [Real; 3],
    t2: [Real; 3],
}

impl Plane {
    /// The plane through the corners' mean with the normal of the corner polygon (the
    /// diagonals' cross product on quads, the edges' on triangles). None when degenerate.
    pub fn of(f: &RotorFace) -> Option<Plane> {
        let nc = f.kind.n_corners();
        let x = &f.coords;
        let c = [0, 1, 2].map(|k| x[..nc].iter().map(|p| p[k]).sum::<Real>() / nc as Real);
        let nv = if nc == 4 {
            cross(sub(x[2], x[0]), sub(x[3], x[1]))
        } else {
            cross(sub(x[1], x[0]), sub(x[2], x[0]))
        };
        let l = norm(nv);
        if !(l.is_finite() && l > 0.0) {
            return None;
        }
        let n = nv.map(|v| v / l);
        let e = sub(x[1], x[0]);
        let e = sub(e, n.map(|v| v * dot(e, n)));
        let le = norm(e);
        if le.is_nan() || le <= 0.0 {
            return None;
        }
        let t1 = e.map(|v| v / le);
        let t2 = cross(n, t1);
        Some(Plane { c, n, t1, t2 })
    }

    /// In-plane coordinates of the orthogonal projection of `x`.
    pub fn to2(&self, x: [Real; 3]) -> [Real; 2] {
        let d = sub(x, self.c);
        [dot(d, self.t1), dot(d, self.t2)]
    }

    /// The point of the plane with in-plane coordinates `p`.
    pub fn to3(&self, p: [Real; 2]) -> [Real; 3] {
        [0, 1, 2].map(|k| self.c[k] + p[0] * self.t1[k] + p[1] * self.t2[k])
    }

    /// Signed distance of `x` from the plane.
    pub fn height(&self, x: [Real; 3]) -> Real {
        dot(sub(x, self.c), self.n)
    }

    /// The shadow of face `f` on the plane as a counterclockwise polygon: its boundary
    /// (corners, with the mid-side nodes between them on quadratic faces). On a flat face
    /// with straight edges this is the face exactly; on a curved face the edges are replaced
    /// by chords through the mid-side nodes (an error of the order of the edges' sagitta,
    /// which falls with the mesh size), and the polygon may be slightly non-convex.
    pub fn shadow(&self, f: &RotorFace) -> Vec<[Real; 2]> {
        let mut p: Vec<[Real; 2]> = f
            .kind
            .boundary()
            .iter()
            .map(|&a| self.to2(f.coords[a]))
            .collect();
        if area2(&p) < 0.0 {
            p.reverse();
        }
        p
    }

    /// [`Plane::shadow`] as signed convex counterclockwise pieces (clipping polygons must be
    /// convex): the shadow itself when convex; else (a curved quadratic face whose edge bulges
    /// inward) the convex polygon with every reflex vertex cut off by its neighbours' chord
    /// (+1), minus the notch triangles cut off (−1): integrals over the pieces, signed, are
    /// the shadow's (the integrands are defined a little beyond the faces). When that does
    /// not give a convex polygon, the fan of triangles from the face's centre (all +1).
    pub fn pieces(&self, f: &RotorFace) -> Vec<(Vec<[Real; 2]>, Real)> {
        let p = self.shadow(f);
        if is_convex(&p) {
            return vec![(p, 1.0)];
        }
        let mut q = p.clone();
        let mut notches = Vec::new();
        while q.len() > 3 && !is_convex(&q) {
            let n = q.len();
            let Some(i) = (0..n).find(|&i| turn(q[(i + n - 1) % n], q[i], q[(i + 1) % n]) < 0.0)
            else {
                break;
            };
            let (a, m, b) = (q[(i + n - 1) % n], q[i], q[(i + 1) % n]);
            notches.push((vec![a, b, m], -1.0));
            q.remove(i);
        }
        if is_convex(&q) && area2(&q) > 0.0 {
            let mut out = vec![(q, 1.0)];
            out.extend(notches);
            return out;
        }
        let (xc, _) = f.point(f.kind.center_ref());
        let c = self.to2(xc);
        (0..p.len())
            .map(|i| (vec![c, p[i], p[(i + 1) % p.len()]], 1.0))
            .filter(|(t, _)| area2(t) > 0.0)
            .collect()
    }
}

/// z of (b − a) × (c − b): > 0 for a left (counterclockwise) turn at b.
fn turn(a: [Real; 2], b: [Real; 2], c: [Real; 2]) -> Real {
    (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0])
}

/// Signed area of a polygon.
pub(crate) fn area2(p: &[[Real; 2]]) -> Real {
    let n = p.len();
    (0..n)
        .map(|i| {
            let (a, b) = (p[i], p[(i + 1) % n]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum::<Real>()
        * 0.5
}

/// Counterclockwise convexity, collinear vertices allowed (to 1e-12 of the edge lengths).
fn is_convex(p: &[[Real; 2]]) -> bool {
    let n = p.len();
    (0..n).all(|i| {
        let (a, b, c) = (p[i], p[(i + 1) % n], p[(i + 2) % n]);
        let scale = (b[0] - a[0]).hypot(b[1] - a[1]) * (c[0] - b[0]).hypot(c[1] - b[1]);
        turn(a, b, c) >= -1e-12 * scale
    })
}

/// Sutherland–Hodgman: `subject` clipped by the convex counterclockwise polygon `clip`. A
/// non-convex subject gives its intersection as one polygon, possibly with zero-width
/// bridges along the clip's edges (they add nothing to a signed-area integral).
pub(crate) fn clip_polygon(subject: &[[Real; 2]], clip: &[[Real; 2]]) -> Vec<[Real; 2]> {
    let mut out = subject.to_vec();
    let n = clip.len();
    for i in 0..n {
        if out.is_empty() {
            break;
        }
        let (a, b) = (clip[i], clip[(i + 1) % n]);
        if a == b {
            continue;
        }
        let side = |p: [Real; 2]| (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
        let input = std::mem::take(&mut out);
        let m = input.len();
        for j in 0..m {
            let (p, q) = (input[j], input[(j + 1) % m]);
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                out.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                let t = sp / (sp - sq);
                out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two unit squares offset by (0.5, 0.25) overlap in a 0.5 × 0.75 rectangle; a square
    /// clipped by itself is itself; disjoint squares give nothing.
    #[test]
    fn clipping() {
        let sq = |x: Real, y: Real| vec![[x, y], [x + 1.0, y], [x + 1.0, y + 1.0], [x, y + 1.0]];
        let a = clip_polygon(&sq(0.5, 0.25), &sq(0.0, 0.0));
        assert!((area2(&a) - 0.375).abs() < 1e-15);
        assert!((area2(&clip_polygon(&sq(0.0, 0.0), &sq(0.0, 0.0))) - 1.0).abs() < 1e-15);
        assert!(area2(&clip_polygon(&sq(2.0, 0.0), &sq(0.0, 0.0))).abs() < 1e-15);
    }
}
