//! The one error type of squeal-reduction.

use thiserror::Error;

/// Errors of the reduction crate (Craig–Bampton, superelements, OP4, punch).
#[derive(Debug, Error)]
pub enum ReductionError {
    // ---- Craig–Bampton and superelements ----
    /// An option value is out of range; names the field and the value.
    #[error("invalid option `{field}` = {value}: {reason}")]
    InvalidOption {
        field: &'static str,
        value: String,
        reason: String,
    },
    /// Matrix shapes do not agree.
    #[error("shape mismatch: {what} is {rows}x{cols}, expected {expected_rows}x{expected_cols}")]
    ShapeMismatch {
        what: String,
        rows: usize,
        cols: usize,
        expected_rows: usize,
        expected_cols: usize,
    },
    /// A boundary DOF index is out of range or repeated.
    #[error(
        "boundary DOF {index} (position {position} in the boundary list) is {reason} (n = {n})"
    )]
    BadBoundary {
        index: usize,
        position: usize,
        reason: &'static str,
        n: usize,
    },
    /// A sparse or dense Cholesky factorisation failed (matrix not positive definite).
    #[error("Cholesky factorisation of {what} ({n}x{n}) failed: {detail}")]
    Factorization {
        what: String,
        n: usize,
        detail: String,
    },
    /// An eigenvalue solve failed or did not converge.
    #[error("eigen solve of {what} ({n} DOFs) failed: {detail}")]
    Eigen {
        what: String,
        n: usize,
        detail: String,
    },
    /// A matrix contains a NaN or infinite entry.
    #[error("{what} has a non-finite entry {value} at ({row}, {col})")]
    NonFinite {
        what: String,
        row: usize,
        col: usize,
        value: f64,
    },
    /// A matrix that must be symmetric is not (relative tolerance 1e-10 of its largest entry).
    #[error("{what} is not symmetric: entry ({row}, {col}) = {value}, entry ({col}, {row}) = {transposed}")]
    NotSymmetric {
        what: String,
        row: usize,
        col: usize,
        value: f64,
        transposed: f64,
    },
    /// The block Lanczos of the fixed-interface modes reached its largest Krylov dimension
    /// (`CbOptions::lanczos_max_dim`) before the modes it needs converged.
    #[error(
        "eigen solve of {what} ({n} DOFs): block Lanczos did not converge within Krylov \
         dimension {dim} (lanczos_max_dim): {needed}"
    )]
    LanczosNotConverged {
        what: String,
        n: usize,
        dim: usize,
        /// What converged against what was needed.
        needed: String,
    },
    /// The caller's interrupt (`CbOptions::interrupt`) asked to stop.
    #[error("interrupted by the caller during {during}")]
    Interrupted { during: &'static str },
    /// Superelement assembly: inconsistent component or key data.
    #[error("superelement `{component}`: {detail}")]
    Superelement { component: String, detail: String },

    // ---- OP4, punch DMIG and inspect (file formats) ----
    /// A file could not be opened, read or written.
    #[error("{path}: {source}")]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },
    /// An OP4 file is malformed; names the file, the position (line for text files, byte
    /// offset for binary ones) and the matrix being read.
    #[error("{path}:{location}: OP4 matrix `{matrix}`: {detail}")]
    Op4 {
        path: String,
        location: String,
        matrix: String,
        detail: String,
    },
    /// A punch (DMIG) file is malformed; names the file, the line and the matrix.
    #[error("{path}:{line}: DMIG `{matrix}`: {detail}")]
    Punch {
        path: String,
        line: usize,
        matrix: String,
        detail: String,
    },
    /// A matrix cannot be written in the requested file format.
    #[error("cannot write matrix `{matrix}`: {detail}")]
    Unwritable { matrix: String, detail: String },
}
