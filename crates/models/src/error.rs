//! The error type of the `models` crate.

/// Everything that can go wrong when building or solving a published model.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A parameter is outside its admissible range (or NaN).
    #[error("{field} must be {bound}, got {value}")]
    InvalidParameter {
        /// Name of the offending field, as in the parameter struct (e.g. `"liu2021.e_r"`).
        field: String,
        /// The bound it violates, in words (e.g. `"> 0"`, `"in [0, 1)"`).
        bound: String,
        /// The value that was given.
        value: f64,
    },
    /// A leaf crate rejected a derived input.
    #[error("gear geometry: {0}")]
    Geometry(String),
    /// A stiffness or backlash leaf rejected a derived input.
    #[error("{0}")]
    Leaf(String),
    /// An engine (harmonic balance or time stepping) did not succeed.
    #[error("solver: {0}")]
    Solver(String),
    /// A quadrature ran out of its panel budget, could not advance, or did not reach its
    /// tolerance.
    #[error("quadrature at τ = {at}: {reason}")]
    Quadrature {
        /// What went wrong, with the bound that was hit.
        reason: String,
        /// Where (the integration variable) it happened.
        at: f64,
    },
}

impl Error {
    /// Shorthand for [`Error::InvalidParameter`].
    pub fn invalid(field: impl Into<String>, bound: impl Into<String>, value: f64) -> Self {
        Error::InvalidParameter {
            field: field.into(),
            bound: bound.into(),
            value,
        }
    }
}
