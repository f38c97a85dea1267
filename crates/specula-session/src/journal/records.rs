//! The journal's typed records: each value the `meta` table keeps, with its key
//! ([`Record::KEY`]), the stages of a session ([`Stage`]), and [`SessionRecord`], everything
//! a journal holds about its session read at once (for `specula session status` and the
//! report). No other module names a record or a stage by a string.

use super::{Journal, JournalError, SessionStatus};
use serde::{Deserialize, Serialize};
use specula_acquisition::calibration::Calibration;
use specula_acquisition::checks::alignment::AlignmentReport;
use specula_acquisition::checks::orientation::OrientationReport;
use specula_acquisition::instrument::InstrumentInfo;
use specula_core::sampling::{Family, SamplingFunction};
use specula_core::{GridSpec, ProbeSpec};
use specula_reconstruct::Method;
use std::path::Path;

/// A value the journal keeps under its own key in the `meta` table (JSON); the records read
/// back are also `DeserializeOwned`.
pub trait Record: Serialize {
    /// The record's key in the `meta` table.
    const KEY: &'static str;
}

/// A stage of samples of a session, each with its own plan in the journal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Stage {
    /// The dense theta_h column at the probe's theta_d and phi_d (paper 5.2).
    Probe,
    /// The main measurement: the grid of paper 5.3 placed with k-hat.
    Main,
}

impl Stage {
    /// The stages in the order a session measures them.
    pub const ALL: [Stage; 2] = [Stage::Probe, Stage::Main];

    /// The stage's name in the journal's tables.
    pub const fn name(self) -> &'static str {
        match self {
            Stage::Probe => "probe",
            Stage::Main => "main",
        }
    }

    /// The stage of a name in the journal's tables.
    pub fn from_name(name: &str) -> Option<Stage> {
        Stage::ALL.into_iter().find(|s| s.name() == name)
    }
}

impl rusqlite::ToSql for Stage {
    /// A stage is stored by its [`Stage::name`].
    fn to_sql(&self) -> rusqlite::Result<rusqlite::types::ToSqlOutput<'_>> {
        Ok(self.name().into())
    }
}

impl std::fmt::Display for Stage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// What a session measures, as the journal keeps it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SourceRecord {
    /// The simulated device with the ground truth of this name.
    Simulated {
        /// The truth's name (a preset, .toml, .binary or model:name).
        truth: String,
    },
    /// A device behind the driver protocol, known by the identity of its info reply (not its
    /// address, which may change between runs).
    Device {
        /// The device's model, from its info reply.
        model: String,
        /// The device's serial number, from its info reply.
        serial: String,
    },
}

impl SourceRecord {
    /// The name of the truth a simulated session measured; `None` for a real device.
    pub fn simulated_truth(&self) -> Option<&str> {
        match self {
            SourceRecord::Simulated { truth } => Some(truth),
            SourceRecord::Device { .. } => None,
        }
    }
}

impl std::fmt::Display for SourceRecord {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SourceRecord::Simulated { truth } => write!(f, "simulated: {truth}"),
            SourceRecord::Device { model, serial } => {
                write!(f, "device: {model} (serial {serial})")
            }
        }
    }
}

impl Record for SourceRecord {
    const KEY: &'static str = "source";
}

/// The device model of a session, as its TOML text (`Device::to_toml_string`).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct DeviceRecord(pub String);

impl Record for DeviceRecord {
    const KEY: &'static str = "device";
}

/// The specula version that started the session.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct VersionRecord(pub String);

impl Record for VersionRecord {
    const KEY: &'static str = "specula_version";
}

/// The newest specula version that wrote the session (the starting one until a newer build
/// resumes it; journals from before this record have only [`VersionRecord`]).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct NewestVersionRecord(pub String);

impl Record for NewestVersionRecord {
    const KEY: &'static str = "specula_version_newest";
}

