//! The paper's measurement workflow in one call, as `specula measure` runs it (paper 4.2,
//! 4.3, 5.2, 5.3; docs/book/src/design.md, "Data flow"):
//!
//! 1. **calibration**: measured on the simulator with its white reference and ColorChecker
//!    (exact with `--ideal`), or read from a file for a real device;
//! 2. **checks**: alignment (the tilt from the highlight at several turntable rotations) and
//!    orientation (a phi_h free of the scratch lobe; when the planned one is not, the plan
//!    uses the recommended one, as turning the sample on its holder would);
//! 3. **probe**: the dense theta_h column at theta_d = 40, phi_d = 90 deg (section 5.2);
//! 4. **fit k** of the sampling function to the probe;
//! 5. **plan** the grid with k-hat ([`MeasureSettings::grid`]: the recommended one by
//!    default, the paper's 5.3 on request), reachability, occlusion and ordering;
//! 6. **acquire** it with predicted exposures ([`crate::engine`]);
//! 7. **reconstruct** the MERL table (each half of phi_d apart when the plan measured both,
//!    `specula_reconstruct::phi_d_halves`) and write it with a summary.
//!
//! Every result is kept in the session journal the first time it is made and read back
//! afterwards, so a rerun of the same command resumes where the last one stopped and, with
//! the same seed, writes byte for byte the same table as an uninterrupted run.

use crate::engine::{is_retryable, Engine, EngineSettings, HdrMode, Progress, StageOutcome};
use crate::estimate::{price_captures, PredictedExposures};
use crate::ideal::{exact_calibration, NoiselessSimulator};
use crate::inputs::{
    brdf_fingerprint, check_device, check_inputs, sha256_hex, DeviceIdentity, InputHashes,
};
pub use crate::journal::{
    ChecksRecord, FitRecord, HdrChoice, MeasureSettings, PlanOrder, PlanRecord,
};
use crate::journal::{
    DeviceRecord, Durability, Journal, JournalError, NewestVersionRecord, PlannedRow, SampleRecord,
    SourceRecord, Stage, VersionRecord, EVENT_COMPLETE,
};

use crate::pace::Paced;
use crate::predict::{Predictor, ProbeModel};
use crate::protocol::validate::ReplyRanges;
use crate::protocol::{ClientSettings, Endpoint, RemoteInstrument};
use crate::workflow_error::WorkflowError;
use serde::{Deserialize, Serialize};
use specula_acquisition::calibration::response::{measure_response, ResponseFit, ResponseOptions};
use specula_acquisition::calibration::{
    calibrate, mount_by_device, Calibration, CalibrationOptions,
};
use specula_acquisition::checks::alignment::{check_alignment, AlignmentSettings};
use specula_acquisition::checks::orientation::{check_orientation, OrientationSettings};
use specula_acquisition::checks::CheckError;
use specula_acquisition::device::Device;
use specula_acquisition::hdr::{HdrCapturer, HdrSettings};
use specula_acquisition::instrument::{Instrument, InstrumentError, InstrumentInfo};
use specula_acquisition::ordering::order;
use specula_acquisition::plan::Plan;
use specula_acquisition::response::InstrumentResponse;
use specula_acquisition::simulator::sample::{MountedSample, Tilt};
use specula_acquisition::simulator::{Simulator, SimulatorConfig};
use specula_core::grid::UnresolvedPeak;
use specula_core::sampling::{Family, SamplingFunction};
use specula_core::{Brdf, GridSpec, HalfDiff, ProbePoint, ProbeSpec, Rgb, Sample};
use specula_reconstruct::phi_d_halves::{measures_both_halves, reconstruct_halves};
use specula_reconstruct::provenance::sidecar_path;
use specula_reconstruct::Method;
use specula_reconstruct::{deblur_probe, DeblurredProbe};
use specula_sampling::{fit_k, Probe};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// Where the samples come from.
pub enum Source {
    /// The simulated device with a ground-truth BRDF.
    Simulated {
        /// The BRDF the simulated device measures.
        truth: Arc<dyn Brdf>,
        /// Runs the simulated clock in real time divided by this (rehearsals, tests).
        speedup: Option<f64>,
    },
    /// A device behind the driver protocol, with its calibration.
    Remote {
        /// Where the device's driver listens.
        endpoint: Endpoint,
        /// How the connection waits, retries and authenticates, and the ranges replies must lie in.
        client: ClientSettings,
        /// The device's calibration (`specula calibrate`).
        calibration: Box<Calibration>,
    },
}

/// A source whose device has answered: a remote device is reached before the journal is
/// opened, so that a failed connection leaves no session behind.
enum Reached {
    Simulated {
        truth: Arc<dyn Brdf>,
        speedup: Option<f64>,
    },
    Remote {
        remote: Box<RemoteInstrument>,
        calibration: Box<Calibration>,
    },
}

impl Reached {
    /// Reaches the device; a remote device's waits end early once `stop` is raised.
    fn reach(
        source: Source,
        device: &Device,
        settings: &MeasureSettings,
        stop: &Arc<AtomicBool>,
    ) -> Result<Self, WorkflowError> {
        Ok(match source {
            Source::Simulated { truth, speedup } => Reached::Simulated { truth, speedup },
            Source::Remote {
                endpoint,
                client,
                calibration,
            } => {
                if settings.ideal {
                    return Err(WorkflowError::IdealRemote { endpoint });
                }
                let client = ClientSettings {
                    ranges: ReplyRanges::for_device(device),
                    ..client
                };
                let mut remote =
                    RemoteInstrument::new(endpoint.clone(), client).with_stop(stop.clone());
                remote.info().map_err(|cause| WorkflowError::Unreachable {
                    endpoint: endpoint.clone(),
                    cause,
                })?;
                Reached::Remote {
                    remote: Box::new(remote),
                    calibration,
                }
            }
        })
    }
}

/// What the journal records as the measured thing: the simulated truth's name, or the
/// device's own identity from its info reply (not its address, which may change).
fn describe(truth: Option<String>, info: &InstrumentInfo) -> SourceRecord {
    match truth {
        Some(truth) => SourceRecord::Simulated { truth },
        None => SourceRecord::Device {
            model: info.model.clone(),
            serial: info.serial.clone(),
        },
    }
}

