//! squeal-reduction: Craig–Bampton superelements, OP4 and punch DMIG.

pub mod error;
pub use error::ReductionError;

pub mod cb;
pub use cb::{CbModel, CbOptions};
pub mod superelement;

// File formats (OP4, punch DMIG) and their inspection.
pub mod inspect;
pub mod matrix;
pub mod op4;
pub mod punch;
pub use matrix::{MatrixData, MatrixForm, NamedMatrix, Precision};
