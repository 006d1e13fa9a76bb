//! The error type of the study engine.

/// Everything that can go wrong while reading, computing, sharding, merging or writing a study.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A study file (see `docs/studies.md`) is invalid.
    #[error("study file: {0}")]
    StudyFile(String),
    /// A shard specification, partial result or journal is invalid, or partial results do not
    /// merge (see the `shard` module).
    #[error("shard: {0}")]
    Shard(String),
    /// A point or a study could not be computed (described in words).
    #[error("{0}")]
    Study(String),
    /// A model or solver computation failed, with what was being done.
    #[error("{context}: {source}")]
    Upstream {
        /// What the study was doing.
        context: String,
        /// The underlying error.
        source: Box<dyn std::error::Error + Send + Sync + 'static>,
    },
    /// A table, figure or heat map could not be built or rendered, or an output name is invalid
    /// (see [`plot::Error`]).
    #[error(transparent)]
    Plot(#[from] plot::Error),
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

/// A model-contract error as the study engine reports it: a bad input (an unknown or ambiguous
/// parameter included) is a study-file error, a
/// point that cannot be computed a study failure, an engine failure keeps its context.
impl From<models::contract::PointError> for Error {
    fn from(e: models::contract::PointError) -> Self {
        use models::contract::PointError as P;
        match e {
            P::Input(m) => Error::StudyFile(m),
            e @ (P::UnknownParameter { .. } | P::AmbiguousParameter { .. }) => {
                Error::StudyFile(e.to_string())
            }
            P::Compute(m) => Error::Study(m),
            P::Upstream { context, source } => Error::Upstream { context, source },
            e => Error::Study(e.to_string()),
        }
    }
}
