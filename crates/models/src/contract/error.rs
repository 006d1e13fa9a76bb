//! The error of the model contract: what a front end (study file, Python) needs to tell a bad
//! input from a failed computation.

/// Why a model could not be set up or solved at one point.
///
/// Front ends map the variants to their own kinds: `geardyn study` reports [`PointError::Input`]
/// as a study-file error (the study stops before computing) and the others as a failed point;
/// the Python package raises `ParameterError` for every variant but a classified
/// [`PointError::Model`] engine failure (`SolverError`).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PointError {
    /// A bad input: an unknown or ill-typed name, a setting out of its bounds, an old spelling.
    #[error("{0}")]
    Input(String),
    /// A parameter override names no field of the model's parameter struct.
    #[error("unknown parameter `{name}`; parameters: {}", paths.join(", "))]
    UnknownParameter {
        /// The name as written.
        name: String,
        /// Every valid address, as canonical dotted paths ([`crate::contract::field_names`]).
        paths: Vec<String>,
    },
    /// A bare parameter name that more than one nested struct holds (no "first holder wins").
    #[error("parameter `{name}` is ambiguous: write one of {}", paths.join(", "))]
    AmbiguousParameter {
        /// The bare name as written.
        name: String,
        /// The dotted paths of every holder.
        paths: Vec<String>,
    },
    /// The point cannot be computed as asked (over a work limit, an unusable value).
    #[error("{0}")]
    Compute(String),
    /// A model, solver or geometry computation failed.
    #[error("{context}: {source}")]
    Upstream {
        /// What was being done.
        context: String,
        /// The underlying error.
        source: Box<dyn std::error::Error + Send + Sync + 'static>,
    },
    /// A model error without context (the full-result solves of [`crate::contract::Model::solve_full`]).
    #[error(transparent)]
    Model(#[from] crate::Error),
    /// A result that serde could not represent.
    #[error("result not representable: {0}")]
    Unrepresentable(String),
}

/// Attach context to any error from another crate, turning it into [`PointError::Upstream`].
pub trait WithContext<T> {
    /// Wrap the error with a description of what was being done.
    fn context(self, what: &str) -> Result<T, PointError>;
}

impl<T, E> WithContext<T> for Result<T, E>
where
    E: std::error::Error + Send + Sync + 'static,
{
    fn context(self, what: &str) -> Result<T, PointError> {
        self.map_err(|e| PointError::Upstream {
            context: what.to_owned(),
            source: Box::new(e),
        })
    }
}
