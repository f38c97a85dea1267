//! A simulated measurement (`specula measure --truth`) and reading a session journal.

use crate::brdf::brdf_arg;
use crate::errors::{invalid, OrRaise};
use crate::interrupt::{self, Stop};
use crate::plan::{device, GridArgs};
use crate::reconstruction::samples_dict;
use crate::sampling::probe_dict;
use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use specula_accuracy::merl_prior::basis_for;
use specula_acquisition::calibration::Calibration;
use specula_acquisition::instrument::MountTarget;
use specula_core::request::ProbeRequest;
use specula_core::ProbeSpec;
use specula_sampling::Probe;
use specula_session::calibrate::{run_calibrate, CalibrateRequest};
use specula_session::journal::{Journal, SequentialSettings, SourceRecord};
use specula_session::workflow::{
    measured_samples, probe_samples, FitRecord, MeasureOutcome, MeasureSettings, Quiet, Source,
    Summary,
};
use specula_session::Stage;
use specula_session::{run_measure, MeasureRequest};
use std::path::PathBuf;

/// Measure a known BRDF on the simulated device (`specula measure --truth`), the paper's
/// whole workflow: calibration, the alignment and orientation checks (`checks`), the probe
/// (`probe_samples`), k-hat, the plan (the grid arguments as `plan`'s: the recommended grid
/// by default), the acquisition with HDR (`hdr`: `"predicted"` or `"bracket"`) and noise
/// (`ideal=True`: none), and the reconstruction with `method` (through the instrument's
/// measured response unless `deblur=False`; by halves of phi_d when the plan measured both)
/// into the MERL file `out` (with its `.provenance.npy` and `.summary.txt`). Everything is
/// journaled in `session` (default `OUT.session.sqlite`); an existing session resumes, on
/// its own grid unless `grid_preset` is given. Without `grid_preset` the main stage is
/// sequential: batch by batch where the table is least sure, until `max_hours` of device
/// time for the whole session, `max_samples`, or a median relative uncertainty of
/// `target_uncertainty` percent; with it, the preset's whole grid is measured.
///
/// Returns the summary as a dict (`k_hat`, `measured_samples`, `captures`, `device_s`,
/// ...). Ctrl-C stops after the sample in progress, leaves the journal resumable (call again
/// with the same arguments) and raises `KeyboardInterrupt`.
#[pyfunction]
#[pyo3(signature = (truth, out, session = None, seed = 1, ideal = false, point_light = false,
    probe_samples = None, family = "exponential", grid_preset = None, theta_h_samples = None,
    theta_d_step_deg = None, phi_d_step_deg = None, phi_d_span = None, phi_h_deg = None,
    order = "optimized", hdr = "predicted",
    method = "lobe", deblur = true, checks = true, tilt_deg = 0.0, tilt_azimuth_deg = 0.0, device = None,
    max_hours = 1.0, max_samples = 4073, target_uncertainty = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn measure<'py>(
    py: Python<'py>,
    truth: &Bound<'py, PyAny>,
    out: PathBuf,
    session: Option<PathBuf>,
    seed: u64,
    ideal: bool,
    point_light: bool,
    probe_samples: Option<usize>,
    family: &str,
    grid_preset: Option<&str>,
    theta_h_samples: Option<usize>,
    theta_d_step_deg: Option<&Bound<'py, PyAny>>,
    phi_d_step_deg: Option<f64>,
    phi_d_span: Option<&str>,
    phi_h_deg: Option<f64>,
    order: &str,
    hdr: &str,
    method: &str,
    deblur: bool,
    checks: bool,
    tilt_deg: f64,
    tilt_azimuth_deg: f64,
    device: Option<PathBuf>,
    max_hours: f64,
    max_samples: usize,
    target_uncertainty: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let sequential = grid_preset.is_none().then_some(SequentialSettings {
        max_hours,
        max_samples,
        target_uncertainty_rel: target_uncertainty.map(|p| p / 100.0),
    });
    let request = MeasureRequest {
        seed,
        ideal,
        point_light,
        probe: ProbeRequest {
            samples: probe_samples.unwrap_or(ProbeSpec::paper().samples),
            tilt_deg,
            tilt_azimuth_deg,
        },
        family: crate::sampling::family(family)?,
        grid: GridArgs {
            grid_preset,
            theta_h_samples,
            theta_d_step_deg,
            phi_d_step_deg,
            phi_d_span,
            phi_h_deg,
        }
        .request()?,
        order: order.parse().or_raise()?,
        hdr: hdr.parse().or_raise()?,
        method: method.parse().map_err(invalid)?,
        deblur,
        checks,
        sequential,
        out,
        session,
    };
    request.validate().or_raise()?;
    let source = Source::Simulated {
        truth: brdf_arg(truth)?,
        speedup: None,
    };
    let device = self::device(device)?;
    let prior = basis_for(request.method).or_raise()?;
    let outcome = interrupt::run(py, Stop::Cooperative, move |stop| {
        run_measure(
            &request,
            source,
            &device,
            prior.as_deref(),
            stop,
            &mut Quiet,
        )
    })?
    .or_raise()?;
    match outcome {
        MeasureOutcome::Complete(summary) => summary_dict(py, &summary),
        MeasureOutcome::Stopped {
            stage,
            done,
            planned,
        } => Err(PyKeyboardInterrupt::new_err(format!(
            "stopped: {stage} {done} of {planned} samples measured and journaled; call again to resume"
        ))),
    }
}