/// Hears what the workflow is doing (the CLI draws progress bars).
pub trait Observer {
    /// A step without samples of its own ("calibrating", "alignment check: ...").
    fn step(&mut self, message: &str);
    /// A stage of samples starts, `done` of `planned` already in the journal.
    fn stage_started(&mut self, stage: Stage, planned: usize, done: usize);
    /// A sample of the current stage is in the journal.
    fn sample(&mut self, progress: &Progress);
    /// The current stage ends, complete or stopped.
    fn stage_finished(&mut self, stage: Stage, outcome: &StageOutcome);
}

/// An observer that ignores everything.
pub struct Quiet;

impl Observer for Quiet {
    fn step(&mut self, _: &str) {}
    fn stage_started(&mut self, _: Stage, _: usize, _: usize) {}
    fn sample(&mut self, _: &Progress) {}
    fn stage_finished(&mut self, _: Stage, _: &StageOutcome) {}
}

/// What a finished measurement reports (the summary file, `key=value` lines).
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// What was measured: the simulated truth's name or the device's model and serial.
    pub source: String,
    /// The session journal.
    pub session: PathBuf,
    /// The reconstructed BRDF table written.
    pub out: PathBuf,
    /// The fitted k of the theta_h sampling function (paper 5.2).
    pub k_hat: f64,
    /// The fit error of k (docs/book/src/design.md, "Fitting k"), 1/sr.
    pub fit_error: f64,
    /// The sampling function's family (paper 5.1).
    pub family: Family,
    /// The alignment and orientation checks' results, when they ran.
    pub checks: Option<ChecksRecord>,
    /// The main plan's grid.
    pub grid: GridSpec,
    /// The main plan's counts.
    pub plan: PlanRecord,
    /// Probe samples measured (paper 5.2).
    pub probe_samples: usize,
    /// Main samples measured.
    pub measured_samples: usize,
    /// Raw captures of the main measurement.
    pub captures: usize,
    /// Main samples that are only lower bounds (saturated in every capture).
    pub lower_bounds: usize,
    /// Device time of checks, probe and main measurement, seconds.
    pub device_s: f64,
    /// Device time of the main measurement alone, seconds.
    pub main_device_s: f64,
    /// The time model's prediction for the main measurement, made before it ([`crate::estimate`]),
    /// seconds.
    pub predicted_main_s: f64,
    /// True when the device time is a simulated clock.
    pub simulated: bool,
    /// The reconstruction method.
    pub method: Method,
    /// Whether the samples measured both halves of phi_d and were reconstructed apart
    /// (`specula_reconstruct::phi_d_halves`).
    pub phi_d_halves: bool,
    /// The instrument's response the reconstruction went through, if any.
    pub deblur: Option<DeblurRecord>,
    /// Events in the journal by kind (faults, retries, resumptions).
    pub events: Vec<(String, usize)>,
    /// The table's uncertainty in summary lines
    /// ([`specula_reconstruct::uncertainty::CellUncertainty::lines`]).
    pub uncertainty: Vec<String>,
}

impl Summary {
    /// The summary as `key=value` lines.
    pub fn lines(&self) -> Vec<String> {
        let mut lines = vec![
            format!("source={}", self.source),
            format!("session={}", self.session.display()),
            format!("out={}", self.out.display()),
            format!("family={}", self.family),
            format!("k_hat={:.4}", self.k_hat),
            format!("fit_error={:.6e}", self.fit_error),
        ];
        if let Some(checks) = &self.checks {
            if let Some(tilt) = checks.tilt_deg {
                lines.push(format!("alignment_tilt_deg={tilt:.4}"));
            }
            lines.push(format!("alignment={}", checks.alignment));
            lines.push(format!("orientation={}", checks.orientation));
            lines.push(format!("phi_h_deg={}", checks.plan_phi_h_deg));
        }
        let hours = |s: f64| s / 3600.0;
        lines.extend([
            format!("grid={}", self.grid),
            format!("planned_samples={}", self.plan.total),
            format!("excluded_limit={}", self.plan.limit),
            format!("excluded_occluded={}", self.plan.occluded),
            format!("probe_samples={}", self.probe_samples),
            format!("measured_samples={}", self.measured_samples),
            format!("captures={}", self.captures),
            format!(
                "captures_per_sample={:.3}",
                self.captures as f64 / self.measured_samples.max(1) as f64
            ),
            format!("lower_bound_samples={}", self.lower_bounds),
        ]);
        let clock = if self.simulated {
            "simulated"
        } else {
            "device"
        };
        lines.push(format!("{clock}_hours={:.3}", hours(self.device_s)));
        lines.push(format!(
            "predicted_main_hours={:.3}",
            hours(self.predicted_main_s)
        ));
        lines.push(format!(
            "{clock}_main_hours={:.3}",
            hours(self.main_device_s)
        ));
        lines.push(format!(
            "model_nested_bracket_hours={:.3}",
            hours(self.plan.nested_bracket_s)
        ));
        lines.push(format!("method={}", self.method));
        lines.push(format!("phi_d_halves={}", self.phi_d_halves));
        match &self.deblur {
            Some(d) => lines.extend(d.lines()),
            None => lines.push("deblurred=false".into()),
        }
        lines.extend(self.uncertainty.iter().cloned());
        for (kind, count) in &self.events {
            lines.push(format!("events_{kind}={count}"));
        }
        lines
    }
}

/// What the fit through the instrument's response found, for the summary and the report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DeblurRecord {
    /// The light's angular radius of the response, degrees.
    pub light_radius_deg: f64,
    /// How it was known ("exact (the simulator's own response)" or the reference measured).
    pub measured_with: String,
    /// The instrument's resolution in theta_h, degrees.
    pub resolution_deg: f64,
    /// The fitted lobe's half width at half maximum in theta_h, degrees.
    pub peak_half_width_deg: Option<f64>,
    /// What the checks of the deblurred table found, as summary lines
    /// ([`specula_reconstruct::safeguard::Safeguard::lines`]).
    #[serde(default)]
    pub checks: Vec<String>,
    /// Below this theta_h (degrees) the table holds the un-deblurred values, because the
    /// deblurred ones failed a check.
    #[serde(default)]
    pub fallback_below_deg: Option<f64>,
    /// True when the deblurred table failed a check ([`specula_reconstruct::safeguard`]).
    #[serde(default)]
    pub check_failed: bool,
}

