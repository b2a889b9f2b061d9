//! Superelement assembly: several reduced components joined on shared boundary DOFs.

mod assemble;
mod dofmap;

pub use assemble::{assemble, Assembly, AssemblyStats, Component};
pub use dofmap::{DofKey, DofKind, RecoveredDof, ReducedDof, ReducedDofMap};
