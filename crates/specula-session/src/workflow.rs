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
//!
//! The steps' own concepts have modules of their own, whose public items this module
//! re-exports: where the samples come from and the instrument they give (`connection`),
//! what a rerun must ask the same to resume (`resume`), the checks (`checks`), what the
//! caller hears (`observer`) and what a finished measurement reports (`summary`, with the
//! fit through the response in `deblur_record`).

use crate::checks::run_checks;
use crate::connection::{connect, describe, Reached};
use crate::engine::{Engine, EngineSettings, HdrMode, StageOutcome};
use crate::estimate::{price_captures, PredictedExposures};
use crate::inputs::{check_device, check_inputs, DeviceIdentity};
use crate::journal::{
    Durability, Journal, JournalError, PlannedRow, SampleRecord, Stage, EVENT_COMPLETE,
};
use crate::predict::{Predictor, ProbeModel};
use crate::resume::{check_version, input_hashes, start_session};
use crate::sequential::{self, SequenceOutcome, SequentialSpec};
use crate::summary::summarise;
use crate::workflow_error::WorkflowError;
use specula_acquisition::calibration::response::ResponseFit;
use specula_acquisition::calibration::Calibration;
use specula_acquisition::device::Device;
use specula_acquisition::hdr::{HdrCapturer, HdrSettings};
use specula_acquisition::ordering::order;
use specula_acquisition::plan::Plan;
use specula_acquisition::response::InstrumentResponse;
use specula_core::sampling::SamplingFunction;
use specula_core::{GridSpec, HalfDiff, ProbePoint, ProbeSpec, Rgb, Sample};
use specula_reconstruct::phi_d_halves::{measures_both_halves, reconstruct_halves};
use specula_reconstruct::provenance::sidecar_path;
use specula_reconstruct::uncertainty::{self, UncertaintyInputs};
use specula_reconstruct::{deblur_probe, DeblurredProbe, PriorBasis, ReconstructError};
use specula_sampling::{fit_k, Probe};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

pub use crate::connection::{simulated_response, Source};
pub use crate::deblur_record::DeblurRecord;
pub use crate::journal::{
    ChecksRecord, FitRecord, HdrChoice, MeasureSettings, PlanOrder, PlanRecord,
};
pub use crate::observer::{Observer, Quiet};
pub use crate::resume::{session_grid, session_settings};
pub use crate::summary::{summary_path, Summary};

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

/// The default session journal beside the table: `OUT.session.sqlite`.
pub fn default_session_path(out: &Path) -> PathBuf {
    out.with_extension("session.sqlite")
}

