//! The error type of the complex eigenvalue analysis.

use thiserror::Error;

/// Errors of [`super::complex_eigen`] and [`super::sweep`]: bad input or a singular
/// factorisation. Messages carry the sizes and values involved.
#[derive(Debug, Error)]
pub enum CeaError {
    /// An option value is out of range; names the field and the value.
    #[error("invalid option `{field}` = {value}: {reason}")]
    InvalidOption {
        /// Field name.
        field: &'static str,
        /// Offending value, printed.
        value: String,
        /// Why it is invalid.
        reason: String,
    },
    /// Matrix shapes do not agree.
    #[error("shape mismatch: {what} is {rows}x{cols}, expected {expected_rows}x{expected_cols}")]
    Shape {
        /// Which matrix.
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
    /// A matrix entry is NaN or infinite.
    #[error("non-finite entry {value} in {what} at ({row}, {col})")]
    NonFinite {
        /// Which matrix.
        what: &'static str,
        /// Row.
        row: usize,
        /// Column.
        col: usize,
        /// The value.
        value: f64,
    },
    /// A mass matrix is not symmetric positive definite (Cholesky failed).
    #[error("{what} ({n}x{n}) is not positive definite: Cholesky failed at pivot {pivot}")]
    NotPositiveDefinite {
        /// Which matrix (`M` or the reduced mass `TᵀMT`).
        what: &'static str,
        /// Size.
        n: usize,
        /// Pivot index where the factorisation failed.
        pivot: usize,
    },
    /// G does not have full row rank: some constraints are redundant.
    #[error("constraint matrix G ({ng}x{n}) is rank deficient: smallest/largest singular value = {ratio:e} <= rank_tol = {tol:e}")]
    RankDeficientConstraints {
        /// Number of constraints.
        ng: usize,
        /// Number of DOFs.
        n: usize,
        /// σ_min/σ_max of G.
        ratio: f64,
        /// Tolerance used.
        tol: f64,
    },
    /// G M⁻¹ (Gᵀ − D) is singular: the contact forces are not determined by the constraint.
    #[error(
        "contact operator G M^-1 (G^T - D) ({ng}x{ng}) is singular: min/max |pivot| = {ratio:e}"
    )]
    SingularContactOperator {
        /// Number of constraints.
        ng: usize,
        /// Smallest/largest absolute LU pivot.
        ratio: f64,
    },
    /// A dense decomposition did not converge.
    #[error("{what} of a {n}x{n} matrix did not converge")]
    NoConvergence {
        /// Which decomposition.
        what: &'static str,
        /// Size.
        n: usize,
    },
    /// The bordered matrix of a shift-invert refinement is singular: the shift is a root to
    /// machine precision.
    #[error("shift-invert matrix at p = {re} + {im}i is singular: min/max |pivot| = {ratio:e}")]
    SingularShift {
        /// Real part of the shift.
        re: f64,
        /// Imaginary part of the shift.
        im: f64,
        /// Smallest/largest absolute LU pivot.
        ratio: f64,
    },
    /// The caller's interrupt (`CeaOptions::interrupt`) asked to stop.
    #[error("interrupted by the caller during {during}")]
    Interrupted {
        /// What was running.
        during: &'static str,
    },
    /// The sweep's matrix builder failed at μ.
    #[error("building the matrices at mu = {mu} failed: {message}")]
    Build {
        /// Friction coefficient asked for.
        mu: f64,
        /// The builder's error, printed.
        message: String,
    },
    /// The problem differs from the one the projection basis was built for in a matrix
    /// that must not change (G, or the matrix sizes).
    #[error("projection basis was built for a different {what}: entry ({row}, {col}) is {value}, the basis had {reference}; use method = \"exact\" or rebuild the basis")]
    BasisMismatch {
        /// Which matrix.
        what: &'static str,
        /// Row of the first differing entry.
        row: usize,
        /// Column of the first differing entry.
        col: usize,
        /// Entry now.
        value: f64,
        /// Entry of the reference.
        reference: f64,
    },
}
