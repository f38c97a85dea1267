//! The report's error: what could not be read, computed or written, naming the file.

use std::error::Error;
use std::path::PathBuf;

/// Why a report could not be made.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// The report's file is neither `.html` nor `.pdf`.
    #[error("{}: a report is written as .html or .pdf (by the file's extension)", .0.display())]
    OutputFormat(PathBuf),
    /// A plot's file is not `.png`.
    #[error("{}: plots are written as .png", .0.display())]
    PlotFormat(PathBuf),
    /// A request's value outside its range.
    #[error(transparent)]
    Range(#[from] specula_core::range::RangeError),
    /// A PDF was asked for and no Chromium is installed to print it.
    #[error("{}: a PDF report is printed by headless Chromium, and none is installed (chromium, chromium-browser or google-chrome on PATH); write .html instead", .0.display())]
    NoChromium(PathBuf),
    /// Chromium did not print the PDF.
    #[error("{}: {problem}", path.display())]
    Pdf {
        /// The PDF file.
        path: PathBuf,
        /// What went wrong, on one line.
        problem: String,
    },
    /// The options do not fit together or lie out of range.
    #[error("{0}")]
    Options(&'static str),
    /// A file of the report could not be written.
    #[error("{}: cannot write", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A step failed on the named input.
    #[error("{origin}")]
    In {
        /// Where the failing data came from.
        origin: String,
        /// The cause.
        source: Box<dyn Error + Send + Sync>,
    },
    /// A library step failed (reading a table or journal, fitting, plotting, ...); its
    /// message names the file.
    #[error(transparent)]
    Step(Box<dyn Error + Send + Sync>),
}

impl ReportError {
    /// A library step's error.
    pub(crate) fn from_source(error: impl Into<Box<dyn Error + Send + Sync>>) -> Self {
        ReportError::Step(error.into())
    }

    /// A library step's error on data from `origin`.
    pub(crate) fn within(origin: &str) -> impl FnOnce(Box<dyn Error + Send + Sync>) -> Self + '_ {
        move |source| ReportError::In {
            origin: origin.to_string(),
            source,
        }
    }
}

/// A library result as the report's.
pub(crate) trait OrReport<T> {
    /// The error as a [`ReportError::Step`].
    fn or_report(self) -> Result<T, ReportError>;
}

impl<T, E: Into<Box<dyn Error + Send + Sync>>> OrReport<T> for Result<T, E> {
    fn or_report(self) -> Result<T, ReportError> {
        self.map_err(ReportError::from_source)
    }
}
