//! One module per verb; each takes a typed scene and a run folder.
//!
//! Two levels, neither importing a module of its own level (`pipeline/tests/layers.rs`):
//! `mesh`, `modes`, `reduce`, `cea`, `transient`, `limit_cycle` and `plotit` sit on the problem
//! layer ([`crate::model`], [`crate::problem`]); `sweep`, `reproduce`, `compare`, `accuracy` and
//! `propensity` sit above them.

pub mod accuracy;
pub mod cea;
pub mod compare;
pub mod limit_cycle;
pub mod mesh;
pub mod modes;
pub mod plotit;
pub mod propensity;
pub mod reduce;
pub mod reproduce;
pub mod sweep;
pub mod transient;

/// The model builder under its former path (the library's API).
pub use crate::model;