/// The summary of a complete measurement (the keys of `OUT.summary.txt`).
fn summary_dict<'py>(py: Python<'py>, s: &Summary) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    dict.set_item("source", &s.source)?;
    dict.set_item("session", &s.session)?;
    dict.set_item("out", &s.out)?;
    dict.set_item("family", s.family.name())?;
    dict.set_item("k_hat", s.k_hat)?;
    dict.set_item("fit_error", s.fit_error)?;
    dict.set_item("planned_samples", s.plan.total)?;
    dict.set_item("excluded_limit", s.plan.limit)?;
    dict.set_item("excluded_occluded", s.plan.occluded)?;
    dict.set_item("probe_samples", s.probe_samples)?;
    dict.set_item("measured_samples", s.measured_samples)?;
    dict.set_item("captures", s.captures)?;
    dict.set_item("lower_bound_samples", s.lower_bounds)?;
    dict.set_item("device_s", s.device_s)?;
    dict.set_item("main_device_s", s.main_device_s)?;
    dict.set_item("predicted_main_s", s.predicted_main_s)?;
    dict.set_item("simulated", s.simulated)?;
    dict.set_item("method", s.method.name())?;
    dict.set_item("grid", s.grid.to_string())?;
    dict.set_item("phi_d_halves", s.phi_d_halves)?;
    let events = PyDict::new(py);
    for (kind, count) in &s.events {
        events.set_item(kind, count)?;
    }
    dict.set_item("events", events)?;
    Ok(dict)
}

