//! The error type of the `gear-geometry` crate.

/// Everything that can go wrong when building a gear pair or evaluating its kinematics.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A parameter is outside its admissible range, or is NaN.
    ///
    /// Renders as e.g. `"b must be in [0, min(1, u)) (keeps both centrode radii positive), got 1.2"`.
    #[error("{name} must be {bound}, got {value}")]
    InvalidParameter {
        /// Name of the offending field or argument, as in the parameter struct.
        name: &'static str,
        /// The bound it violates, in words.
        bound: &'static str,
        /// The value that was given.
        value: f64,
    },
    /// An iterative numerical procedure (root find, closure solve) did not converge.
    #[error("{what} did not converge after {iterations} iterations (residual {residual:e})")]
    NoConvergence {
        /// What was being solved.
        what: &'static str,
        /// Iterations spent.
        iterations: usize,
        /// Last residual.
        residual: f64,
    },
}

impl From<system::numeric::NoConvergence> for Error {
    fn from(e: system::numeric::NoConvergence) -> Self {
        Error::NoConvergence {
            what: e.what,
            iterations: e.iterations,
            residual: e.residual,
        }
    }
}

impl Error {
    /// Shorthand for [`Error::InvalidParameter`].
    pub fn invalid(name: &'static str, bound: &'static str, value: f64) -> Self {
        Error::InvalidParameter { name, bound, value }
    }
}

/// `Ok(x)` when `x` is finite and strictly positive, otherwise an [`Error::InvalidParameter`].
pub(crate) fn positive(name: &'static str, x: f64) -> Result<f64, Error> {
    if x.is_finite() && x > 0.0 {
        Ok(x)
    } else {
        Err(Error::invalid(name, "finite and > 0", x))
    }
}

/// `Ok(x)` when `x` is finite.
pub(crate) fn finite(name: &'static str, x: f64) -> Result<f64, Error> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(Error::invalid(name, "finite", x))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_with_numbers() {
        let e = Error::invalid("r", "finite and > 0", -1e-5);
        assert_eq!(e.to_string(), "r must be finite and > 0, got -0.00001");
        assert!(positive("r", f64::NAN).is_err());
        assert!(positive("r", 0.0).is_err());
        assert!(finite("x", f64::INFINITY).is_err());
    }
}
