//! The error type of the validation harness.

/// Everything that can go wrong while running a study or writing its outputs.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A published-data file could not be parsed.
    #[error("published data {file}: {reason}")]
    PublishedParse {
        /// The file (as passed to [`crate::Published::parse`]).
        file: String,
        /// What the parser reported.
        reason: String,
    },
    /// A published value or claim was looked up by an id the file does not contain.
    #[error("published data {file}: no {kind} with id `{id}`")]
    PublishedMissing {
        /// The file searched.
        file: String,
        /// `"value"` or `"claim"`.
        kind: &'static str,
        /// The id looked up.
        id: String,
    },
    /// A table, figure or heat map could not be built or rendered, or a printed number or an
    /// output name is invalid (see [`plot::Error`]).
    #[error(transparent)]
    Plot(#[from] plot::Error),
    /// A model, solver or geometry computation failed inside a study.
    #[error("{context}: {source}")]
    Upstream {
        /// What the study was doing.
        context: String,
        /// The underlying error.
        source: Box<dyn std::error::Error + Send + Sync + 'static>,
    },
    /// A study-specific failure described in words (e.g. a solver that did not converge).
    #[error("{0}")]
    Study(String),
    /// An input a validation study reads is invalid.
    #[error("study file: {0}")]
    StudyFile(String),
    /// Reading or writing a file failed.
    #[error("{path}: {source}")]
    Io {
        /// The file or directory.
        path: String,
        /// The I/O error.
        source: std::io::Error,
    },
}

pub(crate) use plot::check_name;

/// Attach context to any error from another crate, turning it into [`Error::Upstream`].
///
/// ```
/// use geardyn_validate::ResultExt;
/// fn parse(s: &str) -> Result<f64, geardyn_validate::Error> {
///     s.parse::<f64>().context("reading the input")
/// }
/// assert!(parse("x").is_err());
/// ```
pub trait ResultExt<T> {
    /// Wrap the error with a description of what was being done.
    fn context(self, what: &str) -> Result<T, Error>;
}

impl<T, E> ResultExt<T> for Result<T, E>
where
    E: std::error::Error + Send + Sync + 'static,
{
    fn context(self, what: &str) -> Result<T, Error> {
        self.map_err(|e| Error::Upstream {
            context: what.to_owned(),
            source: Box::new(e),
        })
    }
}
