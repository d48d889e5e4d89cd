//! The errors of a phalanx run and their exit codes.

use crate::dataset::DataError;
use std::path::{Path, PathBuf};

/// Exit status for bad input data (a data file, a claims file, an option value).
pub const EXIT_DATA: i32 = 2;
/// Exit status for any other failure (e.g. an output that cannot be written),
/// and for `check` when a claim disagrees without a recorded erratum.
pub const EXIT_FAILURE: i32 = 1;

/// Everything that can stop a phalanx command.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// An input file has problems; each names its line and column.
    #[error(transparent)]
    Data(#[from] DataError),
    /// An option value is unusable.
    #[error("{0}")]
    Usage(String),
    /// An output could not be written.
    #[error("cannot write {}", path.display())]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// Rendering a report or a plot failed.
    #[error("{context}")]
    Render {
        context: String,
        #[source]
        source: Box<dyn std::error::Error + Send + Sync>,
    },
}

impl Error {
    /// The process exit status for this error.
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Data(_) | Error::Usage(_) => EXIT_DATA,
            Error::Write { .. } | Error::Render { .. } => EXIT_FAILURE,
        }
    }

    /// Turns an I/O error on `path` into [`Error::Write`]: `.map_err(Error::write(&path))`.
    pub(crate) fn write(path: &Path) -> impl FnOnce(std::io::Error) -> Error {
        move |source| Error::Write {
            path: path.to_path_buf(),
            source,
        }
    }

    /// A rendering error with context.
    pub(crate) fn render(
        context: impl Into<String>,
        source: impl Into<Box<dyn std::error::Error + Send + Sync>>,
    ) -> Error {
        Error::Render {
            context: context.into(),
            source: source.into(),
        }
    }
}

/// Formats an error with its chain of causes, one per line.
pub fn report(err: &(dyn std::error::Error + 'static)) -> String {
    let mut out = format!("error: {err}");
    let mut source = err.source();
    while let Some(cause) = source {
        out.push_str(&format!("\n  caused by: {cause}"));
        source = cause.source();
    }
    out
}