impl DeblurRecord {
    /// Of a response and the reconstruction made through it.
    pub fn new(fit: &ResponseFit, reconstruction: &specula_reconstruct::Reconstruction) -> Self {
        let safeguard = reconstruction.safeguard.as_ref();
        Self {
            light_radius_deg: fit.response.light.radius_deg,
            measured_with: fit.reference.clone(),
            resolution_deg: fit.response.resolution_deg(),
            peak_half_width_deg: reconstruction.lobe.map(|l| l.shape.half_width_deg()),
            checks: safeguard.map_or_else(Vec::new, |s| s.lines()),
            fallback_below_deg: safeguard.and_then(|s| s.fallback_below_deg),
            check_failed: safeguard.is_some_and(|s| s.failed()),
        }
    }

    /// True when the peak is at least as wide as the instrument resolves and the deblurred
    /// table passed its checks.
    pub fn resolved(&self) -> bool {
        !self.check_failed
            && self
                .peak_half_width_deg
                .is_some_and(|w| w >= self.resolution_deg)
    }

    /// One sentence: the resolution and whether the peak is resolved.
    pub fn describe(&self) -> String {
        let resolution = format!("resolution {:.3} deg in theta_h", self.resolution_deg);
        match self.peak_half_width_deg {
            _ if self.check_failed && self.fallback_below_deg.is_none() => format!(
                "{resolution}; the deblurred table does not reproduce its samples within their uncertainty, so its peak is not a measurement"
            ),
            _ if self.fallback_below_deg.is_some() => format!(
                "{resolution}; the deblurred peak did not reproduce the samples, so theta_h below {:.2} deg holds the values as measured (a bound, not a measurement)",
                self.fallback_below_deg.unwrap_or_default()
            ),
            Some(w) if self.resolved() => {
                format!("{resolution}; the peak's half width {w:.3} deg is resolved")
            }
            Some(w) => format!(
                "{resolution}; the peak's half width {w:.3} deg is narrower than that: a bound, not a measurement"
            ),
            None => resolution,
        }
    }

    /// The summary's lines.
    pub fn lines(&self) -> Vec<String> {
        let mut lines = vec![
            "deblurred=true".to_string(),
            format!("response_light_radius_deg={:.4}", self.light_radius_deg),
            format!("response_measured_with={}", self.measured_with),
            format!("resolution_deg={:.4}", self.resolution_deg),
        ];
        if let Some(w) = self.peak_half_width_deg {
            lines.push(format!("peak_half_width_deg={w:.4}"));
            lines.push(if self.resolved() {
                "peak_resolved=true".into()
            } else if let Some(limit) = self.fallback_below_deg {
                format!(
                    "peak_resolved=false (the deblurred peak failed its checks: theta_h below {limit:.2} deg holds the values as measured, a bound at the instrument's resolution)"
                )
            } else if self.check_failed {
                "peak_resolved=false (the deblurred table does not reproduce its samples within their uncertainty: see deblur_fallback; its peak is not a measurement)".into()
            } else {
                format!(
                    "peak_resolved=false (the peak is narrower than the instrument's resolution of {:.2} deg: its width is a bound, not a measurement)",
                    self.resolution_deg
                )
            });
        }
        lines.extend(self.checks.iter().cloned());
        lines
    }
}

/// How a call to [`measure`] ended.
#[derive(Debug, Clone, PartialEq)]
pub enum MeasureOutcome {
    /// Every stage finished and the table was written.
    Complete(Box<Summary>),
    /// Stopped by the stop flag; the same call resumes.
    Stopped {
        /// The stage that was running.
        stage: String,
        /// Its samples in the journal.
        done: usize,
        /// Samples in its plan.
        planned: usize,
    },
}

/// The summary file beside the table: `OUT.summary.txt`.
pub fn summary_path(out: &Path) -> PathBuf {
    out.with_extension("summary.txt")
}

/// The default session journal beside the table: `OUT.session.sqlite`.
pub fn default_session_path(out: &Path) -> PathBuf {
    out.with_extension("session.sqlite")
}

/// The instrument and what goes with it.
struct Connected {
    instrument: Box<dyn Instrument>,
    calibration: Calibration,
    link_notes: Option<crate::protocol::client::LinkNotes>,
    simulated: bool,
    /// The name the device gave in `hello` (a remote device only).
    server: Option<String>,
}

/// The content hashes of what a session measures from (see [`crate::inputs`]).
fn input_hashes(source: &Source, device: &Device) -> InputHashes {
    let (truth, calibration) = match source {
        Source::Simulated { truth, .. } => (Some(brdf_fingerprint(truth.as_ref())), None),
        Source::Remote { calibration, .. } => {
            let json = serde_json::to_vec(calibration.as_ref()).unwrap_or_default();
            (None, Some(sha256_hex(&json)))
        }
    };
    InputHashes {
        truth,
        device_model: sha256_hex(device.to_toml_string().as_bytes()),
        calibration,
    }
}

