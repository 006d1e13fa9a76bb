//! The crate's error type.

/// Errors returned by `timestep` functions.
///
/// Integration that runs but does not reach its end (step limit, step-size underflow,
/// non-finite state) is *not* an error: it is reported in [`crate::Status`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A scalar parameter is outside its admissible range (or NaN).
    #[error("{name} must be {bound}, got {value}")]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// Admissible range in words, e.g. "> 0".
        bound: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A vector has the wrong length.
    #[error("{name} must have length {expected}, got {got}")]
    DimensionMismatch {
        /// Vector name.
        name: &'static str,
        /// Expected length.
        expected: usize,
        /// Actual length.
        got: usize,
    },
    /// An input vector or signal contains NaN or infinity.
    #[error("{name} contains a non-finite value at index {index}")]
    NonFinite {
        /// Vector name.
        name: &'static str,
        /// First offending index.
        index: usize,
    },
    /// A signal or sample set is too short for the requested analysis.
    #[error("{name} needs at least {needed} samples, got {got}")]
    TooFewSamples {
        /// What was too short.
        name: &'static str,
        /// Minimum number of samples.
        needed: usize,
        /// Number supplied.
        got: usize,
    },
    /// A user's system could not be built for one parameter value (e.g. a model constructor
    /// refused it); the message is the model's.
    #[error("system not built: {0}")]
    System(String),
}

/// Result alias for this crate.
pub type Result<T> = std::result::Result<T, Error>;

pub(crate) fn check_positive(name: &'static str, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            name,
            bound: "finite and > 0",
            value,
        })
    }
}

pub(crate) fn check_finite(name: &'static str, value: f64) -> Result<()> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            name,
            bound: "finite",
            value,
        })
    }
}

pub(crate) fn check_finite_slice(name: &'static str, v: &[f64]) -> Result<()> {
    match v.iter().position(|x| !x.is_finite()) {
        Some(index) => Err(Error::NonFinite { name, index }),
        None => Ok(()),
    }
}
