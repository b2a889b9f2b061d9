//! The crate's one error type.

use crate::Real;
use thiserror::Error;

/// Errors of squeal-fe. Messages carry the offending names and values.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FeError {
    /// A material or option value is out of its valid range.
    #[error("invalid value {field} = {value}: {reason}")]
    InvalidValue {
        field: String,
        value: Real,
        reason: &'static str,
    },
    /// An element's Jacobian determinant is zero or negative at an integration point.
    #[error(
        "non-positive Jacobian determinant {det:e} in block '{block}', element tag {tag} \
         (check node ordering and element shape)"
    )]
    NonPositiveJacobian { block: String, tag: u64, det: Real },
    /// An element-level failure outside assembly (no block or tag known).
    #[error("non-positive Jacobian determinant {det:e} at parametric point {xi:?}")]
    ElementJacobian { det: Real, xi: [Real; 3] },
    /// The incompatible-mode block of a hex8 could not be condensed.
    #[error("singular incompatible-mode stiffness in block '{block}', element tag {tag}")]
    SingularIncompatible { block: String, tag: u64 },
    /// `materials.len()` differs from `mesh.volumes.len()`.
    #[error("{got} materials given for {expected} volume blocks")]
    MaterialCount { expected: usize, got: usize },
    /// A block of a kind that cannot appear where it was found.
    #[error("block '{block}' has cell kind {kind}, expected {expected}")]
    WrongCellKind {
        block: String,
        kind: String,
        expected: &'static str,
    },
    /// A node index beyond the node count.
    #[error("node index {node} in {context} is out of range (the mesh has {n_nodes} nodes)")]
    NodeOutOfRange {
        node: usize,
        n_nodes: usize,
        context: String,
    },
    /// A DOF component outside 0..3.
    #[error("DOF component {comp} of node {node} is out of range (0, 1 or 2)")]
    ComponentOutOfRange { node: usize, comp: usize },
    /// The DOF map was built for another node count.
    #[error("DOF map has {dof_nodes} nodes, the mesh has {mesh_nodes}")]
    DofMapMismatch { dof_nodes: usize, mesh_nodes: usize },
    /// A named face or node set does not exist.
    #[error("unknown {what} '{name}' (available: {available})")]
    UnknownSet {
        what: &'static str,
        name: String,
        available: String,
    },
    /// A face cell has no adjacent volume cell.
    #[error("face tag {tag} of set '{set}' touches no volume cell")]
    OrphanFace { set: String, tag: u64 },
    /// A face with zero area (degenerate).
    #[error("face tag {tag} of set '{set}' has a degenerate Jacobian {det:e}")]
    DegenerateFace { set: String, tag: u64, det: Real },
    /// Matrix dimensions do not agree.
    #[error("dimension mismatch: {what}: {got} (expected {expected})")]
    Dimension {
        what: &'static str,
        got: usize,
        expected: usize,
    },
    /// More modes requested than the problem has.
    #[error("{requested} modes requested but the problem has only {n} free DOFs")]
    TooManyModes { requested: usize, n: usize },
    /// Factorisation or dense eigen-decomposition failed.
    #[error("factorisation of {what} failed: {reason}")]
    Factorisation { what: String, reason: String },
    /// A non-finite value appeared.
    #[error("non-finite value in {what}")]
    NonFinite { what: String },
    /// The caller's [`Interrupt`](crate::Interrupt) asked to stop.
    #[error("interrupted by the caller during {during}")]
    Interrupted { during: &'static str },
}