/// Runs the whole workflow (see the module documentation) into `session`, writing `out` and
/// its summary when complete.
pub fn measure(
    source: Source,
    device: &Device,
    settings: &MeasureSettings,
    session: &Path,
    out: &Path,
    stop: Arc<AtomicBool>,
    observer: &mut dyn Observer,
) -> Result<MeasureOutcome, WorkflowError> {
    let method = settings.method;
    let truth = match &source {
        Source::Simulated { truth, .. } => Some(truth.name()),
        Source::Remote { .. } => None,
    };
    let hashes = input_hashes(&source, device);
    let reached = Reached::reach(source, device, settings, &stop)?;
    let mut journal = Journal::open(session)?;
    check_version(&journal)?;
    if truth.is_some() {
        journal.set_durability(Durability::Crash)?;
    }
    let mut connected = connect(reached, device, settings, &journal, &stop, observer)?;
    let info = connected
        .instrument
        .info()
        .map_err(WorkflowError::device("cannot describe the device"))?;
    let description = describe(truth, &info);
    start_session(&journal, settings, &description, device)?;
    check_inputs(&journal, &hashes)?;
    let identity = DeviceIdentity {
        server: connected.server.clone(),
        info: info.clone(),
    };
    check_device(&journal, &identity)?;
    journal.put_record(&info)?;
    let calibration = connected.calibration.clone();
    let response_fit = calibration.response.clone().filter(|_| settings.deblur);
    let response = response_fit.as_ref().map(|r| r.response.clone());
    let mut hdr = HdrCapturer::new(HdrSettings::for_device(&info), calibration.noise);

    let checks = if settings.checks {
        Some(run_checks(
            &mut journal,
            connected.instrument.as_mut(),
            &mut hdr,
            device,
            settings,
            observer,
        )?)
    } else {
        None
    };
    let phi_h_deg = checks
        .as_ref()
        .map_or(settings.grid.phi_h_deg, |c| c.plan_phi_h_deg);
    let mut engine = Engine {
        instrument: connected.instrument.as_mut(),
        journal: &mut journal,
        hdr: &mut hdr,
        calibration: &calibration,
        settings: EngineSettings {
            hdr: hdr_mode(settings, device),
            ..EngineSettings::default()
        },
        stop,
        link_notes: connected.link_notes.clone(),
    };

    // The probe (5.2), then k-hat.
    let probe_rows = probe_plan(device, settings, phi_h_deg);
    engine.journal.set_plan(Stage::Probe, &probe_rows)?;
    let outcome = run_stage(
        &mut engine,
        Stage::Probe,
        &Predictor::new(calibration.clone(), None),
        observer,
    )?;
    if !outcome.complete() {
        return Ok(stopped(Stage::Probe, &outcome));
    }
    let probe = probe_samples(engine.journal)?;
    let fit = match engine.journal.record::<FitRecord>()? {
        Some(stored) => stored,
        None => {
            let fit = fit_probe(&probe, settings, response.as_ref(), phi_h_deg, device)?;
            engine.journal.put_record(&fit)?;
            fit
        }
    };
    let grid = fit.grid.unwrap_or(settings.grid);
    observer.step(&format!(
        "k-hat = {:.3} ({})",
        fit.function.k, fit.function.family
    ));
    if grid.theta_h_samples != settings.grid.theta_h_samples {
        observer.step(&format!(
            "the peak is narrower than the instrument resolves: the plan takes {} theta_h positions",
            grid.theta_h_samples
        ));
    }

    // The plan (5.3) with k-hat, then the acquisition.
    let predictor = Predictor::new(calibration.clone(), ProbeModel::new(&probe));
    let plan = main_plan(
        engine.journal,
        device,
        &MainPlanSpec {
            grid: &grid,
            function: &fit.function,
            phi_h_deg,
            order: settings.order,
            hdr: settings.hdr,
        },
        &PredictedExposures {
            predictor: &predictor,
            capturer: engine.hdr,
        },
        observer,
    )?;
    let outcome = run_stage(&mut engine, Stage::Main, &predictor, observer)?;
    if !outcome.complete() {
        return Ok(stopped(Stage::Main, &outcome));
    }

    observer.step("reconstructing");
    let main = engine.journal.samples(Stage::Main)?;
    let samples = measured_samples(&engine.journal.plan(Stage::Main)?, &main);
    let name = out
        .file_stem()
        .map_or_else(|| "measured".into(), |s| s.to_string_lossy().into_owned());
    let halves = measures_both_halves(&samples);
    let result = reconstruct_halves(&samples, method, &name, response.as_ref())
        .map_err(|cause| WorkflowError::Reconstruct { cause })?;
    let deblur = response_fit
        .as_ref()
        .filter(|_| result.resolution_deg.is_some())
        .map(|fit| DeblurRecord::new(fit, &result));
    let uncertainty = crate::measured_uncertainty::of_measurement(
        &engine.journal.plan(Stage::Main)?,
        &main,
        &samples,
        method,
        &result,
    )
    .map_err(|cause| WorkflowError::Reconstruct { cause })?;
    specula_core::atomic_file::write_together(&[
        (out, &result.brdf.to_bytes()),
        (&sidecar_path(out), &result.provenance.to_npy()),
        (
            &specula_reconstruct::uncertainty::sidecar_path(out),
            &uncertainty.absolute(&result.brdf).to_bytes(),
        ),
    ])?;

    let summary = Summary {
        uncertainty: uncertainty.lines(),
        ..summarise(
            &journal,
            session,
            out,
            description.to_string(),
            &fit,
            checks,
            plan,
            connected.simulated,
            settings,
            halves,
            deblur,
        )?
    };
    let text = summary.lines().join("\n") + "\n";
    let path = summary_path(out);
    specula_core::atomic_file::write_bytes(&path, text.as_bytes()).map_err(|cause| {
        WorkflowError::WriteSummary {
            path: path.clone(),
            cause,
        }
    })?;
    journal.log_event(EVENT_COMPLETE, &format!("wrote {}", out.display()))?;
    journal.close()?;
    Ok(MeasureOutcome::Complete(Box::new(summary)))
}

/// The grid an existing session journal measures on, `None` when `session` does not exist
/// yet or holds no settings. A front end resumes on it unless told another grid (which
/// [`measure`] then refuses as a change of settings): a journal written before the graded
/// theta_d and the half turn of phi_d continues on the paper's grid it started with, not on
/// today's default. A session another process is writing is refused
/// ([`Journal::refuse_in_use`]).
pub fn session_grid(session: &Path) -> Result<Option<GridSpec>, WorkflowError> {
    if !session.exists() {
        return Ok(None);
    }
    Journal::refuse_in_use(session)?;
    let journal = Journal::open_read_only(session)?;
    Ok(journal.record::<MeasureSettings>()?.map(|s| s.grid))
}

/// Records the settings of a new session, or checks that a resumed one asks the same.
fn start_session(
    journal: &Journal,
    settings: &MeasureSettings,
    source: &SourceRecord,
    device: &Device,
) -> Result<(), WorkflowError> {
    let session = journal.path().display().to_string();
    let stored: MeasureSettings = journal.record_or_insert(|| settings.clone())?;
    if stored != *settings {
        return Err(WorkflowError::Settings {
            session,
            differences: differences(&stored, settings),
        });
    }
    let stored_source = journal.record_or_insert(|| source.clone())?;
    if stored_source != *source {
        return Err(WorkflowError::Source {
            session,
            stored: stored_source,
            asked: source.clone(),
        });
    }
    let stored_device = journal.record_or_insert(|| DeviceRecord(device.to_toml_string()))?;
    if stored_device.0 != device.to_toml_string() {
        return Err(WorkflowError::DeviceModel { session });
    }
    journal.record_or_insert(|| VersionRecord(THIS_VERSION.to_string()))?;
    Ok(())
}

/// This build's version.
const THIS_VERSION: &str = env!("CARGO_PKG_VERSION");

