//! Orientation of a volume cell in squeal's node order, its mirror permutation, and the
//! check that it is not folded at a node.
//!
//! # Reference
//! A cell is well oriented when det ∂x/∂ξ > 0 in the natural coordinates of [`crate::mesh`].
//! At the centroid of the corners' linear map: tetrahedron det[x1−x0, x2−x0, x3−x0]; wedge
//! (ξ, η at 1/3, ζ = 0) det[((x1−x0)+(x4−x3))/2, ((x2−x0)+(x5−x3))/2, (x̄_top − x̄_bottom)/2];
//! pyramid and hexahedron from their corner averages. Mirroring swaps the two triangles of a
//! wedge, reverses a tetrahedron's 1–2 or a pyramid's base, and swaps a hexahedron's bottom
//! and top, with the mid-edge nodes following their edges.

use crate::jacobian::hex_node_jacobians;
use crate::query::hex_centroid_jacobian;
use crate::CellKind;

/// How a cell is oriented.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Orientation {
    Positive,
    Mirrored,
    /// (Near) zero or non-finite Jacobian at the centroid.
    Degenerate(f64),
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn det3(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}

fn mean(x: &[[f64; 3]]) -> [f64; 3] {
    let n = x.len() as f64;
    [0, 1, 2].map(|k| x.iter().map(|p| p[k]).sum::<f64>() / n)
}

/// Largest corner-to-corner extent (max norm).
fn size(x: &[[f64; 3]]) -> f64 {
    let mut s: f64 = 0.0;
    for a in x {
        for b in x {
            for k in 0..3 {
                s = s.max((a[k] - b[k]).abs());
            }
        }
    }
    s
}

/// det J at the centroid of the corners' linear map.
fn centroid_det(kind: CellKind, x: &[[f64; 3]]) -> f64 {
    match kind.linear() {
        CellKind::Hex8 => {
            let c: [[f64; 3]; 8] = std::array::from_fn(|k| x[k]);
            hex_centroid_jacobian(&c)
        }
        CellKind::Tet4 => det3(sub(x[1], x[0]), sub(x[2], x[0]), sub(x[3], x[0])),
        CellKind::Wedge6 => {
            let half = |a: [f64; 3], b: [f64; 3]| [0, 1, 2].map(|k| (a[k] + b[k]) / 2.0);
            det3(
                half(sub(x[1], x[0]), sub(x[4], x[3])),
                half(sub(x[2], x[0]), sub(x[5], x[3])),
                sub(mean(&x[3..6]), mean(&x[0..3])).map(|v| v / 2.0),
            )
        }
        CellKind::Pyramid5 => {
            // Base bilinear map at its centre, height towards the apex.
            let dxi = [0, 1, 2].map(|k| (x[1][k] + x[2][k] - x[0][k] - x[3][k]) / 4.0);
            let deta = [0, 1, 2].map(|k| (x[2][k] + x[3][k] - x[0][k] - x[1][k]) / 4.0);
            det3(dxi, deta, sub(x[4], mean(&x[0..4])))
        }
        _ => f64::NAN,
    }
}

/// The orientation of the cell with nodes `x` (squeal order).
pub(crate) fn orientation(kind: CellKind, x: &[[f64; 3]]) -> Orientation {
    let nc = kind.n_corners();
    let det = centroid_det(kind, x);
    let s = size(&x[..nc]);
    if !det.is_finite() || det.abs() <= 1e-12 * s.powi(3) {
        Orientation::Degenerate(det)
    } else if det > 0.0 {
        Orientation::Positive
    } else {
        Orientation::Mirrored
    }
}

/// The permutation that mirrors a cell: new node k = old node `mirror(kind)[k]`.
pub(crate) fn mirror(kind: CellKind) -> &'static [usize] {
    match kind {
        CellKind::Hex8 => &[4, 5, 6, 7, 0, 1, 2, 3],
        CellKind::Hex20 => &[
            4, 5, 6, 7, 0, 1, 2, 3, 12, 13, 14, 15, 8, 9, 10, 11, 16, 17, 18, 19,
        ],
        CellKind::Tet4 => &[0, 2, 1, 3],
        CellKind::Tet10 => &[0, 2, 1, 3, 6, 5, 4, 7, 9, 8],
        CellKind::Wedge6 => &[3, 4, 5, 0, 1, 2],
        CellKind::Wedge15 => &[3, 4, 5, 0, 1, 2, 9, 10, 11, 6, 7, 8, 12, 13, 14],
        CellKind::Pyramid5 => &[0, 3, 2, 1, 4],
        CellKind::Pyramid13 => &[0, 3, 2, 1, 4, 8, 7, 6, 5, 9, 12, 11, 10],
        CellKind::Quad4 => &[0, 3, 2, 1],
        CellKind::Quad8 => &[0, 3, 2, 1, 7, 6, 5, 4],
        CellKind::Tri3 => &[0, 2, 1],
        CellKind::Tri6 => &[0, 2, 1, 5, 4, 3],
    }
}

/// The node (index in the cell) where an oriented cell is folded (det J ≤ 1e-12 × size³
/// there), with that det J; None when det J > 0 at every node checked (every node of a
/// hexahedron, the corners of the other kinds, where the corners' edges must form a
/// right-handed frame). A mirrored cell is folded everywhere.
pub fn folded_node(kind: CellKind, x: &[[f64; 3]]) -> Option<(usize, f64)> {
    let nc = kind.n_corners();
    let tol = 1e-12 * size(&x[..nc]).powi(3);
    let worst = match kind.linear() {
        CellKind::Hex8 => hex_node_jacobians(&x[..kind.n_nodes()]).first().copied(),
        CellKind::Tet4 => Some((0, centroid_det(CellKind::Tet4, x))),
        CellKind::Wedge6 => (0..6)
            .map(|a| {
                // At corner a: the two triangle edges from it and the vertical edge.
                let (t, o) = if a < 3 { (0, 3) } else { (3, 0) };
                let i = a - t;
                let e1 = sub(x[t + (i + 1) % 3], x[a]);
                let e2 = sub(x[t + (i + 2) % 3], x[a]);
                let up = sub(x[o + i], x[a]);
                let d = det3(e1, e2, up);
                (a, if a < 3 { d } else { -d })
            })
            .min_by(|p, q| p.1.total_cmp(&q.1)),
        CellKind::Pyramid5 => (0..4)
            .map(|a| {
                let e1 = sub(x[(a + 1) % 4], x[a]);
                let e2 = sub(x[(a + 3) % 4], x[a]);
                (a, det3(e1, e2, sub(x[4], x[a])))
            })
            .min_by(|p, q| p.1.total_cmp(&q.1)),
        _ => None,
    }?;
    (worst.1.is_nan() || worst.1 <= tol).then_some(worst)
}
