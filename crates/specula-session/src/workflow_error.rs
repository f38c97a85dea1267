//! Why a measurement workflow ([`crate::workflow::measure`]) stopped with an error: one line
//! naming the session, the device or the file, as the CLI prints it (causes are part of the
//! message, not error `source`s, so that error chains print them once, as `JournalError`
//! does).

use crate::engine::EngineError;
use crate::inputs::InputsError;
use crate::journal::{JournalError, SourceRecord, Stage};
use crate::protocol::Endpoint;
use specula_acquisition::calibration::CalibrationError;
use specula_acquisition::instrument::InstrumentError;
use specula_reconstruct::ReconstructError;
use specula_sampling::column::ColumnError;
use specula_sampling::fit::FitError;
use std::path::PathBuf;

/// Why the workflow could not go on.
#[derive(Debug, thiserror::Error)]
pub enum WorkflowError {
    /// `--ideal` asked of a remote device.
    #[error("--ideal is for the simulated device (--truth), not {endpoint}")]
    IdealRemote {
        /// The device's address.
        endpoint: Endpoint,
    },
    /// The remote device does not answer.
    #[error("{endpoint}: cannot reach the device: {cause}")]
    Unreachable {
        /// The device's address.
        endpoint: Endpoint,
        /// The cause.
        cause: InstrumentError,
    },
    /// A device step failed (`cannot describe the device`, `homing the device`, ...).
    #[error("{step}: {cause}")]
    Device {
        /// The step, in words.
        step: String,
        /// The cause.
        cause: InstrumentError,
    },
    /// A practical check (paper 4.2, 4.3) kept failing on device faults.
    #[error("{check} could not run: device: {cause} (after {attempts} tries); run the same command to try again, or give --skip-checks to measure without the checks")]
    Check {
        /// `alignment check` or `orientation check`.
        check: String,
        /// The last fault.
        cause: InstrumentError,
        /// The tries made.
        attempts: u32,
    },
    /// Calibrating the device failed.
    #[error("calibrating the device: {cause}")]
    Calibration {
        /// The cause.
        cause: CalibrationError,
    },
    /// Measuring the instrument's response (its light and aperture) failed.
    #[error("measuring the instrument's response: {cause}")]
    Response {
        /// The cause.
        cause: CalibrationError,
    },
    /// The probe's samples do not make a column.
    #[error("fitting k to the probe: {cause}")]
    ProbeColumn {
        /// The cause.
        cause: ColumnError,
    },
    /// Fitting k to the probe failed (paper section 5.2).
    #[error("fitting k to the probe: {cause}")]
    ProbeFit {
        /// The cause.
        cause: FitError,
    },
    /// Reconstructing the measured samples failed (paper section 5.3).
    #[error("reconstructing the samples: {cause}")]
    Reconstruct {
        /// The cause.
        cause: ReconstructError,
    },
    /// The reconstructed table or the provenance beside it cannot be written (neither
    /// then changes: they are written together).
    #[error(transparent)]
    WriteTable(#[from] specula_core::atomic_file::WriteError),
    /// The summary beside the table cannot be written.
    #[error("{path}: cannot write: {cause}")]
    WriteSummary {
        /// The summary's file.
        path: PathBuf,
        /// The cause.
        cause: std::io::Error,
    },
    /// A resumed session asks other settings than it was started with.
    #[error("{session}: this session was started with other settings ({differences}); rerun with those or use another --session")]
    Settings {
        /// The session journal.
        session: String,
        /// The settings that differ.
        differences: String,
    },
    /// A resumed session measures another source.
    #[error("{session}: this session measures '{stored}', not '{asked}'; use another --session")]
    Source {
        /// The session journal.
        session: String,
        /// The source the session measures.
        stored: SourceRecord,
        /// The source asked for.
        asked: SourceRecord,
    },
    /// A resumed session was started with another device model.
    #[error(
        "{session}: this session was started with another device model; use another --session"
    )]
    DeviceModel {
        /// The session journal.
        session: String,
    },
    /// The session was written by a newer specula than this one.
    #[error("{session}: written by specula {journal}, this is specula {this}: resume it with specula {journal} or later (an older build may measure it differently)")]
    NewerVersion {
        /// The session journal.
        session: String,
        /// The newest version that wrote it.
        journal: String,
        /// This build's version.
        this: String,
    },
    /// A resumed session was measured with another calibration.
    #[error("{session}: this session was measured with another calibration; give the same --calibration or use another --session")]
    Calibrated {
        /// The session journal.
        session: PathBuf,
    },
    /// The journal's main plan and its plan record disagree.
    #[error("{session}: the journal is damaged (its main plan holds {stored_rows} samples, its plan record {measurable} measurable ones); restore it from a copy or measure into a new --session")]
    Damaged {
        /// The session journal.
        session: PathBuf,
        /// The rows of the stored main plan.
        stored_rows: usize,
        /// The measurable samples of the plan record.
        measurable: usize,
    },
    /// A sequential session whose record does not fit its grid.
    #[error("{session}: the journal is damaged (its sequential record chose {recorded} candidate nodes per axis, the session's grid has {candidates}); restore it from a copy or measure into a new --session")]
    SequenceDamaged {
        /// The session journal.
        session: PathBuf,
        /// The record's node counts per axis.
        recorded: String,
        /// The candidates' node counts per axis.
        candidates: String,
    },
    /// The grid cannot be stepped (a step zero or negative, ...).
    #[error("the measurement grid: {0}")]
    Grid(#[from] specula_core::grid::GridError),
    /// A session to reconstruct from whose main stage has no measured sample.
    #[error("{session}: the session has no measured sample in its {} stage", Stage::Main.name())]
    NoMainSamples {
        /// The session journal.
        session: PathBuf,
    },
    /// The session's time limit leaves too little after the checks and the probe for even
    /// the coarsest first design of the main stage.
    #[error("{session}: --max-hours {limit_h} leaves {left_h:.2} h after the checks and the probe ({spent_h:.2} h), and the coarsest first design of the material takes {needed_h:.2} h; measure into a new --session with --max-hours {suggested_h:.1} or more")]
    NoTimeLeft {
        /// The session journal.
        session: PathBuf,
        /// The session's time limit, hours.
        limit_h: f64,
        /// The device time the checks and the probe took, hours.
        spent_h: f64,
        /// The time left for the main stage, hours (0 when the limit is spent).
        left_h: f64,
        /// The coarsest first design's priced time, hours.
        needed_h: f64,
        /// A time limit that holds the coarsest first design and the batches after it, hours.
        suggested_h: f64,
    },
    /// A stage the summary needs is not in the journal.
    #[error("the journal has no {0}")]
    MissingStage(&'static str),
    /// The journal cannot be read or written.
    #[error(transparent)]
    Journal(#[from] JournalError),
    /// The session's inputs changed since it started.
    #[error(transparent)]
    Inputs(#[from] InputsError),
    /// The acquisition engine stopped on an error.
    #[error(transparent)]
    Engine(#[from] EngineError),
    /// The device failed.
    #[error(transparent)]
    Instrument(#[from] InstrumentError),
}

impl WorkflowError {
    /// The error of a device step that failed.
    pub(crate) fn device(step: impl Into<String>) -> impl FnOnce(InstrumentError) -> Self {
        let step = step.into();
        move |cause| WorkflowError::Device { step, cause }
    }
}