/// When the journal was created, seconds since the Unix epoch.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct CreatedRecord(pub f64);

impl Record for CreatedRecord {
    const KEY: &'static str = "created_unix_s";
}

impl Record for InstrumentInfo {
    const KEY: &'static str = "instrument";
}

impl Record for Calibration {
    const KEY: &'static str = "calibration";
}

impl Record for AlignmentReport {
    const KEY: &'static str = "alignment_report";
}

impl Record for OrientationReport {
    const KEY: &'static str = "orientation_report";
}

impl Record for MeasureSettings {
    const KEY: &'static str = "settings";
}

impl Record for ChecksRecord {
    const KEY: &'static str = "checks";
}

impl Record for FitRecord {
    const KEY: &'static str = "fit";
}

impl Record for PlanRecord {
    const KEY: &'static str = "plan";
}

/// A reconstruction [`Method`] kept by its name ("lobe", "prior", "log", "linear").
mod method_name {
    use specula_reconstruct::Method;

    pub(super) fn serialize<S: serde::Serializer>(m: &Method, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(m)
    }

    pub(super) fn deserialize<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Method, D::Error> {
        let name = <String as serde::Deserialize>::deserialize(d)?;
        name.parse().map_err(serde::de::Error::custom)
    }
}

/// Execution order of the main plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PlanOrder {
    /// A short path through axis space ([`specula_acquisition::ordering`]).
    Optimized,
    /// theta_h, theta_d, phi_d loops, as the paper.
    Nested,
}

/// How HDR captures are chosen at each sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HdrChoice {
    /// Adaptive from a predicted rate.
    Predicted,
    /// The device file's fixed bracket at every sample (the paper's way).
    Bracket,
}

impl std::fmt::Display for PlanOrder {
    /// The name of `--order`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Optimized => "optimized",
            Self::Nested => "nested",
        })
    }
}

impl std::fmt::Display for HdrChoice {
    /// The name of `--hdr`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Predicted => "predicted",
            Self::Bracket => "bracket",
        })
    }
}

/// What a measurement is; kept in the journal, and a resumed session must ask the same.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MeasureSettings {
    /// Seed of the simulated device's positioning errors and noise.
    pub seed: u64,
    /// Noise-free camera, exact positioning, exact calibration (simulated devices only).
    pub ideal: bool,
    /// The simulated light as a point instead of its disk (which blurs sharp highlights as
    /// the real device's does).
    pub point_light: bool,
    /// Probe samples along theta_h (square-root placement, paper 5.2; [`ProbeSpec`]).
    pub probe_samples: usize,
    /// The theta_h sampling function's family (paper 5.1).
    pub family: Family,
    /// The main plan's grid (paper 5.3; [`GridSpec`]), kept flat in the journal. A journal
    /// written before the graded theta_d and the half turn of phi_d existed reads as the
    /// paper's shape (even theta_d, phi_d to 90 deg), the grid it was measured on. The
    /// orientation check may move the plan to another phi_h than the grid's.
    #[serde(flatten)]
    pub grid: GridSpec,
    /// The order the main plan's samples are taken in.
    pub order: PlanOrder,
    /// How each sample's HDR captures are chosen.
    pub hdr: HdrChoice,
    /// The reconstruction method (kept by its name: lobe, prior, log, linear).
    #[serde(with = "method_name")]
    pub method: Method,
    /// Fit the reconstruction and the probe through the instrument's response when it is
    /// known (always on the simulator): the BRDF before the blur of the light's disk.
    #[serde(default = "deblur_by_default")]
    pub deblur: bool,
    /// Run the alignment and orientation checks.
    pub checks: bool,
    /// The simulated sample's tilt on the turntable, degrees, and its azimuth.
    pub tilt_deg: f64,
    /// The simulated sample's tilt azimuth in the turntable frame, degrees.
    pub tilt_azimuth_deg: f64,
    /// Measure the main stage sequentially, batch by batch where the table is least sure,
    /// until one of these limits; `None` (and journals written before it existed): the whole
    /// grid, every position fixed before the first capture.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sequential: Option<SequentialSettings>,
}