/// Runs the whole workflow (see the module documentation) into `session`, writing `out` and
/// its summary when complete. `prior`: the basis the `prior` method blends in (derived by
/// the caller, e.g. `specula_accuracy::merl_prior::basis_for`); asked for that method
/// without one, it stops before measuring.
#[allow(clippy::too_many_arguments)]
pub fn measure(
    source: Source,
    device: &Device,
    settings: &MeasureSettings,
    prior: Option<&PriorBasis>,
    session: &Path,
    out: &Path,
    stop: Arc<AtomicBool>,
    observer: &mut dyn Observer,
) -> Result<MeasureOutcome, WorkflowError> {
    let method = settings.method;
    if method.uses_prior() && prior.is_none() {
        return Err(WorkflowError::Reconstruct {
            cause: ReconstructError::NoPriorBasis,
        });
    }
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
        ran: Vec::new(),
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

    // The plan (5.3) with k-hat, then the acquisition: the whole grid, or batch by batch.
    let predictor = Predictor::new(calibration.clone(), ProbeModel::new(&probe));
    let spec = MainPlanSpec {
        grid: &grid,
        function: &fit.function,
        phi_h_deg,
        order: settings.order,
        hdr: settings.hdr,
    };
    let plan = match settings.sequential {
        None => {
            let predicted = PredictedExposures {
                predictor: &predictor,
                capturer: engine.hdr,
            };
            let plan = main_plan(engine.journal, device, &spec, &predicted, observer)?;
            let outcome = run_stage(&mut engine, Stage::Main, &predictor, observer)?;
            if !outcome.complete() {
                return Ok(stopped(Stage::Main, &outcome));
            }
            plan
        }
        Some(limits) => {
            let plan = engine
                .journal
                .record_or_insert(|| candidate_record(device, &spec))?;
            let before_main_s = checks.as_ref().map_or(0.0, |c| c.device_s)
                + engine
                    .journal
                    .samples(Stage::Probe)?
                    .values()
                    .map(|s| s.device_s)
                    .sum::<f64>();
            let sequential = SequentialSpec {
                grid: &grid,
                function: &fit.function,
                phi_h_deg,
                settings,
                limits,
                before_main_s,
                prior,
            };
            match sequential::run(&mut engine, device, &sequential, &predictor, observer)? {
                SequenceOutcome::Complete => plan,
                SequenceOutcome::Stopped(outcome) => return Ok(stopped(Stage::Main, &outcome)),
            }
        }
    };

    observer.step("reconstructing");
    let main = engine.journal.samples(Stage::Main)?;
    let samples = measured_samples(
        &engine.journal.plan(Stage::Main)?,
        &main,
        Some(&calibration),
    );
    let name = out
        .file_stem()
        .map_or_else(|| "measured".into(), |s| s.to_string_lossy().into_owned());
    let halves = measures_both_halves(&samples);
    let result = reconstruct_halves(&samples, method, &name, response.as_ref(), prior)
        .map_err(|cause| WorkflowError::Reconstruct { cause })?;
    let deblur = response_fit
        .as_ref()
        .filter(|_| result.resolution_deg.is_some())
        .map(|fit| DeblurRecord::new(fit, &result));
    let inputs = UncertaintyInputs {
        samples: &samples,
        method,
        prior,
    };
    let uncertainty = uncertainty::estimate(&inputs, &result)
        .map_err(|cause| WorkflowError::Reconstruct { cause })?;
    specula_core::atomic_file::write_together(&[
        (out, &result.brdf.to_bytes()),
        (&sidecar_path(out), &result.provenance.to_npy()),
        (
            &uncertainty::sidecar_path(out),
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

fn hdr_mode(settings: &MeasureSettings, device: &Device) -> HdrMode {
    match settings.hdr {
        HdrChoice::Predicted => HdrMode::Predicted,
        HdrChoice::Bracket => HdrMode::Bracket {
            exposures_s: device.capture.exposures_s.clone(),
            light_levels: device.capture.light_levels.clone(),
        },
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
pub(crate) fn rows_of(plan: &Plan) -> Vec<PlannedRow> {
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
/// plan order, and the instrument's response its calibration holds (with how it was
/// measured), if any: what `specula reconstruct --session` rebuilds. A session without main
/// samples is an error.
pub fn session_main_samples(
    path: &Path,
) -> Result<(Vec<Sample>, Option<ResponseFit>), WorkflowError> {
    let journal = Journal::open_read_only(path)?;
    let calibration = journal.record::<Calibration>()?;
    let plan = journal.plan(Stage::Main)?;
    let samples = measured_samples(&plan, &journal.samples(Stage::Main)?, calibration.as_ref());
    let response = calibration.and_then(|c| c.response);
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
    let record = plan_record(&nested, device);
    price_captures(&mut chosen, device, spec.hdr, predicted);
    journal.set_plan(Stage::Main, &rows_of(&chosen))?;
    journal.put_record(&record)?;
    Ok(record)
}

/// A plan's counts and the time model's estimate of its nested order with the fixed
/// bracket (the paper's way).
fn plan_record(nested: &Plan, device: &Device) -> PlanRecord {
    let summary = nested.summary(device);
    PlanRecord {
        total: summary.total,
        measurable: summary.measurable,
        limit: summary.limit,
        occluded: summary.occluded,
        nested_bracket_s: summary.duration_s(),
    }
}

/// The counts of a sequential measurement's candidates: the grid the fixed plan would take.
fn candidate_record(device: &Device, spec: &MainPlanSpec) -> PlanRecord {
    plan_record(
        &nested_plan(device, spec.grid, spec.function, spec.phi_h_deg),
        device,
    )
}

pub(crate) fn run_stage(
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

/// The journal's samples of a stage as reconstruction samples, in plan order, each with the
/// relative noise of its value through `calibration` (the session's,
/// [`Calibration::relative_sigma`]) when one is given.
pub fn measured_samples(
    plan: &[PlannedRow],
    samples: &std::collections::BTreeMap<u32, SampleRecord>,
    calibration: Option<&Calibration>,
) -> Vec<Sample> {
    plan.iter()
        .filter_map(|row| {
            samples.get(&row.seq).map(|s| {
                let sample = Sample::new(row.hd, s.value);
                calibration.map_or(sample, |c| {
                    sample.with_noise_rel(c.relative_sigma(s.rate_dn_s, s.sigma_dn_s))
                })
            })
        })
        .collect()
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
}