/// Refuses a session written by a newer specula (same schema, but an older build may measure
/// or reconstruct it differently); a session from an older one is resumed, and this build
/// recorded as its newest writer (with an event saying so).
fn check_version(journal: &Journal) -> Result<(), WorkflowError> {
    let newest = match journal.record::<NewestVersionRecord>()? {
        Some(NewestVersionRecord(v)) => Some(v),
        None => journal.record::<VersionRecord>()?.map(|VersionRecord(v)| v),
    };
    match newest.as_deref() {
        Some(v) if v == THIS_VERSION => return Ok(()),
        Some(v) if !is_older_version(v, THIS_VERSION) => {
            return Err(WorkflowError::NewerVersion {
                session: journal.path().display().to_string(),
                journal: v.to_string(),
                this: THIS_VERSION.to_string(),
            })
        }
        Some(v) => journal.log_event(
            "version",
            &format!("resumed by specula {THIS_VERSION}; last written by specula {v}"),
        )?,
        None => {}
    }
    journal.put_record(&NewestVersionRecord(THIS_VERSION.to_string()))?;
    Ok(())
}

/// Whether version `a` comes before `b` (dotted numbers, compared number by number; a
/// pre-release or build suffix after `-` or `+` is ignored). A version that does not read
/// as dotted numbers is not older.
fn is_older_version(a: &str, b: &str) -> bool {
    let numbers = |v: &str| -> Option<Vec<u64>> {
        v.split(['-', '+'])
            .next()?
            .split('.')
            .map(|n| n.parse().ok())
            .collect()
    };
    match (numbers(a), numbers(b)) {
        (Some(a), Some(b)) => a < b,
        _ => false,
    }
}

/// The settings that differ, in words: `SETTING: SESSION'S in the session, ASKED asked`,
/// joined by `; ` (the grid's parts one by one, each as its option reads).
fn differences(stored: &MeasureSettings, asked: &MeasureSettings) -> String {
    let mut found = Vec::new();
    let mut differ = |name: &str, a: String, b: String| {
        if a != b {
            found.push(format!("{name}: {a} in the session, {b} asked"));
        }
    };
    let yes_no = |v: bool| if v { "on" } else { "off" }.to_string();
    differ("--seed", stored.seed.to_string(), asked.seed.to_string());
    differ("--ideal", yes_no(stored.ideal), yes_no(asked.ideal));
    differ(
        "--point-light",
        yes_no(stored.point_light),
        yes_no(asked.point_light),
    );
    differ(
        "--probe-samples",
        stored.probe_samples.to_string(),
        asked.probe_samples.to_string(),
    );
    differ(
        "--family",
        stored.family.to_string(),
        asked.family.to_string(),
    );
    grid_differences(&stored.grid, &asked.grid, &mut differ);
    differ("--order", stored.order.to_string(), asked.order.to_string());
    differ("--hdr", stored.hdr.to_string(), asked.hdr.to_string());
    differ(
        "--method",
        stored.method.to_string(),
        asked.method.to_string(),
    );
    differ(
        "deblurring (--no-deblur)",
        yes_no(stored.deblur),
        yes_no(asked.deblur),
    );
    differ(
        "the checks (--skip-checks)",
        yes_no(stored.checks),
        yes_no(asked.checks),
    );
    let deg = |v: f64| format!("{v} deg");
    differ("--tilt", deg(stored.tilt_deg), deg(asked.tilt_deg));
    differ(
        "--tilt-azimuth",
        deg(stored.tilt_azimuth_deg),
        deg(asked.tilt_azimuth_deg),
    );
    found.join("; ")
}

/// The grid's parts that differ, named as the options that set them.
fn grid_differences(
    stored: &GridSpec,
    asked: &GridSpec,
    differ: &mut dyn FnMut(&str, String, String),
) {
    differ(
        "--theta-h-samples",
        stored.theta_h_samples.to_string(),
        asked.theta_h_samples.to_string(),
    );
    differ(
        "--theta-d-step",
        stored.theta_d.to_string(),
        asked.theta_d.to_string(),
    );
    let deg = |v: f64| format!("{v} deg");
    differ(
        "--phi-d-step",
        deg(stored.phi_d_step_deg),
        deg(asked.phi_d_step_deg),
    );
    differ(
        "--phi-d-span",
        stored.phi_d_span.to_string(),
        asked.phi_d_span.to_string(),
    );
    differ("--phi-h", deg(stored.phi_h_deg), deg(asked.phi_h_deg));
    let peak = |rule: &Option<UnresolvedPeak>| match rule {
        Some(rule) => format!(
            "up to {} theta_h with theta_d step {} deg within {} samples",
            rule.theta_h_samples, rule.theta_d, rule.budget_samples
        ),
        None => "none".to_string(),
    };
    differ(
        "the rule for a peak the instrument does not resolve (--grid-preset)",
        peak(&stored.unresolved_peak),
        peak(&asked.unresolved_peak),
    );
}

/// Opens the instrument and finds its calibration (the journal's, once there is one).
fn connect(
    source: Reached,
    device: &Device,
    settings: &MeasureSettings,
    journal: &Journal,
    stop: &Arc<AtomicBool>,
    observer: &mut dyn Observer,
) -> Result<Connected, WorkflowError> {
    match source {
        Reached::Simulated { truth, speedup } => {
            let mut config = SimulatorConfig::new(settings.seed, device);
            if settings.point_light {
                config.response =
                    InstrumentResponse::point(device.light.distance_m, device.camera.distance_m);
            }
            let tilt = if settings.ideal {
                config.positioning.sigma_deg = 0.0;
                Tilt::default()
            } else {
                Tilt::new(settings.tilt_deg, settings.tilt_azimuth_deg)
            };
            let sample = MountedSample::new(truth.name(), truth, tilt);
            let true_response = config.response.clone();
            let mut simulator = Simulator::new(device.clone(), sample.clone(), config);
            let calibration = match journal.record::<Calibration>()? {
                Some(stored) => stored,
                None => {
                    let calibration = if settings.ideal {
                        let model = simulator.info()?.model;
                        let mut c = exact_calibration(&simulator.config().camera, &model);
                        c.response = Some(ResponseFit::exact(true_response));
                        c
                    } else {
                        observer.step("calibrating: white reference and ColorChecker");
                        let mut c = calibrate(
                            &mut simulator,
                            mount_by_device,
                            &CalibrationOptions::default(),
                        )
                        .map_err(|cause| WorkflowError::Calibration { cause })?;
                        c.response = Some(if settings.point_light {
                            ResponseFit::exact(true_response)
                        } else {
                            observer.step("calibrating: the response, a mirror across the light");
                            simulated_response(&mut simulator, &c, device)?
                        });
                        simulator.mount_sample(sample);
                        c
                    };
                    journal.put_record(&calibration)?;
                    calibration
                }
            };
            let instrument: Box<dyn Instrument> = match (settings.ideal, speedup) {
                (true, Some(s)) => Box::new(
                    Paced::new(NoiselessSimulator::new(simulator), s).with_stop(stop.clone()),
                ),
                (true, None) => Box::new(NoiselessSimulator::new(simulator)),
                (false, Some(s)) => Box::new(Paced::new(simulator, s).with_stop(stop.clone())),
                (false, None) => Box::new(simulator),
            };
            Ok(Connected {
                instrument,
                calibration,
                link_notes: None,
                simulated: true,
                server: None,
            })
        }
        Reached::Remote {
            remote,
            calibration,
        } => {
            let calibration = *calibration;
            let stored: Calibration = journal.record_or_insert(|| calibration.clone())?;
            if stored != calibration {
                return Err(WorkflowError::Calibrated {
                    session: journal.path().to_path_buf(),
                });
            }

            let notes = remote.notes();
            let simulated = remote.simulated_clock_s().is_some();
            let server = remote.server_name().map(str::to_string);
            Ok(Connected {
                instrument: remote,
                calibration,
                link_notes: Some(notes),
                simulated,
                server,
            })
        }
    }
}

