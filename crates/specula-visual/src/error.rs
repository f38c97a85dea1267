//! The visual crate's error: a picture, a report page or an environment that cannot be
//! drawn, read or written, in one line naming the file (causes are part of the message, not
//! error `source`s, so that error chains print them once, as `MerlError` does).

use crate::canvas::Canvas;
use plotters::drawing::DrawingAreaErrorKind;
use plotters_backend::DrawingBackend;
use std::path::PathBuf;

/// A drawing error of plotters on Specula's canvas.
pub type DrawCause = DrawingAreaErrorKind<<Canvas<'static> as DrawingBackend>::ErrorType>;

/// Why a picture, a report page or an environment cannot be made, read or written.
#[derive(Debug, thiserror::Error)]
pub enum VisualError {
    /// The render was stopped before it finished.
    #[error(transparent)]
    Stopped(#[from] specula_core::progress::Stopped),
    /// What was given to draw cannot be drawn (no values, mismatched sizes, ...), in words.
    #[error("{0}")]
    Data(String),
    /// Drawing failed.
    #[error("cannot draw {what}: {cause}")]
    Draw {
        /// What was being drawn: `the plot`, `the heatmap`, `the grid`, a label.
        what: String,
        /// The cause.
        cause: DrawCause,
    },
    /// The drawn buffer does not have the picture's size.
    #[error("plot buffer size mismatch")]
    Buffer,
    /// A file that cannot be written.
    #[error("{path}: cannot write {what}: {cause}")]
    Write {
        /// The file.
        path: PathBuf,
        /// What was being written: `the image`, `the PNG`, `the report`.
        what: &'static str,
        /// The cause.
        cause: std::io::Error,
    },
    /// An image file that cannot be read or decoded.
    #[error("{path}: cannot read the image: {cause}")]
    Read {
        /// The file.
        path: PathBuf,
        /// The cause.
        cause: image::ImageError,
    },
    /// A picture that cannot be encoded as PNG.
    #[error("cannot encode a PNG: {cause}")]
    Encode {
        /// The cause.
        cause: image::ImageError,
    },
    /// An environment file whose image is not a usable environment.
    #[error("{path}: {cause}")]
    Environment {
        /// The file.
        path: PathBuf,
        /// What is wrong with its image.
        cause: Box<VisualError>,
    },
    /// A request's value outside its range.
    #[error(transparent)]
    Range(#[from] specula_core::range::RangeError),
    /// A request's choice that is none of the names it accepts.
    #[error(transparent)]
    Choice(#[from] specula_core::request::ChoiceError),
}

impl VisualError {
    /// The error of drawing `what`.
    pub(crate) fn draw(what: impl Into<String>) -> impl FnOnce(DrawCause) -> Self {
        let what = what.into();
        move |cause| VisualError::Draw { what, cause }
    }
}
