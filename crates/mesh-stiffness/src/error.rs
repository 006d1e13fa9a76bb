//! The crate's error type.

/// Everything that can go wrong when building or evaluating a stiffness model.
///
/// Every variant carries the numbers that explain it, so that the message reads like
/// "contact ratio must be in (1, 2], got 2.3".
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A scalar parameter is outside its admissible range (NaN is always outside).
    #[error("{name} must be {bound}, got {value}")]
    InvalidParameter {
        /// Name of the parameter (paper symbol where there is one).
        name: &'static str,
        /// The admissible range, in words or interval notation.
        bound: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A sample of a stiffness curve is NaN or infinite.
    #[error("sample {index} of the stiffness curve must be finite, got {value}")]
    NonFiniteSample {
        /// Index of the offending sample.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// Too few samples for the requested fit.
    #[error("need at least {min} samples, got {got}")]
    TooFewSamples {
        /// Minimum number of samples.
        min: usize,
        /// Number of samples supplied.
        got: usize,
    },
    /// More harmonics requested than the sampling resolves (Nyquist).
    #[error(
        "{requested} harmonics requested, but {samples} samples over {periods} periods resolve at most {max}"
    )]
    TooManyHarmonics {
        /// Harmonics requested.
        requested: usize,
        /// Largest resolvable number of harmonics, `floor((samples - 1) / (2 periods))`.
        max: usize,
        /// Number of samples.
        samples: usize,
        /// Number of whole mesh periods covered by the samples.
        periods: usize,
    },
    /// The cosine and sine coefficient lists of a Fourier series differ in length.
    #[error("{cos} cosine coefficients but {sin} sine coefficients")]
    CoefficientLengthMismatch {
        /// Number of cosine coefficients.
        cos: usize,
        /// Number of sine coefficients.
        sin: usize,
    },
    /// A count (teeth, periods, samples per period) must be positive.
    #[error("{name} must be at least {min}, got {value}")]
    InvalidCount {
        /// Name of the count.
        name: &'static str,
        /// Smallest admissible value.
        min: usize,
        /// The offending value.
        value: usize,
    },
}

/// Shorthand for `Result<T, geardyn_mesh_stiffness::Error>`.
pub type Result<T> = std::result::Result<T, Error>;

/// `value` must be finite and strictly positive.
pub(crate) fn positive(name: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name,
            bound: "finite and > 0",
            value,
        })
    }
}

/// `value` must be finite and non-negative.
pub(crate) fn non_negative(name: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name,
            bound: "finite and >= 0",
            value,
        })
    }
}

/// `value` must be finite.
pub(crate) fn finite(name: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name,
            bound: "finite",
            value,
        })
    }
}