/// The response measured on the simulator with the reference mirror
/// ([`measure_response`]).
pub fn simulated_response(
    simulator: &mut Simulator,
    calibration: &Calibration,
    device: &Device,
) -> Result<ResponseFit, WorkflowError> {
    let info = simulator.info()?;
    let mut hdr = HdrCapturer::new(HdrSettings::for_device(&info), calibration.noise);
    measure_response(
        simulator,
        mount_by_device,
        &mut hdr,
        calibration,
        &device.response(),
        &ResponseOptions::default(),
    )
    .map_err(|cause| WorkflowError::Response { cause })
}

fn hdr_mode(settings: &MeasureSettings, device: &Device) -> HdrMode {
    match settings.hdr {
        HdrChoice::Predicted => HdrMode::Predicted,
        HdrChoice::Bracket => HdrMode::Bracket {
            exposures_s: device.capture.exposures_s.clone(),
            light_levels: device.capture.light_levels.clone(),
        },
    }
}

/// Alignment and orientation (paper 4.2, 4.3), once per session.
fn run_checks(
    journal: &mut Journal,
    instrument: &mut dyn Instrument,
    hdr: &mut HdrCapturer,
    device: &Device,
    settings: &MeasureSettings,
    observer: &mut dyn Observer,
) -> Result<ChecksRecord, WorkflowError> {
    if let Some(stored) = journal.record::<ChecksRecord>()? {
        return Ok(stored);
    }
    let clock = |i: &dyn Instrument| i.simulated_clock_s();
    let started = (clock(instrument), std::time::Instant::now());
    observer.step("alignment check: the highlight at 8 turntable rotations");
    instrument
        .home()
        .map_err(WorkflowError::device("homing the device"))?;
    let alignment = with_retries(journal, instrument, hdr, "alignment check", |i, h| {
        check_alignment(i, h, &AlignmentSettings::default())
    })?;
    let (tilt_deg, tilt_azimuth_deg, alignment) = match alignment {
        Ok(report) => {
            journal.put_record(&report)?;
            let advice = report.adjustment(device.accuracy_deg);
            (
                Some(report.fit.tilt_deg),
                Some(report.fit.azimuth_deg),
                advice,
            )
        }
        Err(e) => (None, None, format!("inconclusive: {e}")),
    };
    observer.step(&format!("alignment: {alignment}"));
    observer.step("orientation check: rings of phi_h for the scratch lobe");
    let orientation_settings = OrientationSettings {
        planned_phi_h_deg: settings.grid.phi_h_deg,
        ..OrientationSettings::default()
    };
    let orientation = with_retries(journal, instrument, hdr, "orientation check", |i, h| {
        check_orientation(i, h, device, &orientation_settings)
    })?;
    let (anisotropic, plan_phi_h_deg, orientation) = match orientation {
        Ok(report) => {
            journal.put_record(&report)?;
            if report.planned_is_clean {
                let what = if report.anisotropic {
                    "anisotropic, but"
                } else {
                    "isotropic:"
                };
                (
                    Some(report.anisotropic),
                    settings.grid.phi_h_deg,
                    format!("{what} phi_h {} deg is clean", settings.grid.phi_h_deg),
                )
            } else {
                let chosen = report.recommended_phi_h_deg;
                let message = format!(
                    "scratch lobe at phi_h {} deg: measuring at phi_h {chosen} deg instead (turn the sample by {:.1} deg to keep {})",
                    settings.grid.phi_h_deg,
                    report.turn_sample_deg(),
                    settings.grid.phi_h_deg
                );
                (Some(true), chosen, message)
            }
        }
        Err(e) => (None, settings.grid.phi_h_deg, format!("inconclusive: {e}")),
    };
    observer.step(&format!("orientation: {orientation}"));
    let device_s = match (started.0, clock(instrument)) {
        (Some(a), Some(b)) => b - a,
        _ => started.1.elapsed().as_secs_f64(),
    };
    let record = ChecksRecord {
        tilt_deg,
        tilt_azimuth_deg,
        alignment,
        anisotropic,
        plan_phi_h_deg,
        orientation,
        device_s,
    };
    journal.put_record(&record)?;
    Ok(record)
}

/// Runs a check with the acquisition's retries: after a fault that another try may cure
/// ([`is_retryable`]; the axes homed after a motor fault) the check starts again, up to the
/// engine's [`EngineSettings::max_attempts`] tries, each fault journaled. A check that still
/// cannot run is an error (the user may skip the checks); one that ran but found nothing
/// (no highlight, say) comes back as `Ok(Err(..))`, recorded as inconclusive.
fn with_retries<T>(
    journal: &Journal,
    instrument: &mut dyn Instrument,
    hdr: &mut HdrCapturer,
    what: &str,
    mut check: impl FnMut(&mut dyn Instrument, &mut HdrCapturer) -> Result<T, CheckError>,
) -> Result<Result<T, CheckError>, WorkflowError> {
    let max_attempts = EngineSettings::default().max_attempts;
    let mut attempts = 0;
    loop {
        attempts += 1;
        let error = match check(instrument, hdr) {
            Err(CheckError::Instrument(error)) => error,
            done => return Ok(done),
        };
        journal.log_event("fault", &format!("{what} try {attempts}: {error}"))?;
        if !is_retryable(&error) || attempts >= max_attempts {
            return Err(WorkflowError::Check {
                check: what.to_string(),
                cause: error,
                attempts,
            });
        }
        hdr.forget_light_level();
        if matches!(error, InstrumentError::MotorFault(_)) {
            instrument.home().map_err(WorkflowError::device(format!(
                "{what}: homing the device after a motor fault"
            )))?;
            journal.log_event("recovered", "homed the axes")?;
        }
    }
}