/// When a sequential measurement stops (`crate::sequential`): the first limit reached.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SequentialSettings {
    /// The whole session's device time (checks, probe, main stage), hours.
    pub max_hours: f64,
    /// The main stage's samples.
    pub max_samples: usize,
    /// The median relative standard uncertainty (k = 1) of the cells within 75 deg at which
    /// the table is good enough; `None`: no such target.
    pub target_uncertainty_rel: Option<f64>,
}

impl Default for SequentialSettings {
    /// One hour per material, at most the paper's 4073 samples, no uncertainty target.
    fn default() -> Self {
        Self {
            max_hours: 1.0,
            max_samples: 4073,
            target_uncertainty_rel: None,
        }
    }
}

impl std::fmt::Display for SequentialSettings {
    /// `sequential, batch by batch where the table is least sure, until 1 h of device time or
    /// 4073 samples`, and the uncertainty target when there is one.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "sequential, batch by batch where the table is least sure, until {} h of device time or {} samples",
            self.max_hours, self.max_samples
        )?;
        match self.target_uncertainty_rel {
            Some(t) => write!(f, " or a median relative uncertainty of {} %", 100.0 * t),
            None => Ok(()),
        }
    }
}

/// One batch of a sequential measurement and why it was chosen.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BatchRecord {
    /// The main stage's samples before the batch.
    pub samples_before: usize,
    /// The batch's samples.
    pub samples: usize,
    /// The session's device time before the batch, seconds.
    pub device_s_before: f64,
    /// The batch's predicted device time, seconds.
    pub predicted_s: f64,
    /// The median relative standard uncertainty (k = 1) of the cells within 75 deg of the
    /// table before the batch; `None` for the first design, chosen before any table.
    pub median_uncertainty_rel: Option<f64>,
    /// Where the batch went: the candidate planes it added (`theta_d 33, 39 deg`), or for the
    /// first design its nodes (`8 of 16 theta_h x 12 of 50 theta_d x 4 of 7 phi_d`).
    #[serde(default)]
    pub planes: String,
}

/// A sequential measurement's decisions: its batches, and why it stopped.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SequenceRecord {
    /// The batches in the order they were chosen.
    pub batches: Vec<BatchRecord>,
    /// Why no further batch was chosen, once that was decided.
    pub stopped: Option<String>,
    /// The median relative standard uncertainty of the table after the last batch.
    pub final_median_uncertainty_rel: Option<f64>,
    /// The candidate nodes chosen so far on each axis (theta_h, theta_d, phi_d): what a
    /// resumed run decides from.
    pub chosen: Vec<Vec<bool>>,
}

impl Record for SequenceRecord {
    const KEY: &'static str = "sequence";
}

impl MeasureSettings {
    /// The probe (paper 5.2) at `phi_h_deg` (the planned one, or the orientation check's).
    pub fn probe(&self, phi_h_deg: f64) -> ProbeSpec {
        ProbeSpec {
            phi_h_deg,
            samples: self.probe_samples,
            ..ProbeSpec::paper()
        }
    }
}

impl Default for MeasureSettings {
    /// The paper's measurement (5.2) on the recommended grid ([`GridSpec::recommended`]),
    /// with our ordering and predicted exposures.
    fn default() -> Self {
        Self {
            seed: 1,
            ideal: false,
            point_light: false,
            probe_samples: ProbeSpec::paper().samples,
            family: Family::Exponential,
            grid: GridSpec::recommended(),
            order: PlanOrder::Optimized,
            hdr: HdrChoice::Predicted,
            method: Method::Lobe,
            deblur: true,
            checks: true,
            tilt_deg: 0.0,
            tilt_azimuth_deg: 0.0,
            sequential: None,
        }
    }
}

