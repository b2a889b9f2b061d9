//! Recursive inertial bisection with minimum-cover vertex separators.

use super::graph::NodeGraph;
use super::leaf::order_leaf;
use super::separator::{min_cover_separator, Marks};
use super::{DofPermutation, NestedDissectionOptions, NestedDissectionStats};
use crate::{FeError, Real};
use faer::sparse::SymbolicSparseColMatRef;
use nalgebra::{Matrix3, SymmetricEigen};
use std::time::Instant;

/// Nested-dissection ordering of the DOFs of a symmetric sparse matrix.
///
/// `pattern` is the n × n pattern (either or both triangles), `dof_coords[i]` the point of
/// DOF i. Consecutive DOFs at the same point form one graph node and stay consecutive in the
/// ordering. Node sets are split at the median of their projection on the principal axis of
/// inertia; the separator is a minimum vertex cover of the cut edges; halves come first, the
/// separator last; sets of at most `opts.leaf_nodes` nodes are ordered by AMD.
///
/// Errors: invalid options, `dof_coords.len() != n`, non-finite coordinates.
pub fn nested_dissection(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    dof_coords: &[[Real; 3]],
    opts: &NestedDissectionOptions,
) -> Result<(DofPermutation, NestedDissectionStats), FeError> {
    let t0 = Instant::now();
    opts.validate()?;
    let n = pattern.ncols();
    if pattern.nrows() != n || dof_coords.len() != n {
        return Err(FeError::Dimension {
            what: "DOF coordinates for nested dissection",
            got: dof_coords.len(),
            expected: n,
        });
    }
    if let Some(i) = dof_coords
        .iter()
        .position(|p| p.iter().any(|c| !c.is_finite()))
    {
        return Err(FeError::NonFinite {
            what: format!("coordinates of DOF {i} ({:?})", dof_coords[i]),
        });
    }
    let g = NodeGraph::new(pattern, dof_coords);
    let mut d = Dissection {
        g: &g,
        opts,
        marks: Marks::new(g.len()),
        order: Vec::with_capacity(g.len()),
        next_id: 0,
        stats: NestedDissectionStats {
            n_nodes: g.len(),
            ..Default::default()
        },
    };
    d.dissect((0..g.len()).collect(), 0);
    let mut stats = d.stats;
    let mut perm = Vec::with_capacity(n);
    for &v in &d.order {
        perm.extend(g.dof_ptr[v]..g.dof_ptr[v + 1]);
    }
    let perm = DofPermutation::from_order(perm)?;
    stats.ordering_s = t0.elapsed().as_secs_f64();
    Ok((perm, stats))
}

pub(super) struct Dissection<'a> {
    pub(super) g: &'a NodeGraph,
    pub(super) opts: &'a NestedDissectionOptions,
    pub(super) marks: Marks,
    /// Node elimination order built so far.
    pub(super) order: Vec<usize>,
    pub(super) next_id: usize,
    pub(super) stats: NestedDissectionStats,
}