/// The probe's samples (paper 5.2, [`MeasureSettings::probe`]) as a stage plan:
/// square-root theta_h in increasing order; the ones the device cannot take are left out.
fn probe_plan(device: &Device, settings: &MeasureSettings, phi_h_deg: f64) -> Vec<PlannedRow> {
    let probe = settings.probe(phi_h_deg);
    let hds: Vec<HalfDiff> = probe
        .theta_h_deg()
        .into_iter()
        .map(|theta_h| probe.half_diff(theta_h))
        .collect();
    rows_of(&Plan::from_half_diffs(&hds, device))
}

/// The measurable samples of a plan as journal rows, in execution order.
fn rows_of(plan: &Plan) -> Vec<PlannedRow> {
    plan.measured()
        .enumerate()
        .map(|(seq, (s, axes))| PlannedRow {
            seq: seq as u32,
            hd: s.hd,
            axes,
            predicted_s: s.time_s,
        })
        .collect()
}

/// The measured samples of the main stage of the session at `path` (opened read-only), in
/// plan order, and the instrument's response its calibration holds, if any: what
/// `specula reconstruct --session` rebuilds. A session without main samples is an error.
pub fn session_main_samples(
    path: &Path,
) -> Result<(Vec<Sample>, Option<InstrumentResponse>), WorkflowError> {
    let journal = Journal::open_read_only(path)?;
    let response = journal
        .record::<Calibration>()?
        .and_then(|c| c.response)
        .map(|fit| fit.response);
    let plan = journal.plan(Stage::Main)?;
    let samples = measured_samples(&plan, &journal.samples(Stage::Main)?);
    if samples.is_empty() {
        return Err(WorkflowError::NoMainSamples {
            session: path.to_path_buf(),
        });
    }
    Ok((samples, response))
}

/// The probe's samples as points, in increasing theta_h.
pub fn probe_samples(journal: &Journal) -> Result<Vec<ProbePoint>, JournalError> {
    let rows = journal.plan(Stage::Probe)?;
    let samples = journal.samples(Stage::Probe)?;
    let mut probe: Vec<ProbePoint> = rows
        .iter()
        .filter_map(|r| {
            samples
                .get(&r.seq)
                .map(|s| ProbePoint::new(r.hd.theta_h.to_degrees(), s.value.max(Rgb::ZERO)))
        })
        .collect();
    probe.sort_by(|a, b| a.theta_h_deg.total_cmp(&b.theta_h_deg));
    Ok(probe)
}

/// k-hat of the settings' family for the probe (paper 5.2), deblurred first when the
/// response is known ([`deblurred_probe`]), so that k adapts to the material; and the grid
/// the plan takes ([`GridSpec::for_material`]: more theta_h where the deblurred peak is
/// narrower than the instrument's resolution, each candidate with k fitted for its theta_h
/// count).
fn fit_probe(
    probe: &[ProbePoint],
    settings: &MeasureSettings,
    response: Option<&InstrumentResponse>,
    phi_h_deg: f64,
    device: &Device,
) -> Result<FitRecord, WorkflowError> {
    let response = response.filter(|r| !r.is_point());
    let deblurred = response.map(|r| deblurred_probe(probe, r, phi_h_deg));
    let unresolved = deblurred
        .as_ref()
        .zip(response)
        .is_some_and(|(d, r)| d.peak_unresolved(r.resolution_deg()));
    let points = deblurred.map_or_else(|| probe.to_vec(), |d| d.points);
    let (theta_h, values): (Vec<f64>, Vec<Rgb>) =
        points.iter().map(|p| (p.theta_h_deg, p.value)).unzip();
    let probe =
        Probe::new(theta_h, values).map_err(|cause| WorkflowError::ProbeColumn { cause })?;
    let fit_on = |grid: GridSpec| -> Result<FitRecord, WorkflowError> {
        let fit = fit_k(&probe.column(), settings.family, grid.theta_h_samples)
            .map_err(|cause| WorkflowError::ProbeFit { cause })?;
        Ok(FitRecord {
            function: fit.function,
            error: fit.error,
            grid: Some(grid),
        })
    };
    let grid = settings.grid.for_material(unresolved, |grid| {
        let fit = fit_on(*grid)?;
        Ok::<_, WorkflowError>(
            nested_plan(device, grid, &fit.function, phi_h_deg)
                .measured()
                .count(),
        )
    })?;
    fit_on(grid)
}

/// The probe before the instrument's blur ([`deblur_probe`] on the probe's column at
/// `phi_h_deg`: theta_d and phi_d of [`ProbeSpec::paper`], as [`probe_plan`] takes it).
pub fn deblurred_probe(
    probe: &[ProbePoint],
    response: &InstrumentResponse,
    phi_h_deg: f64,
) -> DeblurredProbe {
    let column = ProbeSpec {
        phi_h_deg,
        ..ProbeSpec::paper()
    };
    deblur_probe(probe, &column, response)
}

/// The main plan's samples on `grid` with theta_h from `function`, in the paper's nested
/// order (5.3).
fn nested_plan(
    device: &Device,
    grid: &GridSpec,
    function: &SamplingFunction,
    phi_h_deg: f64,
) -> Plan {
    let theta_h = function.positions_deg(grid.theta_h_samples);
    Plan::from_grid(
        &theta_h,
        &grid.theta_d_deg(),
        &grid.phi_d_deg(),
        phi_h_deg,
        device,
    )
}

/// What the main plan is made of: the grid, theta_h's sampling function, phi_h, the order
/// and the HDR scheme its captures are priced with.
struct MainPlanSpec<'a> {
    grid: &'a GridSpec,
    function: &'a SamplingFunction,
    phi_h_deg: f64,
    order: PlanOrder,
    hdr: HdrChoice,
}

