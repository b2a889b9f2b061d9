//! NASTRAN punch files: DMIG matrices (direct matrix input at grid points).
//!
//! Reading accepts small-field, large-field (`DMIG*` with `*` continuations) and free-field
//! (comma) cards, `D` exponents and NASTRAN's compressed reals (`1.-3`, `-.5+2`), real and
//! complex (`POLAR` 0 or 1) values, IFO 1, 2, 6 (one triangle given, symmetrised; both given
//! with different values is an error) and 9. Other bulk-data cards in the file are skipped,
//! with their continuation lines. A DMIG header card has no continuation: data continuing it
//! is an error naming the line (a column card whose first line is missing would otherwise lose
//! its entries). Rows and columns are (grid, component) pairs sorted as NASTRAN orders them.

mod cards;
pub(crate) mod number;
mod read;
mod write;

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::matrix::NamedMatrix;
use crate::ReductionError;

/// A degree of freedom: (grid or scalar point id, component 0..=6; 0 for scalar points).
pub type Dof = (u64, u8);

/// A DMIG matrix with the DOFs of its rows and columns.
#[derive(Debug, Clone, PartialEq)]
pub struct DmigMatrix {
    /// The values, name, form (from IFO) and precision (from TIN).
    pub matrix: NamedMatrix,
    /// DOF of each row, sorted by grid then component.
    pub rows: Vec<Dof>,
    /// DOF of each column, sorted by grid then component (IFO 9: column numbers, component 0).
    pub cols: Vec<Dof>,
}

/// Options of [`write`].
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PunchWriteOptions {
    /// Large-field (`DMIG*`, 16-character) column cards; else small field, 8 characters
    /// (default: true — about 11 significant digits instead of 5).
    pub large_field: bool,
}

impl Default for PunchWriteOptions {
    fn default() -> Self {
        Self { large_field: true }
    }
}

impl PunchWriteOptions {
    /// Every combination is valid; kept for the house Options pattern.
    pub fn validate(&self) -> Result<(), ReductionError> {
        Ok(())
    }
}

/// Reads every DMIG matrix of a punch (or bulk-data) file, in the order of their header cards.
pub fn read(path: impl AsRef<Path>) -> Result<Vec<DmigMatrix>, ReductionError> {
    let path = path.as_ref();
    let p = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|source| ReductionError::Io {
        path: p.clone(),
        source,
    })?;
    read_bytes_named(&bytes, &p)
}

/// Reads every DMIG matrix of punch text (errors name the file `<text>`).
pub fn read_str(text: &str) -> Result<Vec<DmigMatrix>, ReductionError> {
    read_bytes_named(text.as_bytes(), "<text>")
}

/// Reads every DMIG matrix of punch file contents; errors name the file `path`.
pub fn read_bytes_named(bytes: &[u8], path: &str) -> Result<Vec<DmigMatrix>, ReductionError> {
    let text = std::str::from_utf8(bytes).map_err(|e| ReductionError::Punch {
        path: path.to_string(),
        line: bytes[..e.valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
            + 1,
        matrix: String::new(),
        detail: "not UTF-8 text".to_string(),
    })?;
    read::read_text(text).map_err(|(line, matrix, detail)| ReductionError::Punch {
        path: path.to_string(),
        line,
        matrix,
        detail,
    })
}

/// Writes the matrices, in order, as DMIG cards.
pub fn write(
    path: impl AsRef<Path>,
    mats: &[&DmigMatrix],
    opts: &PunchWriteOptions,
) -> Result<(), ReductionError> {
    let path = path.as_ref();
    let text = write_string(mats, opts)?;
    std::fs::write(path, text).map_err(|source| ReductionError::Io {
        path: path.display().to_string(),
        source,
    })
}

/// The DMIG cards of the matrices, as text.
pub fn write_string(
    mats: &[&DmigMatrix],
    opts: &PunchWriteOptions,
) -> Result<String, ReductionError> {
    opts.validate()?;
    write::write_text(mats, opts)
}
