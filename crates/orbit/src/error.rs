//! The crate's error type.

use system::SystemError;

/// Everything that can go wrong in [`crate`]: invalid input (naming the field and the bound),
/// integration failures, and solvers that did not converge.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum OrbitError {
    /// An input value is outside its admissible range.
    #[error("{field} must be {bound}, got {value}")]
    InvalidInput {
        /// Name of the offending field or argument.
        field: &'static str,
        /// The admissible range, in words.
        bound: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A vector or matrix has the wrong length.
    #[error("{what}: expected length {expected}, got {got}")]
    DimensionMismatch {
        /// What was passed.
        what: &'static str,
        /// The required length.
        expected: usize,
        /// The length given.
        got: usize,
    },
    /// A matrix that must be invertible is (numerically) singular.
    #[error("singular {what}")]
    Singular {
        /// Which matrix.
        what: &'static str,
    },
    /// A state, right-hand side or Jacobian became NaN or infinite.
    #[error("non-finite {what} at t = {time}")]
    NonFinite {
        /// Which quantity.
        what: &'static str,
        /// Time at which it was seen.
        time: f64,
    },
    /// The adaptive step size fell below its floor.
    #[error("step size underflow at t = {time} (h = {step})")]
    StepSizeUnderflow {
        /// Time reached.
        time: f64,
        /// The step that was too small.
        step: f64,
    },
    /// More steps than [`FlowOptions::max_steps`](crate::FlowOptions::max_steps).
    #[error("more than {limit} steps in one flow (t = {time})")]
    TooManySteps {
        /// The cap.
        limit: usize,
        /// Time reached.
        time: f64,
    },
    /// The thread's wall-clock deadline ([`system::deadline`]) passed.
    #[error("time limit: the flow stopped at t = {time}")]
    TimeLimit {
        /// Time reached.
        time: f64,
    },
    /// More events than [`FlowOptions::max_events`](crate::FlowOptions::max_events) (chattering).
    #[error("more than {limit} events in one flow (t = {time}): chattering?")]
    TooManyEvents {
        /// The cap.
        limit: usize,
        /// Time reached.
        time: f64,
    },
    /// The saltation matrix is undefined: the trajectory meets the switching surface
    /// tangentially (`dh/dt = 0`, a grazing contact).
    #[error("tangential (grazing) crossing of event {index} at t = {time}: saltation undefined")]
    TangentialEvent {
        /// Event index.
        index: usize,
        /// Event time.
        time: f64,
    },
    /// A Newton iteration did not reach its tolerance.
    #[error("{what} did not converge in {iterations} iterations (residual {residual:e})")]
    NotConverged {
        /// Which solver.
        what: &'static str,
        /// Iterations done.
        iterations: usize,
        /// Last residual norm.
        residual: f64,
    },
    /// An eigenvalue computation failed to converge.
    #[error("eigenvalue iteration did not converge")]
    Eigen,
    /// The model rejected a parameter or base frequency.
    #[error(transparent)]
    System(#[from] SystemError),
}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, OrbitError>;

/// `Err(InvalidInput)` unless `ok`.
pub(crate) fn check(ok: bool, field: &'static str, bound: &'static str, value: f64) -> Result<()> {
    if ok {
        Ok(())
    } else {
        Err(OrbitError::InvalidInput {
            field,
            bound,
            value,
        })
    }
}
