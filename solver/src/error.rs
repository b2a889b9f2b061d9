//! The crate's one error type.

use crate::Real;

/// Errors of the solver crate. Messages carry the numbers needed to locate the problem.
///
/// `Err` is for bad input, a callback failure or a singular factorisation; a time integration
/// that merely fails to converge returns `Ok(Status::…)` instead (see [`crate::bdf::Status`]).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SolverError {
    /// An option is out of range.
    #[error("invalid option `{field}` = {value}: {reason}")]
    InvalidOption {
        /// Name of the offending field.
        field: &'static str,
        /// Its value, printed.
        value: String,
        /// What was expected.
        reason: &'static str,
    },
    /// Two inputs disagree in size.
    #[error("dimension mismatch for {what}: expected {expected}, got {got}")]
    DimensionMismatch {
        /// Which input.
        what: &'static str,
        /// Expected length (or rows).
        expected: usize,
        /// Actual length (or rows).
        got: usize,
    },
    /// A dense factorisation met a (numerically) zero pivot.
    #[error(
        "singular {what} matrix at t = {t:e}: pivot {index} = {pivot:e} (largest {max_pivot:e})"
    )]
    SingularMatrix {
        /// Which matrix (e.g. "BSQL iteration").
        what: &'static str,
        /// Time at which it was formed.
        t: Real,
        /// Pivot index.
        index: usize,
        /// Pivot value.
        pivot: Real,
        /// Largest pivot magnitude, for scale.
        max_pivot: Real,
    },
    /// A callback produced a NaN or infinite value.
    #[error("non-finite {what} at t = {t:e}, component {index}: {value}")]
    NonFinite {
        /// Which quantity (e.g. "residual", "friction force").
        what: &'static str,
        /// Time.
        t: Real,
        /// Component index.
        index: usize,
        /// The value.
        value: Real,
    },
    /// A Newton solve outside the time stepper (initial conditions, steady state) did not converge.
    #[error("{what} Newton did not converge after {iterations} iterations: residual {residual:e} > tolerance {tolerance:e}")]
    NewtonFailed {
        /// Which solve.
        what: &'static str,
        /// Iterations done.
        iterations: usize,
        /// Final residual norm.
        residual: Real,
        /// Requested tolerance.
        tolerance: Real,
    },
    /// A saved integrator state does not fit the system or options it is restored into.
    #[error("restart state mismatch: {what} (state {state}, expected {expected})")]
    StateMismatch {
        /// What differs.
        what: &'static str,
        /// Value in the state.
        state: usize,
        /// Value expected.
        expected: usize,
    },
    /// A saved integrator state has a field out of range (a damaged or hand-edited restart).
    #[error("integrator state field `{field}`: {message}")]
    InvalidState {
        /// The field (`order`, `phi[2]`, `stats.order_histogram`, ...).
        field: String,
        /// What is wrong, with the value.
        message: String,
    },
    /// An output time lies before the interval the integrator can interpolate.
    #[error("output time {tout:e} lies outside the interpolation interval [{t_min:e}, {t_max:e}]")]
    BadOutputTime {
        /// Requested time.
        tout: Real,
        /// Start of the last step.
        t_min: Real,
        /// Current internal time.
        t_max: Real,
    },
    /// A user callback failed for a reason of its own.
    #[error("callback failed at t = {t:e}: {message}")]
    Callback {
        /// Time.
        t: Real,
        /// Explanation.
        message: String,
    },
}

impl SolverError {
    /// Whether the time stepper may recover from this error by reducing the step size
    /// (IDA's "recoverable" callback failures): non-finite values and singular iteration matrices.
    pub fn is_recoverable(&self) -> bool {
        matches!(
            self,
            SolverError::NonFinite { .. } | SolverError::SingularMatrix { .. }
        )
    }
}
