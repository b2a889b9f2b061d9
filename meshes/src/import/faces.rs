//! Orientation of a volume cell in squeal's node order and the check that it is not folded,
//! on [`crate::jacobian`]'s det J (the msh reader's rules): a cell is well oriented when det J
//! at the centroid of its corners is positive, mirrored when negative, degenerate when
//! (nearly) zero; it is folded when det J ≤ 1e-12 × size³ at any node (a linear kind's corners,
//! a quadratic kind's corners and mid-edge nodes, a pyramid's apex from each base corner).

use crate::jacobian::{centroid_jacobian, node_jacobians};
use crate::CellKind;

/// How a cell is oriented.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Orientation {
    Positive,
    Mirrored,
    /// (Near) zero or non-finite Jacobian at the centroid.
    Degenerate(f64),
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

/// The orientation of the cell with nodes `x` (squeal order).
pub(crate) fn orientation(kind: CellKind, x: &[[f64; 3]]) -> Orientation {
    let det = centroid_jacobian(kind, x);
    let s = size(&x[..kind.n_corners()]);
    if !det.is_finite() || det.abs() <= 1e-12 * s.powi(3) {
        Orientation::Degenerate(det)
    } else if det > 0.0 {
        Orientation::Positive
    } else {
        Orientation::Mirrored
    }
}

/// The node (index in the cell) where an oriented cell is folded, with det J there; None
/// when det J > 1e-12 × size³ at every node.
pub fn folded_node(kind: CellKind, x: &[[f64; 3]]) -> Option<(usize, f64)> {
    let tol = 1e-12 * size(&x[..kind.n_corners()]).powi(3);
    let &(a, det) = node_jacobians(kind, x).first()?;
    (det.is_nan() || det <= tol).then_some((a, det))
}
