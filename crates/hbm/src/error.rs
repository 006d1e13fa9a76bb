//! The crate's error type.

/// Everything that can go wrong in `hbm`.
///
/// Non-convergence of a solver is *not* an error: it is reported in the returned
/// [`PeriodicSolution`](crate::PeriodicSolution) / [`SolveReport`](crate::SolveReport).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum HbmError {
    /// A scalar argument is outside its admissible range (or NaN).
    #[error("{name} must be {bound}, got {value}")]
    InvalidParameter {
        /// Name of the argument.
        name: &'static str,
        /// The admissible range, in words.
        bound: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A vector or matrix has the wrong size.
    #[error("{what} must have length {expected}, got {got}")]
    DimensionMismatch {
        /// What was passed.
        what: &'static str,
        /// Expected length.
        expected: usize,
        /// Actual length.
        got: usize,
    },
    /// The system does not know the named continuation parameter.
    #[error("unknown parameter `{name}`")]
    UnknownParameter {
        /// The name that was asked for.
        name: String,
    },
    /// The system returned a NaN or infinite value.
    #[error("non-finite value in {what} at t = {time}")]
    NonFinite {
        /// Which quantity (force, forcing, Jacobian, residual).
        what: &'static str,
        /// Time of the sample (s, or the system's time unit).
        time: f64,
    },
    /// The basis cannot be built from the given harmonics.
    #[error("invalid basis: {reason}")]
    InvalidBasis {
        /// Why.
        reason: String,
    },
    /// A matrix that must be invertible (mass matrix, Jacobian of an initial guess) is singular.
    #[error("singular matrix: {what}")]
    Singular {
        /// Which matrix.
        what: &'static str,
    },
    /// An LU factorisation ([`BlockedLu`](crate::BlockedLu)) found no non-zero pivot: the
    /// matrix is singular (column `column`, from 0, depends on the columns before it).
    #[error("singular matrix: no non-zero pivot in column {column} of the LU factorisation")]
    SingularPivot {
        /// The column (from 0) whose pivot search found only zeros.
        column: usize,
    },
    /// A matrix to be factored has (or the elimination produced) a NaN or infinite entry.
    #[error("non-finite entry in column {column} of the matrix to be LU-factored")]
    NonFiniteMatrix {
        /// The column (from 0) of the first non-finite entry found.
        column: usize,
    },
    /// The argmin executor failed for a reason other than an [`HbmError`].
    #[error("solver failure: {message}")]
    Solver {
        /// The message of the underlying error.
        message: String,
    },
    /// The inner GMRES solve of [`Method::NewtonKrylov`](crate::Method::NewtonKrylov) did not
    /// reach its tolerance within [`KrylovOptions::max_products`](crate::KrylovOptions)
    /// (raise the bound or the restart length, or use the dense [`Method::Newton`](crate::Method)).
    #[error(
        "GMRES did not converge in Newton iteration {newton_iteration}: relative residual \
         {relative_residual} after {products} Jacobian-vector products"
    )]
    KrylovNotConverged {
        /// The Newton iteration (from 1) whose linear solve failed.
        newton_iteration: u64,
        /// Jacobian-vector products spent.
        products: usize,
        /// `‖J δ + r‖ / ‖r‖` reached.
        relative_residual: f64,
    },
    /// The system rejected a base frequency or parameter value (see
    /// [`SystemError`](crate::SystemError)).
    #[error("system: {0}")]
    System(#[source] system::SystemError),
}

impl HbmError {
    /// Convert an argmin (anyhow) error back into an [`HbmError`] when it is one.
    pub(crate) fn from_argmin(e: argmin::core::Error) -> Self {
        match e.downcast::<HbmError>() {
            Ok(h) => h,
            Err(e) => HbmError::Solver {
                message: e.to_string(),
            },
        }
    }
}

/// Check that `value` is finite and strictly positive.
pub(crate) fn check_positive(name: &'static str, value: f64) -> Result<f64, HbmError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(HbmError::InvalidParameter {
            name,
            bound: "finite and > 0",
            value,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_carry_numbers() {
        let e = check_positive("omega", -2.0).unwrap_err();
        assert_eq!(e.to_string(), "omega must be finite and > 0, got -2");
        assert!(check_positive("omega", f64::NAN).is_err());
    }
}