/// Read a session journal (`specula measure`'s SQLite file), read-only, as far as the
/// session got. Returns `{"source", "simulated_truth" (the truth's name, or None for a real
/// device), "grid" (the main plan's grid in words, or None), "stages": {name: {"planned",
/// "done", "device_s_done", "predicted_s_left", "captures"}}, "events": {kind: count}, "fit":
/// {"k", "family", "error"} or None, "probe":
/// {"theta_h_deg", "rgb"} or None, "samples"}` (the main stage's measured samples in plan
/// order with each value's relative noise per channel, `noise_rel` (N, 3): a dict for `reconstruct`). A file that is not a journal raises `SpeculaError`.
#[pyfunction]
pub(crate) fn read_session(py: Python<'_>, path: PathBuf) -> PyResult<Bound<'_, PyDict>> {
    let journal = Journal::open_read_only(&path).or_raise()?;
    let status = journal.status().or_raise()?;
    let source: Option<SourceRecord> = journal.record().or_raise()?;
    let fit: Option<FitRecord> = journal.record().or_raise()?;
    let settings: Option<MeasureSettings> = journal.record().or_raise()?;
    let has = |stage: Stage| status.stages.iter().any(|s| s.stage == stage);
    let probe = if has(Stage::Probe) {
        let points = probe_samples(&journal).or_raise()?;
        let (theta_h, rgb) = points.iter().map(|p| (p.theta_h_deg, p.value)).unzip();
        Probe::new(theta_h, rgb).ok()
    } else {
        None
    };
    let samples = if has(Stage::Main) {
        let plan = journal.plan(Stage::Main).or_raise()?;
        let calibration: Option<Calibration> = journal.record().or_raise()?;
        let records = journal.samples(Stage::Main).or_raise()?;
        measured_samples(&plan, &records, calibration.as_ref())
    } else {
        Vec::new()
    };

    let dict = PyDict::new(py);
    dict.set_item("source", source.as_ref().map(|s| s.to_string()))?;
    dict.set_item(
        "simulated_truth",
        source.as_ref().and_then(|s| s.simulated_truth()),
    )?;
    dict.set_item("grid", settings.map(|s| s.grid.to_string()))?;
    let stages = PyDict::new(py);
    for stage in &status.stages {
        let entry = PyDict::new(py);
        entry.set_item("planned", stage.planned)?;
        entry.set_item("done", stage.done)?;
        entry.set_item("device_s_done", stage.device_s_done)?;
        entry.set_item("predicted_s_left", stage.predicted_s_left)?;
        entry.set_item("captures", stage.captures)?;
        stages.set_item(stage.stage.name(), entry)?;
    }
    dict.set_item("stages", stages)?;
    dict.set_item("events", status.events.clone())?;
    match fit {
        Some(fit) => {
            let entry = PyDict::new(py);
            entry.set_item("k", fit.function.k)?;
            entry.set_item("family", fit.function.family.name())?;
            entry.set_item("error", fit.error)?;
            dict.set_item("fit", entry)?;
        }
        None => dict.set_item("fit", py.None())?,
    }
    match probe {
        Some(probe) => dict.set_item("probe", probe_dict(py, &probe)?)?,
        None => dict.set_item("probe", py.None())?,
    }
    dict.set_item("samples", samples_dict(py, &samples)?)?;
    Ok(dict)
}

/// Calibrate the simulated device with `truth` on its turntable (`specula calibrate
/// --truth`): the camera's noise model, gains to 1/sr, colour matrix and the instrument's
/// response, written to `out` (TOML, what `specula measure --calibration` reads).
/// `white_reflectance` (a fraction above 0 and at most 1) or a `white_certificate` (TOML)
/// describe the white reference; `seed` the simulated device's positioning errors and
/// noise; `device` a device TOML (default the paper's UTIA goniometer). Returns `out`.
/// Ctrl-C returns at once (the calibration is not stoppable; nothing is written).
#[pyfunction]
#[pyo3(signature = (truth, out, white_reflectance = 0.99, white_certificate = None, seed = 1,
    device = None))]
pub(crate) fn calibrate(
    py: Python<'_>,
    truth: &Bound<'_, PyAny>,
    out: PathBuf,
    white_reflectance: f64,
    white_certificate: Option<PathBuf>,
    seed: u64,
    device: Option<PathBuf>,
) -> PyResult<PathBuf> {
    let request = CalibrateRequest {
        white_reflectance,
        white_certificate,
        seed,
        out: out.clone(),
    };
    request.validate().or_raise()?;
    let device = self::device(device)?;
    let mut simulator = request.simulator(brdf_arg(truth)?, &device);
    interrupt::run(py, Stop::Abandon, move |_| {
        // The simulator mounts every target itself: no operator is asked.
        let mut operator = |_: &MountTarget| Ok(());
        run_calibrate(
            &request,
            &mut simulator,
            &mut operator,
            &device,
            &mut |_| {},
        )
    })?
    .or_raise()?;
    Ok(out)
}