impl Dissection<'_> {
    /// Orders `nodes`: halves recursively, then the separator.
    pub(super) fn dissect(&mut self, nodes: Vec<usize>, depth: usize) {
        self.stats.depth = self.stats.depth.max(depth);
        if nodes.len() <= self.opts.leaf_nodes {
            return self.leaf(&nodes);
        }
        let (a, b, sep) = match self.bisect(nodes) {
            Ok(parts) => parts,
            Err(nodes) => return self.leaf(&nodes),
        };
        if depth == 0 {
            self.stats.top_separator_nodes = sep.len();
            self.stats.top_split_dofs = [self.dofs(&a), self.dofs(&b), self.dofs(&sep)];
        }
        self.stats.n_separators += 1;
        self.stats.separator_nodes += sep.len();
        self.dissect(a, depth + 1);
        self.dissect(b, depth + 1);
        self.order.extend_from_slice(&sep);
    }

    /// DOFs of a node set.
    pub(super) fn dofs(&self, set: &[usize]) -> usize {
        set.iter()
            .map(|&v| self.g.dof_ptr[v + 1] - self.g.dof_ptr[v])
            .sum()
    }

    /// Splits `nodes` at the median of their projection on the principal axis: (first half,
    /// second half, separator), or the nodes back when they cannot be split geometrically.
    #[allow(clippy::type_complexity)]
    pub(super) fn bisect(
        &mut self,
        nodes: Vec<usize>,
    ) -> Result<(Vec<usize>, Vec<usize>, Vec<usize>), Vec<usize>> {
        let Some(axis) = principal_axis(self.g, &nodes) else {
            return Err(nodes);
        };
        let proj: Vec<Real> = nodes
            .iter()
            .map(|&v| {
                let p = self.g.xyz[v];
                axis[0] * p[0] + axis[1] * p[1] + axis[2] * p[2]
            })
            .collect();
        let mut sorted = proj.clone();
        let mid = sorted.len() / 2;
        let (_, &mut med, _) = sorted.select_nth_unstable_by(mid, |a, b| a.total_cmp(b));
        // Points within round-off of the median plane count as on it; the plane goes to the
        // side that balances the halves better (a node plane is then kept whole).
        let (lo, hi) = proj
            .iter()
            .fold((Real::INFINITY, Real::NEG_INFINITY), |(a, b), &p| {
                (a.min(p), b.max(p))
            });
        let tol = 1e-9 * (hi - lo);
        let below = proj.iter().filter(|&&p| p < med - tol).count();
        let upto = proj.iter().filter(|&&p| p <= med + tol).count();
        let half = nodes.len() / 2;
        let strict = match (below > 0, upto < nodes.len()) {
            (true, true) => below.abs_diff(half) <= upto.abs_diff(half),
            (true, false) => true,
            (false, true) => false,
            // All points coincide along the axis: no geometric split.
            (false, false) => return Err(nodes),
        };
        let id = self.next_id;
        self.next_id += 1;
        let mut n0 = 0;
        for (&v, &p) in nodes.iter().zip(&proj) {
            let left = if strict {
                p < med - tol
            } else {
                p <= med + tol
            };
            self.marks.stamp[v] = id;
            self.marks.side[v] = if left { 0 } else { 1 };
            n0 += usize::from(left);
        }
        let sep = min_cover_separator(self.g, &nodes, id, &mut self.marks);
        for &v in &sep {
            self.marks.stamp[v] = usize::MAX;
        }
        let (mut a, mut b) = (Vec::with_capacity(n0), Vec::with_capacity(nodes.len() - n0));
        for &v in &nodes {
            if self.marks.stamp[v] == id {
                if self.marks.side[v] == 0 {
                    a.push(v);
                } else {
                    b.push(v);
                }
            }
        }
        Ok((a, b, sep))
    }

    fn leaf(&mut self, nodes: &[usize]) {
        self.stats.n_leaves += 1;
        order_leaf(
            self.g,
            nodes,
            self.opts.leaf_amd,
            &mut self.marks,
            &mut self.order,
        );
    }
}

/// Unit eigenvector of the largest eigenvalue of the coordinate covariance of `nodes`;
/// `None` if the points coincide.
fn principal_axis(g: &NodeGraph, nodes: &[usize]) -> Option<[Real; 3]> {
    let inv = 1.0 / nodes.len() as Real;
    let mut c = [0.0; 3];
    for &v in nodes {
        for k in 0..3 {
            c[k] += g.xyz[v][k] * inv;
        }
    }
    let mut cov = Matrix3::<Real>::zeros();
    for &v in nodes {
        let d = [0, 1, 2].map(|k| g.xyz[v][k] - c[k]);
        for i in 0..3 {
            for j in 0..3 {
                cov[(i, j)] += d[i] * d[j];
            }
        }
    }
    let trace = cov.trace();
    if trace.is_nan() || trace <= 0.0 {
        return None;
    }
    let e = SymmetricEigen::new(cov);
    let k = e.eigenvalues.imax();
    let v = e.eigenvectors.column(k);
    Some([v[0], v[1], v[2]])
}
