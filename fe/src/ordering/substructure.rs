//! Substructuring by the same recursive inertial bisection as [`nested_dissection`]: node sets
//! are split until they have at most a given number of DOFs; those are the substructures (each
//! ordered by nested dissection for its own factorisation), and the separators found on the
//! way are split into their connected pieces.
//!
//! [`nested_dissection`]: super::nested_dissection

use super::dissect::Dissection;
use super::graph::NodeGraph;
use super::separator::Marks;
use super::{NestedDissectionOptions, NestedDissectionStats};
use crate::{FeError, Real};
use faer::sparse::SymbolicSparseColMatRef;

/// Substructures and separator pieces of a matrix pattern (DOF indices of the pattern).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Substructuring {
    /// DOFs of each substructure, in nested-dissection order (fill-reducing for its factor).
    pub substructures: Vec<Vec<usize>>,
    /// DOFs of each separator piece: a connected part of one separator.
    pub separators: Vec<Vec<usize>>,
    /// Depth in the bisection tree of each piece's separator (0 = the first split).
    pub separator_depth: Vec<usize>,
}

/// Splits the DOFs of `pattern` (n × n, either or both triangles; `dof_coords[i]` the point of
/// DOF i, consecutive DOFs at one point forming a node) into substructures of at most
/// `max_dofs` DOFs and the separators between them (see the [module docs](self)).
///
/// Errors: invalid options, `max_dofs` = 0, `dof_coords.len() != n`, non-finite coordinates.
pub fn substructure(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    dof_coords: &[[Real; 3]],
    max_dofs: usize,
    opts: &NestedDissectionOptions,
) -> Result<Substructuring, FeError> {
    opts.validate()?;
    if max_dofs == 0 {
        return Err(FeError::InvalidValue {
            field: "substructure max_dofs".into(),
            value: 0.0,
            reason: "must be at least 1",
        });
    }
    let n = pattern.ncols();
    if pattern.nrows() != n || dof_coords.len() != n {
        return Err(FeError::Dimension {
            what: "DOF coordinates for substructuring",
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
    let mut d = Dissection::new(&g, opts);
    let mut out = Substructuring::default();
    split(&mut d, (0..g.len()).collect(), 0, max_dofs, &mut out);
    Ok(out)
}

fn split(
    d: &mut Dissection<'_>,
    nodes: Vec<usize>,
    depth: usize,
    max_dofs: usize,
    out: &mut Substructuring,
) {
    if nodes.is_empty() {
        return;
    }
    let leaf = |d: &mut Dissection<'_>, nodes: Vec<usize>, out: &mut Substructuring| {
        let start = d.order.len();
        d.dissect(nodes, 1);
        let order = d.order.split_off(start);
        out.substructures.push(d.node_dofs(&order));
    };
    if d.dofs(&nodes) <= max_dofs {
        return leaf(d, nodes, out);
    }
    match d.bisect(nodes) {
        Err(nodes) => leaf(d, nodes, out),
        Ok((a, b, sep)) => {
            for piece in pieces(d.g, &sep, &mut d.marks) {
                out.separators.push(d.node_dofs(&piece));
                out.separator_depth.push(depth);
            }
            split(d, a, depth + 1, max_dofs, out);
            split(d, b, depth + 1, max_dofs, out);
        }
    }
}

/// Connected components of the subgraph `set` induces.
fn pieces(g: &NodeGraph, set: &[usize], marks: &mut Marks) -> Vec<Vec<usize>> {
    const IN: usize = usize::MAX - 1;
    for &v in set {
        marks.local[v] = IN;
    }
    let mut out = Vec::new();
    for &s in set {
        if marks.local[s] != IN {
            continue;
        }
        let id = out.len();
        marks.local[s] = id;
        let mut piece = vec![s];
        let mut head = 0;
        while head < piece.len() {
            let v = piece[head];
            head += 1;
            for &u in g.neighbours(v) {
                if marks.local[u] == IN {
                    marks.local[u] = id;
                    piece.push(u);
                }
            }
        }
        out.push(piece);
    }
    for &v in set {
        marks.local[v] = usize::MAX;
    }
    out
}

impl<'a> Dissection<'a> {
    pub(super) fn new(g: &'a NodeGraph, opts: &'a NestedDissectionOptions) -> Self {
        Dissection {
            g,
            opts,
            marks: Marks::new(g.len()),
            order: Vec::with_capacity(g.len()),
            next_id: 0,
            stats: NestedDissectionStats {
                n_nodes: g.len(),
                ..Default::default()
            },
        }
    }

    /// The DOFs of `nodes`, node by node.
    pub(super) fn node_dofs(&self, nodes: &[usize]) -> Vec<usize> {
        nodes
            .iter()
            .flat_map(|&v| self.g.dof_ptr[v]..self.g.dof_ptr[v + 1])
            .collect()
    }
}