/// Deblurring is on for journals written before the setting existed.
fn deblur_by_default() -> bool {
    true
}

/// The checks' results as the journal keeps them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ChecksRecord {
    /// The tilt the alignment check fitted, degrees; `None` when it failed or was not run.
    pub tilt_deg: Option<f64>,
    /// Azimuth towards which the normal leans, degrees; `None` as for `tilt_deg`.
    pub tilt_azimuth_deg: Option<f64>,
    /// What the operator should do about the alignment, or why the check failed.
    pub alignment: String,
    /// Whether the orientation check found the BRDF anisotropic; `None` when it failed.
    pub anisotropic: Option<bool>,
    /// The phi_h the plan uses, degrees.
    pub plan_phi_h_deg: f64,
    /// What the orientation check said.
    pub orientation: String,
    /// Device time of the checks, seconds.
    pub device_s: f64,
}

/// The fit of k as the journal keeps it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FitRecord {
    /// The fitted theta_h sampling function: its family and k (paper 5.2).
    pub function: SamplingFunction,
    /// The fit error (docs/book/src/design.md), 1/sr.
    pub error: f64,
    /// The grid the main plan takes, chosen with the fit (`GridSpec::unresolved_peak`);
    /// `None` in records written before the choice existed: the settings' grid.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grid: Option<GridSpec>,
}

/// The main plan's counts as the journal keeps them (for a sequential measurement, its
/// candidates').
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PlanRecord {
    /// Samples in the main plan.
    pub total: usize,
    /// Samples with status `ok`.
    pub measurable: usize,
    /// Samples out of the axes' ranges (status `limit`).
    pub limit: usize,
    /// Samples blocked at every reachable position (status `occluded`).
    pub occluded: usize,
    /// The time model's estimate of the paper's way: nested order, fixed bracket, seconds.
    pub nested_bracket_s: f64,
}

/// Everything a journal holds about its session, read at once.
#[derive(Debug, Clone)]
pub struct SessionRecord {
    /// What was measured.
    pub source: Option<SourceRecord>,
    /// The measurement's settings.
    pub settings: Option<MeasureSettings>,
    /// The device model, as TOML text.
    pub device: Option<DeviceRecord>,
    /// The instrument that measured.
    pub instrument: Option<InstrumentInfo>,
    /// The specula version that started the session.
    pub version: Option<VersionRecord>,
    /// When the journal was created, seconds since the Unix epoch.
    pub created_unix_s: Option<f64>,
    /// The checks' results.
    pub checks: Option<ChecksRecord>,
    /// The fit of k (paper 5.2).
    pub fit: Option<FitRecord>,
    /// The main plan's counts (paper 5.3).
    pub plan: Option<PlanRecord>,
    /// A sequential measurement's batches and why it stopped.
    pub sequence: Option<SequenceRecord>,
    /// The stages' progress and the events.
    pub status: SessionStatus,
}

impl SessionRecord {
    /// Read the session's records from the journal at `path` (opened read-only).
    pub fn read(path: &Path) -> Result<Self, JournalError> {
        Self::of(&Journal::open_read_only(path)?)
    }

    /// Read the session's records from an open journal.
    pub fn of(journal: &Journal) -> Result<Self, JournalError> {
        Ok(SessionRecord {
            source: journal.record()?,
            settings: journal.record()?,
            device: journal.record()?,
            instrument: journal.record()?,
            version: journal.record()?,
            created_unix_s: journal.record::<CreatedRecord>()?.map(|c| c.0),
            checks: journal.record()?,
            fit: journal.record()?,
            plan: journal.record()?,
            sequence: journal.record()?,
            status: journal.status()?,
        })
    }

    /// The status of one stage, if it has a plan.
    pub fn stage(&self, stage: Stage) -> Option<&super::StageStatus> {
        self.status.stages.iter().find(|s| s.stage == stage)
    }
}
