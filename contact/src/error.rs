//! The one error type of squeal-contact.

use std::fmt;
use thiserror::Error;

/// A node named in an error message: its id, coordinates and what is wrong with it.
#[derive(Debug, Clone, PartialEq)]
pub struct NodeReport {
    /// Node id as given by the caller.
    pub id: u64,
    /// Node coordinates.
    pub coords: [f64; 3],
    /// What is wrong with this node.
    pub reason: String,
}

impl fmt::Display for NodeReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "node {} at ({:.6e}, {:.6e}, {:.6e}): {}",
            self.id, self.coords[0], self.coords[1], self.coords[2], self.reason
        )
    }
}

fn list(nodes: &[NodeReport]) -> String {
    nodes.iter().map(|n| format!("\n  {n}")).collect::<String>()
}

/// Errors of the contact crate (gap matching, friction laws, gap forces).
#[derive(Debug, Error)]
pub enum ContactError {
    /// An option or law parameter is out of range; names the field and the value.
    #[error("invalid option `{field}` = {value}: {reason}")]
    InvalidOption {
        /// Field name (dotted path).
        field: String,
        /// Offending value, printed.
        value: String,
        /// Why it is invalid.
        reason: String,
    },
    /// Gap matching failed; every offending node is listed with id and coordinates.
    #[error("gap matching failed for {} node(s) (tolerance {tolerance:e}):{}", nodes.len(), list(nodes))]
    Matching {
        /// Matching tolerance used.
        tolerance: f64,
        /// Every offending node (unmatched pad nodes, ambiguous matches, rotor nodes used twice).
        nodes: Vec<NodeReport>,
    },
    /// A vector passed to a force routine has the wrong length.
    #[error("{what} has length {len}, expected {expected}")]
    Length {
        /// Which argument.
        what: &'static str,
        /// Its length.
        len: usize,
        /// Expected length.
        expected: usize,
    },
    /// A matrix passed to a tangent routine has the wrong shape.
    #[error("{what} is {rows}x{cols}, expected {expected_rows}x{expected_cols}")]
    Shape {
        /// Which argument.
        what: &'static str,
        /// Rows.
        rows: usize,
        /// Columns.
        cols: usize,
        /// Expected rows.
        expected_rows: usize,
        /// Expected columns.
        expected_cols: usize,
    },
    /// A gap refers to a DOF index outside the vector.
    #[error(
        "gap {gap} (pad node {pad_node}, rotor node {rotor_node}) refers to DOF {dof}, but n = {n}"
    )]
    DofOutOfRange {
        /// Gap index.
        gap: usize,
        /// Pad node id.
        pad_node: u64,
        /// Rotor node id.
        rotor_node: u64,
        /// Offending DOF index.
        dof: usize,
        /// Vector length.
        n: usize,
    },
    /// A tied gap's face data are inconsistent (counts of nodes, weights, DOFs).
    #[error("gap {gap} (pad node {pad_node}): {message}")]
    Tie {
        /// Gap index.
        gap: usize,
        /// Pad node id.
        pad_node: u64,
        /// What is inconsistent.
        message: String,
    },
    /// A non-finite value appeared (input or result) at a gap.
    #[error(
        "non-finite {what} = {value} at gap {gap} (pad node {pad_node}, rotor node {rotor_node})"
    )]
    NonFinite {
        /// Which quantity.
        what: &'static str,
        /// Its value.
        value: f64,
        /// Gap index.
        gap: usize,
        /// Pad node id.
        pad_node: u64,
        /// Rotor node id.
        rotor_node: u64,
    },
}