/// The main plan (5.3): made, ordered, timed with the session's HDR scheme
/// ([`price_captures`]) and journaled the first time, read back afterwards.
fn main_plan(
    journal: &mut Journal,
    device: &Device,
    spec: &MainPlanSpec,
    predicted: &PredictedExposures,
    observer: &mut dyn Observer,
) -> Result<PlanRecord, WorkflowError> {
    let stored_rows = journal.plan(Stage::Main)?.len();
    if let (Some(record), true) = (journal.record::<PlanRecord>()?, stored_rows > 0) {
        if record.measurable != stored_rows {
            return Err(WorkflowError::Damaged {
                session: journal.path().to_path_buf(),
                stored_rows,
                measurable: record.measurable,
            });
        }
        return Ok(record);
    }
    spec.grid.check()?;
    observer.step("planning and ordering the samples");
    let nested = nested_plan(device, spec.grid, spec.function, spec.phi_h_deg);
    let mut chosen = match spec.order {
        PlanOrder::Optimized => order(&nested),
        PlanOrder::Nested => nested.clone(),
    };
    let summary = nested.summary(device);
    let record = PlanRecord {
        total: summary.total,
        measurable: summary.measurable,
        limit: summary.limit,
        occluded: summary.occluded,
        nested_bracket_s: summary.duration_s(),
        ordered_bracket_s: chosen.summary(device).duration_s(),
    };
    price_captures(&mut chosen, device, spec.hdr, predicted);
    journal.set_plan(Stage::Main, &rows_of(&chosen))?;
    journal.put_record(&record)?;
    Ok(record)
}

fn run_stage(
    engine: &mut Engine,
    stage: Stage,
    predictor: &Predictor,
    observer: &mut dyn Observer,
) -> Result<StageOutcome, WorkflowError> {
    let planned = engine.journal.plan(stage)?.len();
    let done = engine.journal.samples(stage)?.len();
    observer.stage_started(stage, planned, done);
    let outcome = engine.run_stage(stage, predictor, &mut |p| observer.sample(&p))?;
    observer.stage_finished(stage, &outcome);
    Ok(outcome)
}

fn stopped(stage: Stage, outcome: &StageOutcome) -> MeasureOutcome {
    MeasureOutcome::Stopped {
        stage: stage.to_string(),
        done: outcome.resumed + outcome.measured,
        planned: outcome.planned,
    }
}

/// The journal's samples of a stage as reconstruction samples, in plan order.
pub fn measured_samples(
    plan: &[PlannedRow],
    samples: &std::collections::BTreeMap<u32, SampleRecord>,
) -> Vec<Sample> {
    plan.iter()
        .filter_map(|row| samples.get(&row.seq).map(|s| Sample::new(row.hd, s.value)))
        .collect()
}

#[allow(clippy::too_many_arguments)]
fn summarise(
    journal: &Journal,
    session: &Path,
    out: &Path,
    source: String,
    fit: &FitRecord,
    checks: Option<ChecksRecord>,
    plan: PlanRecord,
    simulated: bool,
    settings: &MeasureSettings,
    phi_d_halves: bool,
    deblur: Option<DeblurRecord>,
) -> Result<Summary, WorkflowError> {
    let status = journal.status()?;
    let stage = |stage: Stage| status.stages.iter().find(|s| s.stage == stage).cloned();
    let probe = stage(Stage::Probe).ok_or(WorkflowError::MissingStage("probe"))?;
    let main = stage(Stage::Main).ok_or(WorkflowError::MissingStage("main stage"))?;
    let lower_bounds = journal
        .samples(Stage::Main)?
        .values()
        .filter(|s| s.lower_bound)
        .count();
    let checks_s = checks.as_ref().map_or(0.0, |c| c.device_s);
    Ok(Summary {
        source,
        session: session.to_path_buf(),
        out: out.to_path_buf(),
        k_hat: fit.function.k,
        fit_error: fit.error,
        family: fit.function.family,
        checks,
        grid: fit.grid.unwrap_or(settings.grid),
        plan,
        probe_samples: probe.done,
        measured_samples: main.done,
        captures: main.captures,
        lower_bounds,
        device_s: checks_s + probe.device_s_done + main.device_s_done,
        main_device_s: main.device_s_done,
        predicted_main_s: journal
            .plan(Stage::Main)?
            .iter()
            .map(|row| row.predicted_s)
            .sum(),
        simulated,
        method: settings.method,
        phi_d_halves,
        deblur,
        events: status.events.into_iter().collect(),
        uncertainty: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_steps_match_the_paper() {
        let grid = MeasureSettings {
            grid: specula_core::GridSpec::paper(),
            ..MeasureSettings::default()
        }
        .grid;
        let theta_d = grid.theta_d_deg();
        assert_eq!(theta_d.len(), 30);
        assert_eq!(theta_d.last(), Some(&87.0));
        let phi_d = grid.phi_d_deg();
        assert_eq!(phi_d, vec![0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 90.0]);
    }

    #[test]
    fn versions_compare_number_by_number() {
        assert!(is_older_version("0.1.0", "0.2.0"));
        assert!(is_older_version("0.9.9", "0.10.0"));
        assert!(is_older_version("1.2", "1.2.1"));
        assert!(!is_older_version("0.2.0", "0.1.0"));
        assert!(!is_older_version("0.1.0", "0.1.0"));
        assert!(!is_older_version("0.1.0-rc1+x", "0.1.0"));
        assert!(
            !is_older_version("garbage", "0.1.0"),
            "unreadable: not older"
        );
    }

    #[test]
    fn settings_differences_name_the_field() {
        let a = MeasureSettings::default();
        let b = MeasureSettings {
            seed: 7,
            ..MeasureSettings::default()
        };
        assert_eq!(differences(&a, &b), "--seed: 1 in the session, 7 asked");
        // The recommended grid's rule for an unresolved peak against the paper's grid: in
        // words, not the record's JSON.
        let paper = MeasureSettings {
            grid: GridSpec::paper(),
            ..MeasureSettings::default()
        };
        let recommended = MeasureSettings {
            grid: GridSpec {
                unresolved_peak: Some(UnresolvedPeak {
                    theta_h_samples: 30,
                    theta_d: specula_core::ThetaDSteps::even(3.0),
                    budget_samples: 4073,
                }),
                ..GridSpec::paper()
            },
            ..MeasureSettings::default()
        };
        let text = differences(&recommended, &paper);
        assert_eq!(
            text,
            "the rule for a peak the instrument does not resolve (--grid-preset): up to 30 \
             theta_h with theta_d step 3 deg within 4073 samples in the session, none asked"
        );
    }
}
