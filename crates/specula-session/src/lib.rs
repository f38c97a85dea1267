//! Measurement sessions: what turns a plan into a measured BRDF on a real or simulated
//! device, for hours, without losing or repeating a sample (paper 4, 5.3).
//!
//! - [`journal`]: the session's SQLite file (one transaction per sample, resumable);
//! - `journal::check`: seeing damage to a journal (integrity check, checksums, counts);
//! - [`protocol`]: the JSON-lines driver protocol for real hardware (client and server);
//! - [`engine`]: the acquisition loop: move, HDR capture, calibrate, journal; Ctrl-C;
//! - [`predict`]: predicted exposures from the probe and the previous sample;
//! - [`estimate`]: how long a stage will take, with the HDR scheme it uses;
//! - [`inputs`]: content hashes of the inputs and the device identity, checked on resume;
//! - [`workflow`]: the paper's workflow behind `specula measure`;
//!   its steps' concepts in modules of their own: `connection` (the source and the
//!   instrument), `resume` (what a rerun must ask the same), `checks` (alignment and
//!   orientation), `observer`, `summary` and `deblur_record` (what a finished measurement
//!   reports);
//! - [`calibrate`]: the calibration behind `specula calibrate`, on any device;
//! - [`ideal`], [`pace`]: a noise-free simulated device, and a simulated one paced in real
//!   time.

pub mod calibrate;
mod calibration_text;
mod checks;
mod choices;
mod connection;
mod deblur_record;
pub mod engine;
pub mod estimate;
pub mod ideal;
pub mod inputs;
pub mod journal;
mod measure_request;
mod observer;
pub mod pace;
mod plan_request;
pub mod predict;
pub mod protocol;
mod resume;
mod sequential;
mod summary;
pub mod workflow;
pub mod workflow_error;

pub use calibration_text::{CalibrationText, CheckTable};
pub use journal::Stage;
pub use measure_request::{run_measure, MeasureError, MeasureRequest};
pub use plan_request::{run_plan, PlanError, PlanRequest, PlannedMeasurement, ThetaH};
