//! NASTRAN `OUTPUT4` (OP4) matrix files: read and write, ASCII and binary, dense and sparse.
//!
//! Reading accepts what NASTRAN, pyNastran and pyyeti write: ASCII or binary (either byte
//! order, 4- or 8-byte record markers, 32- or 64-bit integers), dense columns or sparse
//! strings (non-BIGMAT `IS` words or BIGMAT `L+1, IROW` pairs; pyNastran's ASCII sparse
//! strings, whose headers carry the column's word count, are recognised), real or complex,
//! single or double precision, several matrices per file. A file without a matrix is an error. Symmetric matrices (form 6) are stored in full
//! and read as stored. Values are kept as read (single-precision binary values are `f32`).
//!
//! Writing covers ASCII (`1P,3E23.16`, 17 significant digits: round trips are exact) and
//! binary (4-byte markers and integers, little- or big-endian), dense / non-BIGMAT / BIGMAT.

mod binary_read;
mod build;
mod text_read;
mod write;

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::matrix::NamedMatrix;
use crate::ReductionError;

/// Largest matrix (entries) the readers build: reduced models are stored dense, and a
/// garbled header must not make a reader allocate more than 1 GiB per matrix. (At 2²⁵ the
/// cad brake's 7 497-DOF superelement model, written by the model cache, could not be read
/// back: every run rebuilt it.)
pub const MAX_DENSE_ENTRIES: usize = 1 << 27;

/// How columns are stored in a written OP4 file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Sparsity {
    /// Each nonzero column from its first to its last nonzero, zeros between included.
    #[default]
    Dense,
    /// Strings of consecutive nonzeros with one-word `IS = IROW + 65536 (L + 1)` headers
    /// (switches to BIGMAT above 65535 rows, as NASTRAN does).
    NonBigmat,
    /// Strings with two-word `L + 1, IROW` headers; the header row count is negative.
    Bigmat,
}

/// Precision of written values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WritePrecision {
    /// Each matrix's own `precision`.
    #[default]
    AsMatrix,
    /// Single precision (types 1 and 3): values are rounded to `f32`.
    Single,
    /// Double precision (types 2 and 4).
    Double,
}

/// Options of [`write`].
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Op4WriteOptions {
    /// Binary (Fortran unformatted) rather than ASCII (default: true).
    pub binary: bool,
    /// Column storage (default: dense).
    pub sparse: Sparsity,
    /// Value precision (default: each matrix's own).
    pub precision: WritePrecision,
    /// Big-endian binary files (default: false, little-endian; ignored for ASCII).
    pub big_endian: bool,
}

impl Default for Op4WriteOptions {
    fn default() -> Self {
        Self {
            binary: true,
            sparse: Sparsity::Dense,
            precision: WritePrecision::AsMatrix,
            big_endian: false,
        }
    }
}

impl Op4WriteOptions {
    /// Every combination is valid; kept for the house Options pattern.
    pub fn validate(&self) -> Result<(), ReductionError> {
        Ok(())
    }
}

/// Reads every matrix of an OP4 file, in file order.
pub fn read(path: impl AsRef<Path>) -> Result<Vec<NamedMatrix>, ReductionError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|source| ReductionError::Io {
        path: path.display().to_string(),
        source,
    })?;
    read_bytes_named(&bytes, &path.display().to_string())
}

/// Reads every matrix of OP4 file contents (errors name the file `<bytes>`).
pub fn read_bytes(bytes: &[u8]) -> Result<Vec<NamedMatrix>, ReductionError> {
    read_bytes_named(bytes, "<bytes>")
}

/// Reads every matrix of OP4 file contents; errors name the file `path`. A file without a
/// matrix (empty, or blank lines only) is an error.
pub fn read_bytes_named(bytes: &[u8], path: &str) -> Result<Vec<NamedMatrix>, ReductionError> {
    let mats = read_any(bytes, path)?;
    if mats.is_empty() {
        return Err(ReductionError::Op4 {
            path: path.to_string(),
            location: "line 1".to_string(),
            matrix: String::new(),
            detail: format!("no matrix in the file ({} bytes)", bytes.len()),
        });
    }
    Ok(mats)
}

fn read_any(bytes: &[u8], path: &str) -> Result<Vec<NamedMatrix>, ReductionError> {
    if let Some(layout) = binary_read::detect(bytes) {
        return binary_read::read_binary(bytes, layout).map_err(|(offset, matrix, detail)| {
            ReductionError::Op4 {
                path: path.to_string(),
                location: format!("byte {offset}"),
                matrix,
                detail,
            }
        });
    }
    let text = std::str::from_utf8(bytes).map_err(|e| ReductionError::Op4 {
        path: path.to_string(),
        location: format!("byte {}", e.valid_up_to()),
        matrix: String::new(),
        detail: "neither a binary OP4 (first record marker is not 24 or 48) nor ASCII text"
            .to_string(),
    })?;
    text_read::read_text(text).map_err(|(line, matrix, detail)| ReductionError::Op4 {
        path: path.to_string(),
        location: format!("line {line}"),
        matrix,
        detail,
    })
}

/// True if the bytes start like a binary OP4 file.
pub fn is_binary(bytes: &[u8]) -> bool {
    binary_read::detect(bytes).is_some()
}

/// Writes the matrices, in order, to an OP4 file.
pub fn write(
    path: impl AsRef<Path>,
    mats: &[&NamedMatrix],
    opts: &Op4WriteOptions,
) -> Result<(), ReductionError> {
    let path = path.as_ref();
    let bytes = write_bytes(mats, opts)?;
    std::fs::write(path, bytes).map_err(|source| ReductionError::Io {
        path: path.display().to_string(),
        source,
    })
}

/// The OP4 file contents of the matrices.
pub fn write_bytes(
    mats: &[&NamedMatrix],
    opts: &Op4WriteOptions,
) -> Result<Vec<u8>, ReductionError> {
    opts.validate()?;
    if opts.binary {
        write::write_binary(mats, opts)
    } else {
        write::write_text(mats, opts).map(String::into_bytes)
    }
}
