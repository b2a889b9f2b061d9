//! Fill-reducing orderings for the sparse Cholesky factorisation of K − σM.
//!
//! [`nested_dissection`] orders the *nodes* of the mesh (the 3 DOFs of a node stay together)
//! by recursive inertial bisection: the node set is split at the median of its coordinates
//! projected on the principal axis of inertia, the vertex separator is the minimum vertex
//! cover of the graph edges that cross the cut (König's theorem), and the two halves are
//! ordered first, recursively, the separator last. Leaves are ordered by AMD.
//!
//! # Why geometric (inertial) bisection
//! The coordinates are at hand when the model comes from a mesh, and on solid meshes a cut
//! across the principal axis gives the planar cross-sections that a good separator is: on a
//! brake-rotor annulus the arcs are cut radially. Graph-only level-structure separators (BFS
//! from a pseudo-peripheral node) give curved, up to one element thick, separators on compact
//! pieces. The graph is still used to extract the separator, so the result is a valid vertex
//! separator on any mesh; the coordinates only choose where to cut.

mod dissect;
mod fill;
mod graph;
mod leaf;
mod separator;
mod substructure;

pub use dissect::nested_dissection;
pub use fill::{cholesky_fill, CholeskyFill};
pub use graph::dof_coordinates;
pub use substructure::{substructure, Substructuring};

use crate::{FeError, Real};
use serde::{Deserialize, Serialize};

/// Which fill-reducing ordering the sparse Cholesky of K − σM uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FillOrdering {
    /// Nested dissection when DOF coordinates are given and the problem has at least
    /// [`AUTO_ND_MIN_DOFS`] DOFs, AMD otherwise.
    #[default]
    Auto,
    /// Approximate minimum degree (faer's AMD).
    Amd,
    /// Geometric nested dissection ([`nested_dissection`]); needs DOF coordinates.
    NestedDissection,
}

/// Smallest problem for which `FillOrdering::Auto` picks nested dissection.
pub const AUTO_ND_MIN_DOFS: usize = 20_000;

/// Nested-dissection options.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct NestedDissectionOptions {
    /// Node sets with at most this many nodes are not split further (default: 32).
    pub leaf_nodes: usize,
    /// Order the leaves by AMD (default: true); natural order otherwise.
    pub leaf_amd: bool,
}

impl Default for NestedDissectionOptions {
    fn default() -> Self {
        NestedDissectionOptions {
            leaf_nodes: 32,
            leaf_amd: true,
        }
    }
}

impl NestedDissectionOptions {
    /// Checks the option values; errors name the field.
    pub fn validate(&self) -> Result<(), FeError> {
        if self.leaf_nodes < 2 {
            return Err(FeError::InvalidValue {
                field: "nested_dissection.leaf_nodes".to_string(),
                value: self.leaf_nodes as Real,
                reason: "must be at least 2",
            });
        }
        Ok(())
    }
}

/// Nested-dissection statistics.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct NestedDissectionStats {
    /// Graph nodes (groups of consecutive DOFs at the same point).
    pub n_nodes: usize,
    /// Separators found.
    pub n_separators: usize,
    /// Nodes in all separators.
    pub separator_nodes: usize,
    /// Nodes in the top-level separator.
    pub top_separator_nodes: usize,
    /// DOFs of the top level's first half, second half and separator, in that order at the
    /// start, middle and end of the permutation (all zero when the top level is a leaf).
    pub top_split_dofs: [usize; 3],
    /// Leaves ordered.
    pub n_leaves: usize,
    /// Deepest level of the dissection tree.
    pub depth: usize,
    /// Seconds to compute the ordering.
    pub ordering_s: Real,
}

/// A fill-reducing permutation of the DOFs: `perm[new] = old`, `perm_inv[old] = new`.
#[derive(Debug, Clone, PartialEq)]
pub struct DofPermutation {
    /// New position → original DOF.
    pub perm: Vec<usize>,
    /// Original DOF → new position.
    pub perm_inv: Vec<usize>,
}

impl DofPermutation {
    /// Builds the permutation from `perm` (new → old); errors if it is not a permutation.
    pub fn from_order(perm: Vec<usize>) -> Result<Self, FeError> {
        let n = perm.len();
        let mut perm_inv = vec![usize::MAX; n];
        for (new, &old) in perm.iter().enumerate() {
            if old >= n || perm_inv[old] != usize::MAX {
                return Err(FeError::Factorisation {
                    what: "nested-dissection ordering".to_string(),
                    reason: format!("entry {new} = {old} repeated or out of range (n = {n})"),
                });
            }
            perm_inv[old] = new;
        }
        Ok(DofPermutation { perm, perm_inv })
    }
}
