//! The sampling crate's error: a probe, a MERL slice or a result file that cannot be read,
//! made or written, in one line naming the file or the BRDF (causes are part of the message,
//! not error `source`s, so that error chains print them once, as `MerlError` does).

use crate::column::ColumnError;
use crate::fit::FitError;
use crate::slice::PROBE_THETA_D_DEG;
use specula_core::merl::MerlProblem;
use std::path::PathBuf;

/// Why a probe, a characteristic slice or a result file cannot be read, made or written.
#[derive(Debug, thiserror::Error)]
pub enum SamplingError {
    /// A file or folder that cannot be opened, read, listed or written.
    #[error("{path}: cannot {action}: {}", specula_core::shown::io_cause(cause))]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// What was being done: `open`, `read`, `write` or `list the folder`.
        action: &'static str,
        /// The cause.
        cause: std::io::Error,
    },
    /// A CSV file that cannot be opened, read or written, or a row that cannot be parsed.
    #[error("{path}: {place}: {cause}")]
    Csv {
        /// The file.
        path: PathBuf,
        /// What was being done or where: `cannot write`, `row 3: expected four numbers`, ...
        place: String,
        /// The cause.
        cause: csv::Error,
    },
    /// A MERL `.binary` file whose header or length is wrong.
    #[error("{path}: {problem}")]
    Merl {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        problem: MerlProblem,
    },
    /// A MERL file with a NaN or infinite value in its characteristic slice.
    #[error("{path}: non-finite value in the {channel} channel at cell (theta_h {theta_h_i}, theta_d {theta_d_i}, phi_d {phi_d_i})")]
    NonFinite {
        /// The file.
        path: PathBuf,
        /// `red`, `green` or `blue`.
        channel: &'static str,
        /// The MERL theta_h bin.
        theta_h_i: usize,
        /// The MERL theta_d bin.
        theta_d_i: usize,
        /// The MERL phi_d bin.
        phi_d_i: usize,
    },
    /// A folder without MERL files.
    #[error("{path}: no MERL .binary files in this folder")]
    NoMerlFiles {
        /// The folder.
        path: PathBuf,
    },
    /// A probe CSV file with another header than `theta_h,r,g,b`.
    #[error("{path}: expected the header theta_h,r,g,b, found {found}")]
    ProbeHeader {
        /// The file.
        path: PathBuf,
        /// The header found.
        found: String,
    },
    /// A CSV file without a column it needs.
    #[error("{path}: no {column} column (header: {found})")]
    NoColumn {
        /// The file.
        path: PathBuf,
        /// The column looked for.
        column: &'static str,
        /// The header found.
        found: String,
    },
    /// A CSV cell that is not a finite number.
    #[error("{path}: row {row}: '{text}' is not a number")]
    NotANumber {
        /// The file.
        path: PathBuf,
        /// The row, counting the header as row 1.
        row: usize,
        /// The cell's text.
        text: String,
    },
    /// A CSV file with a header and no rows.
    #[error("{path}: no rows")]
    NoRows {
        /// The file.
        path: PathBuf,
    },
    /// Too few probe samples asked for.
    #[error("a probe needs at least 2 samples, got {0}")]
    ProbeSamples(usize),
    /// A probe angle outside its range.
    #[error("{what} = {value_deg} deg is outside [{min_deg}, {max_deg}]")]
    ProbeAngle {
        /// `theta_d`, `phi_d` or `phi_h`.
        what: &'static str,
        /// The angle, degrees.
        value_deg: f64,
        /// The smallest accepted angle, degrees.
        min_deg: f64,
        /// The largest accepted angle, degrees.
        max_deg: f64,
    },
    /// Probe samples that do not make a usable column.
    #[error("{origin}: {problem}: {cause}")]
    Probe {
        /// The BRDF or the file the probe came from.
        origin: String,
        /// What is wrong with the probe, in words.
        problem: &'static str,
        /// The cause.
        cause: ColumnError,
    },
    /// A material whose probe column (theta_d = 40 deg, paper section 5.1) is not measured.
    #[error("{material}: the probe column theta_d = {PROBE_THETA_D_DEG} is not measured")]
    NoProbeColumn {
        /// The material.
        material: String,
    },
    /// Fitting k to a probe failed (paper section 5.2).
    #[error(transparent)]
    Fit(#[from] FitError),
    /// Probe samples that do not make a column.
    #[error(transparent)]
    Column(#[from] ColumnError),
}

impl SamplingError {
    /// The error of a file or folder that cannot be opened, read, listed or written.
    pub(crate) fn io<'a>(
        path: &'a std::path::Path,
        action: &'static str,
    ) -> impl FnOnce(std::io::Error) -> Self + 'a {
        move |cause| SamplingError::Io {
            path: path.to_path_buf(),
            action,
            cause,
        }
    }

    /// The CSV file at `path` opened through the bounded reader
    /// ([`specula_core::bounded_read::CSV_LIMITS`]), its header read; the error names the
    /// file.
    pub(crate) fn open_csv(
        path: &std::path::Path,
    ) -> Result<csv::Reader<impl std::io::Read>, Self> {
        let text =
            specula_core::bounded_read::open_text(path, specula_core::bounded_read::CSV_LIMITS)
                .map_err(Self::io(path, "read"))?;
        let mut reader = csv::Reader::from_reader(text);
        reader
            .headers()
            .map_err(Self::csv(path, "cannot read the header".to_string()))?;
        Ok(reader)
    }

    /// The error of the CSV file at `path`, `place` saying what was being done or where.
    pub(crate) fn csv(
        path: &std::path::Path,
        place: String,
    ) -> impl FnOnce(csv::Error) -> Self + '_ {
        move |cause| SamplingError::Csv {
            path: path.to_path_buf(),
            place,
            cause,
        }
    }

    /// The error of a CSV file that cannot be written.
    pub(crate) fn csv_write(path: &std::path::Path) -> impl FnOnce(csv::Error) -> Self + '_ {
        Self::csv(path, "cannot write".to_string())
    }
}
