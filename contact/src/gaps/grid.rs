//! A uniform spatial hash for coincident-node queries (O(n) matching instead of O(n²)).

use crate::Real;
use std::collections::HashMap;

/// Points bucketed in cubic cells of side `cell`.
pub(crate) struct Grid {
    cell: Real,
    buckets: HashMap<[i64; 3], Vec<usize>>,
}

impl Grid {
    fn key(&self, x: &[Real; 3]) -> [i64; 3] {
        [
            (x[0] / self.cell).floor() as i64,
            (x[1] / self.cell).floor() as i64,
            (x[2] / self.cell).floor() as i64,
        ]
    }

    /// Buckets `points` (finite coordinates) in cells of side `cell` > 0.
    pub(crate) fn new(points: &[[Real; 3]], cell: Real) -> Self {
        let mut g = Grid {
            cell,
            buckets: HashMap::with_capacity(points.len()),
        };
        for (i, p) in points.iter().enumerate() {
            let k = g.key(p);
            g.buckets.entry(k).or_default().push(i);
        }
        g
    }

    /// Indices of the points within distance `tol` ≤ `cell` of `x`, in increasing order.
    pub(crate) fn within(&self, points: &[[Real; 3]], x: &[Real; 3], tol: Real) -> Vec<usize> {
        let k = self.key(x);
        let mut out = Vec::new();
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(b) = self.buckets.get(&[k[0] + dx, k[1] + dy, k[2] + dz]) {
                        for &i in b {
                            let p = &points[i];
                            let d2 = (p[0] - x[0]).powi(2)
                                + (p[1] - x[1]).powi(2)
                                + (p[2] - x[2]).powi(2);
                            if d2 <= tol * tol {
                                out.push(i);
                            }
                        }
                    }
                }
            }
        }
        out.sort_unstable();
        out
    }
}

/// Boxes bucketed in every cubic cell of side `cell` they overlap.
pub(crate) struct BoxGrid {
    cell: Real,
    buckets: HashMap<[i64; 3], Vec<usize>>,
}

impl BoxGrid {
    fn key(&self, x: &[Real; 3]) -> [i64; 3] {
        x.map(|v| (v / self.cell).floor() as i64)
    }

    /// Indices of the boxes (lo, hi) (finite) containing `x`'s cell, in increasing order.
    pub(crate) fn boxes_at(&self, x: &[Real; 3]) -> Vec<usize> {
        self.buckets.get(&self.key(x)).cloned().unwrap_or_default()
    }

    /// Indices of the boxes sharing a cell with the box (lo, hi) (finite), in increasing
    /// order (a superset of those overlapping it).
    pub(crate) fn boxes_near(&self, lo: &[Real; 3], hi: &[Real; 3]) -> Vec<usize> {
        let (a, b) = (self.key(lo), self.key(hi));
        let mut out = Vec::new();
        for x in a[0]..=b[0] {
            for y in a[1]..=b[1] {
                for z in a[2]..=b[2] {
                    if let Some(v) = self.buckets.get(&[x, y, z]) {
                        out.extend_from_slice(v);
                    }
                }
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }
}

impl Grid {
    /// Buckets boxes `(lo, hi)` (finite) in the cells of side `cell` > 0 they overlap.
    pub(crate) fn from_boxes(boxes: &[([Real; 3], [Real; 3])], cell: Real) -> BoxGrid {
        let mut g = BoxGrid {
            cell,
            buckets: HashMap::new(),
        };
        for (i, (lo, hi)) in boxes.iter().enumerate() {
            let (a, b) = (g.key(lo), g.key(hi));
            for x in a[0]..=b[0] {
                for y in a[1]..=b[1] {
                    for z in a[2]..=b[2] {
                        g.buckets.entry([x, y, z]).or_default().push(i);
                    }
                }
            }
        }
        g
    }
}
