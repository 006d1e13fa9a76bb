//! The error type of the output layer.

/// A table, figure or heat map that cannot be built or rendered, or a name or printed number that
/// cannot be read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A printed number could not be read (it must look like `12`, `-0.0125` or `1.5e-3`).
    #[error("printed number `{printed}` is not a decimal number")]
    PrintedNumber {
        /// The text as transcribed.
        printed: String,
    },
    /// A table row had the wrong number of cells.
    #[error("table `{table}`: row has {got} cells, the header has {expected}")]
    RowLength {
        /// The table's name.
        table: String,
        /// Number of columns in the header.
        expected: usize,
        /// Number of cells in the row.
        got: usize,
    },
    /// An output name is not usable as a file-name part (allowed: `a-z`, `0-9`, `-`, `_`, `.`).
    #[error("name `{name}` must be non-empty and use only a-z, 0-9, '-', '_', '.'")]
    InvalidName {
        /// The offending name.
        name: String,
    },
    /// Rendering a figure failed.
    #[error("figure `{figure}`: {reason}")]
    Plot {
        /// The figure's name.
        figure: String,
        /// What plotters reported.
        reason: String,
    },
}

/// Check that `name` is usable in a file name: non-empty, only `a-z 0-9 - _ .`.
///
/// ```
/// assert!(geardyn_plot::check_name("liu2021-fig11_a.b").is_ok());
/// assert!(geardyn_plot::check_name("Fig 11").is_err());
/// ```
pub fn check_name(name: &str) -> Result<(), Error> {
    let ok = !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || matches!(c, '-' | '_' | '.'));
    if ok {
        Ok(())
    } else {
        Err(Error::InvalidName {
            name: name.to_owned(),
        })
    }
}
