//! The report of a measurement session: what its journal holds (the settings, the probe and
//! k-hat of paper 5.2, the plan of 5.3 and the samples measured of it, the device time), the
//! table reconstructed from its samples, and the error against the truth it simulated.

use crate::appearance;
use crate::error::{OrReport, ReportError};
use crate::figures::{
    coverage_rows, errors, peak_fact, probe_figure, provenance_rows, raw_samples_figure, renders,
    slice_figures,
};
use crate::{
    generator, header, layout, today, Audience, Page, Progress, ReportRequest, PLACED_SAMPLES,
};
use specula_accuracy::merl_prior::basis_for;
use specula_acquisition::calibration::response::ResponseFit;
use specula_acquisition::calibration::Calibration;
use specula_acquisition::device::Device;
use specula_acquisition::instrument::InstrumentInfo;
use specula_appearance::aperture::ExtrapolatedCells;
use specula_appearance::Options;
use specula_appearance::Tolerances;
use specula_core::merl::CELLS;
use specula_core::{Brdf, MerlBrdf, ProbePoint, Sample};
use specula_formats::BrdfSource;
use specula_reconstruct::phi_d_halves::{measures_both_halves, reconstruct_halves};
use specula_reconstruct::provenance::Provenance;
use specula_reconstruct::safeguard::{AtNormal, Safeguard, FAIL_FACTOR};
use specula_reconstruct::Method;
use specula_session::journal::{
    Journal, JournalError, SequenceRecord, SessionRecord, SessionStatus, SourceRecord, Stage,
    StageStatus,
};
use specula_session::workflow::{
    measured_samples, probe_samples, ChecksRecord, DeblurRecord, FitRecord, MeasureSettings,
    PlanRecord,
};
use specula_visual::report::{
    CoverageSection, DurationSection, KHatSection, MaterialSection, Report, TableSection,
};
use std::path::{Path, PathBuf};

/// Everything the report reads from a session journal.
struct Session {
    path: PathBuf,
    /// What was measured.
    source: Option<SourceRecord>,
    settings: Option<MeasureSettings>,
    device: Option<Device>,
    instrument: Option<InstrumentInfo>,
    version: Option<String>,
    created_unix_s: Option<f64>,
    checks: Option<ChecksRecord>,
    fit: Option<FitRecord>,
    plan: Option<PlanRecord>,
    /// A sequential measurement's batches.
    sequence: Option<SequenceRecord>,
    status: SessionStatus,
    /// The time model's estimate for every planned sample of every stage, seconds.
    predicted_s: f64,
    /// When the last sample finished, seconds since the Unix epoch.
    last_unix_s: Option<f64>,
    /// Main-stage samples whose value is only a lower bound (saturated in every capture).
    lower_bounds: usize,
    /// The probe's points, in increasing theta_h, and its phi_h, degrees.
    probe: Vec<ProbePoint>,
    probe_phi_h_deg: Option<f64>,
    /// The main stage's measured samples, in plan order.
    main: Vec<Sample>,
    /// The instrument's response of the session's calibration, if the session deblurs.
    response: Option<ResponseFit>,
}

impl Session {
    fn read(path: &Path) -> Result<Self, ReportError> {
        let journal = Journal::open_read_only(path).or_report()?;
        let record = SessionRecord::of(&journal).or_report()?;
        let mut predicted_s = 0.0;
        let mut last_unix_s: Option<f64> = None;
        let mut lower_bounds = 0;
        let mut main = Vec::new();
        // The samples carry their noise as `specula reconstruct --session` reads them.
        let calibration = journal.record::<Calibration>().or_report()?;
        for stage in &record.status.stages {
            let plan = journal.plan(stage.stage).or_report()?;
            predicted_s += plan.iter().map(|row| row.predicted_s).sum::<f64>();
            let samples = journal.samples(stage.stage).or_report()?;
            for sample in samples.values() {
                last_unix_s = Some(
                    last_unix_s.map_or(sample.finished_unix_s, |t| t.max(sample.finished_unix_s)),
                );
            }
            if stage.stage == Stage::Main {
                lower_bounds = samples.values().filter(|s| s.lower_bound).count();
                main = measured_samples(&plan, &samples, calibration.as_ref());
            }
        }
        let device = record
            .device
            .as_ref()
            .map(|text| Device::from_toml_str(&text.0, &path.display().to_string()))
            .transpose()
            .or_report()?;
        let response = response_of(&journal, record.settings.as_ref()).or_report()?;
        Ok(Session {
            path: path.to_path_buf(),
            source: record.source,
            settings: record.settings,
            device,
            instrument: record.instrument,
            version: record.version.map(|v| v.0),
            created_unix_s: record.created_unix_s,
            checks: record.checks,
            fit: record.fit,
            plan: record.plan,
            sequence: record.sequence,
            predicted_s,
            last_unix_s,
            lower_bounds,
            probe: probe_samples(&journal).or_report()?,
            probe_phi_h_deg: journal
                .plan(Stage::Probe)
                .or_report()?
                .first()
                .map(|row| row.hd.phi_h.to_degrees()),
            main,
            response,
            status: record.status,
        })
    }

    /// The name of the truth a simulated session measured.
    fn simulated_truth(&self) -> Option<&str> {
        self.source.as_ref()?.simulated_truth()
    }

    /// The angular resolution in theta_h of the session's samples, degrees: its calibrated
    /// response's, else the device model's nominal one (`None` without a device).
    fn resolution_deg(&self) -> Option<f64> {
        match (&self.response, &self.device) {
            (Some(fit), _) => Some(fit.response.resolution_deg()),
            (None, Some(device)) => Some(device.response().resolution_deg()),
            (None, None) => None,
        }
    }

    /// The measured material's name: the simulated truth's, else the journal's file name.
    fn material_name(&self) -> String {
        if let Some(name) = self.simulated_truth() {
            return name.to_string();
        }
        let stem = self
            .path
            .file_stem()
            .map_or_else(|| "session".into(), |s| s.to_string_lossy());
        stem.strip_suffix(".session").unwrap_or(&stem).to_string()
    }

    /// Samples the fitted function places along theta_h.
    fn placed_samples(&self) -> usize {
        self.settings
            .as_ref()
            .map_or(PLACED_SAMPLES, |s| s.grid.theta_h_samples)
    }

    /// Every planned stage, the main one among them, is wholly measured.
    fn measured_completely(&self) -> bool {
        stage(&self.status, Stage::Main).is_some()
            && self.status.stages.iter().all(|s| s.done == s.planned)
    }

    fn k_hat(&self) -> Option<KHatSection> {
        let fit = self.fit?;
        Some(KHatSection {
            family: fit.function.family.to_string(),
            k: fit.function.k,
            fit_error: fit.error,
            probe_samples: self.probe.len(),
            placed_samples: self.placed_samples(),
        })
    }

    /// Per stage, the planned samples measured; and the grid samples the plan could take.
    fn coverage_rows(&self) -> Vec<(String, usize, usize)> {
        let mut rows: Vec<(String, usize, usize)> = self
            .status
            .stages
            .iter()
            .map(|s| {
                (
                    format!("{} stage: planned samples measured", s.stage),
                    s.done,
                    s.planned,
                )
            })
            .collect();
        if let Some(plan) = &self.plan {
            rows.push((
                "grid samples the device can take (the others lie beyond its axes' limits or are occluded)".into(),
                plan.measurable,
                plan.total,
            ));
        }
        rows
    }

    /// Device time of the checks and of the samples measured, against the time model's
    /// estimate for every planned sample; none before anything was done.
    fn duration(&self) -> Option<DurationSection> {
        let checks_s = self.checks.as_ref().map(|c| c.device_s);
        if self.status.stages.is_empty() && checks_s.is_none() {
            return None;
        }
        let samples_s: f64 = self.status.stages.iter().map(|s| s.device_s_done).sum();
        Some(DurationSection {
            measured_s: Some(checks_s.unwrap_or(0.0) + samples_s),
            estimated_s: (self.predicted_s > 0.0).then_some(self.predicted_s),
        })
    }

    /// How the duration was counted, stage by stage.
    fn duration_note(&self) -> Option<String> {
        self.duration()?;
        let clock = if self.simulated_truth().is_some() {
            "the simulated device's clock"
        } else {
            "the device's time"
        };
        let mut parts: Vec<String> = self
            .checks
            .iter()
            .map(|c| format!("checks {}", hours(c.device_s)))
            .collect();
        parts.extend(
            self.status
                .stages
                .iter()
                .map(|s| format!("{} {}", s.stage, hours(s.device_s_done))),
        );
        let wall_s: f64 = self.status.stages.iter().map(|s| s.wall_s_done).sum();
        Some(format!(
            "Duration: {clock} spent on the session ({}). Planned duration: the time model's \
             estimate for every planned sample of the probe and the main stage with the \
             device's fixed exposure bracket (the checks are not planned, and predicted \
             exposures need fewer captures than the bracket). The sample steps took {wall_s:.1} s \
             of wall-clock time here.",
            parts.join(", ")
        ))
    }

    /// Complete, or how far the measurement got, in a few words.
    fn state(&self) -> String {
        if self.measured_completely() {
            return "complete: every planned sample is measured".into();
        }
        let stages: Vec<String> = self
            .status
            .stages
            .iter()
            .map(|s| format!("{} {} of {}", s.stage, s.done, s.planned))
            .collect();
        if stages.is_empty() {
            return "incomplete: nothing planned yet".into();
        }
        format!("incomplete: {} samples measured", stages.join(", "))
    }

    /// Where an incomplete session stands; none for a complete one.
    fn progress_note(&self) -> Option<String> {
        if self.measured_completely() {
            return None;
        }
        let resume = "run the same `specula measure` command to resume; this report shows \
                      what the journal holds so far.";
        Some(
            match (
                stage(&self.status, Stage::Probe),
                stage(&self.status, Stage::Main),
            ) {
                (_, Some(main)) => format!(
                    "This session is incomplete: {} of {} planned samples of the main stage are \
                     measured ({:.1} %); the time model gives {} for the samples left (with the \
                     fixed bracket; predicted exposures take less); {resume}",
                    main.done,
                    main.planned,
                    100.0 * main.done as f64 / main.planned.max(1) as f64,
                    hours(main.predicted_s_left)
                ),
                (Some(probe), None) => format!(
                    "This session is incomplete: it stopped in the probe ({} of {} samples \
                     measured), before k-hat was fitted and the main stage planned; {resume}",
                    probe.done, probe.planned
                ),
                (None, None) => format!("This session has no planned stage yet; {resume}"),
            },
        )
    }

    /// The session's facts: what, on which device, how, when, and what happened.
    fn facts(&self) -> Vec<(String, String)> {
        let mut facts = Vec::new();
        let mut fact = |label: &str, value: String| facts.push((label.to_string(), value));
        fact("state", self.state());
        if let Some(source) = &self.source {
            fact("measured", source.to_string());
        }
        if let Some(device) = &self.device {
            fact("device model", device.name.clone());
        }
        if let Some(i) = &self.instrument {
            fact("instrument", format!("{}, serial {}", i.model, i.serial));
        }
        if let Some(s) = &self.settings {
            fact("settings", settings_text(s));
        }
        if let Some(fit) = &self.response {
            fact(
                "instrument response",
                format!(
                    "light disk of {:.3} deg angular radius (measured with the {}; fit residual {:.3} of the peak), camera pupil {:.3} deg, measured area {:.1} mm across: resolution {:.3} deg in theta_h",
                    fit.response.light.radius_deg,
                    fit.reference,
                    fit.rms_relative,
                    fit.response.camera_aperture_deg,
                    2e3 * fit.response.footprint_radius_m,
                    fit.response.resolution_deg()
                ),
            );
        }
        if let Some(checks) = &self.checks {
            fact("alignment", checks.alignment.clone());
            fact("orientation", checks.orientation.clone());
        }
        if let Some(plan) = &self.plan {
            fact(
                "plan",
                format!(
                    "{} grid samples: {} measurable, {} beyond the axes' limits, {} occluded",
                    plan.total, plan.measurable, plan.limit, plan.occluded
                ),
            );
        }
        if let Some(main) = stage(&self.status, Stage::Main) {
            fact(
                "captures",
                format!(
                    "{} for {} main samples ({:.3} per sample); {} lower bounds (a channel \
                     saturated in every capture)",
                    main.captures,
                    main.done,
                    main.captures as f64 / main.done.max(1) as f64,
                    self.lower_bounds
                ),
            );
        }
        if !self.status.events.is_empty() {
            let events: Vec<String> = self
                .status
                .events
                .iter()
                .map(|(kind, n)| format!("{kind} {n}"))
                .collect();
            fact("events", events.join(", "));
        }
        if let Some(t) = self.created_unix_s {
            fact("session started", utc_text(t));
        }
        if let Some(t) = self.last_unix_s {
            fact("last sample", utc_text(t));
        }
        if let Some(v) = &self.version {
            fact("specula version", v.clone());
        }
        facts
    }
}

/// The status of one stage, if it has a plan.
fn stage(status: &SessionStatus, stage: Stage) -> Option<&StageStatus> {
    status.stages.iter().find(|s| s.stage == stage)
}

/// A sequential measurement's batches: when each ran, how many samples it took and the
/// table's median relative uncertainty after it (the uncertainty against time), and why the
/// measurement stopped.
fn batches_table(sequence: &SequenceRecord) -> TableSection {
    let after = sequence
        .batches
        .iter()
        .skip(1)
        .map(|b| b.median_uncertainty_rel)
        .chain(std::iter::once(sequence.final_median_uncertainty_rel));
    let rows = sequence
        .batches
        .iter()
        .zip(after)
        .enumerate()
        .map(|(i, (b, after))| {
            let start_h = b.device_s_before / 3600.0;
            vec![
                if i == 0 {
                    "1 (first design)".to_string()
                } else {
                    (i + 1).to_string()
                },
                b.samples.to_string(),
                b.planes.clone(),
                format!("{start_h:.2} to {:.2}", start_h + b.predicted_s / 3600.0),
                after.map_or_else(|| "-".to_string(), |u| format!("{:.2} %", 100.0 * u)),
            ]
        })
        .collect();
    TableSection {
        title: "Sequential measurement".into(),
        header: [
            "batch",
            "samples",
            "where",
            "device time, h",
            "median uncertainty after",
        ]
        .map(String::from)
        .to_vec(),
        rows,
        notes: vec![format!(
            "Each batch after the first design measured the planes of the grid where the table \
             of the samples before it was least sure; the uncertainty is the relative standard \
             uncertainty (k = 1) of the cells within 75 deg, median, of the table each batch \
             made without the instrument's response. {}",
            sequence
                .stopped
                .as_ref()
                .map_or_else(String::new, |reason| format!("Stopped: {reason}."))
        )],
    }
}

/// The checks of the deblurred table ([`specula_reconstruct::safeguard`]): per region of
/// theta_h, how well the table blurred by the response reproduces the samples against what
/// their uncertainties explain, and what the table holds where a check failed.
fn checks_table(guard: &Safeguard) -> TableSection {
    // Where part of the table was replaced, the deblurred table's figures say why.
    let checked = guard.deblurred.as_ref().unwrap_or(&guard.consistency);
    let rows = checked
        .regions
        .iter()
        .map(|r| {
            let passed = !r.misses_by(FAIL_FACTOR);
            vec![
                r.name.to_string(),
                r.samples.to_string(),
                format!("{:.3}", r.chi2_per_value),
                format!("{:.2} %", 100.0 * r.relative_error),
                format!("{:.2} %", 100.0 * r.expected_error),
                if passed { "passes" } else { "fails" }.to_string(),
            ]
        })
        .collect();
    let held = match (
        guard.fallback_below_deg,
        guard.bounded_below_deg,
        &guard.reason,
    ) {
        (Some(limit), _, Some(reason)) => format!(
            "Below theta_h {limit:.2} deg the table holds the values as measured (not \
             deblurred): {reason}."
        ),
        (None, Some(limit), Some(reason)) => format!(
            "Below theta_h {limit:.2} deg the peak is a bound, not a measurement: the table \
             holds the geometric mean of the deblurred values and the values as measured. \
             {reason}."
        ),
        (None, None, Some(reason)) => {
            format!(
                "The deblurred table is kept, flagged: its peak is not a measurement. {reason}."
            )
        }
        _ => "Every region passes: the deblurred table reproduces its samples.".into(),
    };
    let normal = match &guard.at_normal {
        AtNormal::Restored(n) => Some(format!(
            "At theta_h 0 every phi_d is one configuration, and the deblurred table varied \
             {:.2} times over phi_d there: {n}.",
            n.before.ratio
        )),
        AtNormal::Kept(why) => Some(format!(
            "At theta_h 0 every phi_d is one configuration, and the table varies {:.2} \
             times over phi_d there; it is kept as it is: {why}.",
            guard.consistency.normal_spread.ratio
        )),
        AtNormal::Untouched => None,
    };
    let energy = guard.energy.map_or_else(
        || format!("Largest directional albedo {:.3}.", guard.max_albedo),
        |e| format!("Energy held: {e}."),
    );
    TableSection {
        title: "Checks of the deblurred table".into(),
        header: [
            "region of theta_h",
            "samples",
            "chi-square per value",
            "reproduction error",
            "explained by the uncertainties",
            "check",
        ]
        .map(String::from)
        .to_vec(),
        rows,
        notes: vec![
            format!(
                "The deblurred table, blurred again by the instrument's response, predicts each \
                 sample; a region fails when the share of the samples' signal it misses is more \
                 than {FAIL_FACTOR} times the share their uncertainties explain (peak: within \
                 twice the resolution, flank: to 20 deg, body: beyond)."
            ),
            held,
        ]
        .into_iter()
        .chain(normal)
        .chain([energy])
        .collect(),
    }
}

fn settings_text(s: &MeasureSettings) -> String {
    format!(
        "seed {}, {} probe samples, grid {} ({} function), order {}, exposures {}, method {}{}",
        s.seed,
        s.probe_samples,
        s.grid,
        s.family,
        s.order,
        s.hdr,
        s.method,
        if s.ideal { ", ideal" } else { "" }
    )
}

fn hours(seconds: f64) -> String {
    format!("{:.3} h", seconds / 3600.0)
}

/// Seconds since the Unix epoch as an RFC 3339 UTC time to the second.
fn utc_text(unix_s: f64) -> String {
    let since_epoch = std::time::Duration::try_from_secs_f64(unix_s).unwrap_or_default();
    humantime::format_rfc3339_seconds(std::time::UNIX_EPOCH + since_epoch).to_string()
}

/// The truth to compare with: --truth, else the one a simulated session measured; labelled
/// "truth" when the session was simulated, else "reference".
fn truth(
    options: &ReportRequest,
    session: &Session,
    notes: &mut Vec<String>,
) -> Result<Option<(String, BrdfSource)>, ReportError> {
    let role = if session.simulated_truth().is_some() {
        "truth"
    } else {
        "reference"
    };
    if let Some(spec) = &options.truth {
        return Ok(Some((
            format!("{spec} ({role})"),
            specula_formats::load_brdf(spec).or_report()?,
        )));
    }
    let Some(name) = session.simulated_truth() else {
        return Ok(None);
    };
    match specula_formats::load_brdf(name) {
        Ok(brdf) => Ok(Some((format!("{name} (truth)"), brdf))),
        Err(e) => {
            notes.push(format!(
                "The session simulated {name}, which does not load by that name ({e:#}); give \
                 --truth for the error figures."
            ));
            Ok(None)
        }
    }
}

/// Why a sharp material's error is large when the session was measured with `--no-deblur`
/// (docs/book/src/pictures.md gives the figures of the demo's green paint).
const LIGHT_DISK_NOTE: &str = "About the error figures: this session was measured with \
     --no-deblur, and the simulated light is a disk (1.8 deg across on the default device, as on \
     the real one), not a point, so a highlight sharper than the disk is measured blurred. The \
     relative RMSE is dominated by the specular peak and counts that blur together with the \
     error of sampling and reconstruction (for the demo's green paint the relative RMSE within \
     75 deg is 0.88 without deblurring and 0.11 with it).";

/// The response a session's reconstruction goes through: its calibration's, unless the
/// session was measured with `--no-deblur`.
fn response_of(
    journal: &Journal,
    settings: Option<&MeasureSettings>,
) -> Result<Option<ResponseFit>, JournalError> {
    let deblur = settings.is_none_or(|s| s.deblur);
    let calibration = journal.record::<Calibration>()?;
    Ok(calibration.and_then(|c| c.response).filter(|_| deblur))
}

/// The table shown: --table, or the main stage's samples reconstructed with the session's
/// method (as `specula reconstruct --session`: each half of phi_d apart when the samples
/// measure both); with its coverage rows and where it is from.
struct Shown {
    table: MerlBrdf,
    provenance: Option<Provenance>,
    rows: Vec<(String, usize, usize)>,
    origin: String,
    /// The cells the reconstruction extrapolated, when known.
    extrapolated: Option<ExtrapolatedCells>,
    /// The table's standard uncertainty (1/sr), when its sidecar is there.
    uncertainty: Option<MerlBrdf>,
    /// Where the uncertainty is from, or that there is none.
    uncertainty_origin: String,
    /// The checks of the deblurred table, when it was deblurred.
    checks: Option<TableSection>,
}

/// The uncertainty `measure` wrote beside the table of the session journal `path`
/// (`OUT.uncertainty.binary` beside `OUT.session.sqlite`), when it is there; and what the
/// report says of it.
fn measured_uncertainty(path: &Path) -> Result<(Option<MerlBrdf>, String), ReportError> {
    let file_name = path.file_name().map(|n| n.to_string_lossy().into_owned());
    let Some(stem) = file_name
        .as_deref()
        .and_then(|n| n.strip_suffix(".session.sqlite"))
    else {
        return Ok((
            None,
            "none: the journal is not named OUT.session.sqlite, so no table of measure's is known"
                .into(),
        ));
    };
    let sidecar = crate::view::uncertainty_path(&path.with_file_name(format!("{stem}.binary")));
    if !sidecar.is_file() {
        return Ok((
            None,
            format!("none: no {} beside the session", sidecar.display()),
        ));
    }
    let uncertainty = MerlBrdf::read(&sidecar).or_report()?;
    Ok((
        Some(uncertainty),
        format!("{} (written by measure with its table)", sidecar.display()),
    ))
}

fn shown_table(
    options: &ReportRequest,
    session: &Session,
    name: &str,
    notes: &mut Vec<String>,
    progress: &dyn Progress,
) -> Result<Option<Shown>, ReportError> {
    if let Some(path) = &options.table {
        let table = MerlBrdf::read(path).or_report()?;
        let (provenance, uncertainty) = crate::view::sidecars(path)?;
        let uncertainty_origin = if uncertainty.is_some() {
            crate::view::uncertainty_path(path).display().to_string()
        } else {
            format!(
                "none: no {} beside the table",
                crate::view::uncertainty_path(path).display()
            )
        };
        return Ok(Some(Shown {
            rows: coverage_rows(&table, path)?,
            provenance,
            table,
            origin: format!("{} (--table)", path.display()),
            extrapolated: appearance::extrapolated_cells(&path.to_string_lossy())?,
            uncertainty,
            uncertainty_origin,
            checks: None,
        }));
    }
    if session.main.is_empty() {
        notes.push(
            "No table: the main stage has no measured sample yet, so there are no renders, \
             slices or error figures."
                .into(),
        );
        return Ok(None);
    }
    let method = session.settings.as_ref().map_or(Method::Lobe, |s| s.method);
    progress.start("reconstructing", None);
    let response = session.response.as_ref().map(|fit| &fit.response);
    let halves = measures_both_halves(&session.main);
    let prior = basis_for(method).or_report()?;
    let result = reconstruct_halves(
        &session.main,
        method,
        &format!("{name}, measured"),
        response,
        prior.as_deref(),
    );
    progress.finish();
    match result {
        Ok(r) => {
            let deblurred = match (&session.response, r.resolution_deg) {
                (Some(fit), Some(_)) => format!(
                    ", fitted through the instrument's response: {}",
                    DeblurRecord::new(fit, &r).describe()
                ),
                _ => ", not deblurred (as measured, blurred by the light's disk)".into(),
            };
            let mut rows = vec![(
                "MERL cells holding a value".to_string(),
                r.brdf.measured_count(),
                CELLS,
            )];
            rows.extend(provenance_rows(&r.provenance));
            let (uncertainty, uncertainty_origin) = measured_uncertainty(&session.path)?;
            Ok(Some(Shown {
                uncertainty,
                uncertainty_origin,
                checks: r.safeguard.as_ref().map(checks_table),
                extrapolated: appearance::extrapolated_cells_of(&r.provenance),
                table: r.brdf,
                provenance: Some(r.provenance),
                rows,
                origin: format!(
                    "reconstructed from the {} main samples with the {method} method{}{}",
                    session.main.len(),
                    if halves {
                        ", each half of phi_d (0-90 and 90-180 deg) from its own samples"
                    } else {
                        ""
                    },
                    deblurred
                ),
            }))
        }
        Err(e) => {
            notes.push(format!(
                "No table could be reconstructed from the {} main samples measured: {e}.",
                session.main.len()
            ));
            Ok(None)
        }
    }
}

/// The table the report of the session journal `path` shows, named after its material, with
/// its provenance: what the viewer shows of a session.
pub(crate) fn shown_of(
    path: &Path,
    progress: &dyn Progress,
) -> Result<(String, MerlBrdf, Option<Provenance>), ReportError> {
    let session = Session::read(path)?;
    let name = session.material_name();
    let mut notes = Vec::new();
    match shown_table(
        &ReportRequest::new(path),
        &session,
        &name,
        &mut notes,
        progress,
    )? {
        Some(shown) => Ok((format!("{name}, measured"), shown.table, shown.provenance)),
        None => Err(ReportError::In {
            origin: path.display().to_string(),
            source: notes.join(" ").into(),
        }),
    }
}

/// The report of the session journal `options.input` (`specula report`, and the demo's).
pub(crate) fn report(
    options: &ReportRequest,
    progress: &dyn Progress,
) -> Result<Page, ReportError> {
    let session = Session::read(&options.input)?;
    let name = session.material_name();
    let engineering = options.audience == Audience::Engineering;
    let mut notes: Vec<String> = session.progress_note().into_iter().collect();
    let truth = truth(options, &session, &mut notes)?;
    let against = options
        .against
        .as_deref()
        .map(|spec| {
            let brdf = specula_formats::load_brdf(spec).or_report()?;
            Ok::<_, ReportError>((format!("{} (reference)", brdf.name()), brdf))
        })
        .transpose()?;
    let tolerances = options
        .tolerances
        .as_deref()
        .map(Tolerances::read)
        .transpose()
        .or_report()?;
    let shown = shown_table(options, &session, &name, &mut notes, progress)?;
    notes.extend(session.duration_note());

    let mut facts = session.facts();
    let mut coverage = session.coverage_rows();
    let date = session
        .created_unix_s
        .map_or_else(today, |t| utc_text(t)[..10].to_string());
    let mut report = Report {
        title: options
            .title
            .clone()
            .unwrap_or_else(|| format!("Session report: {name}")),
        generator: generator(),
        layout: layout(options),
        header: header(options, date),
        k_hat: session.k_hat(),
        duration: session.duration(),
        ..Report::default()
    };
    let mut verdict = None;
    let mut warnings = Vec::new();
    let truth_brdf = truth.as_ref().map(|(_, brdf)| brdf.as_ref());
    let truth_role = if session.simulated_truth().is_some() {
        "truth"
    } else {
        "reference"
    };
    // The figures are compared with the reference when one is given, else with the truth.
    let reference = against.as_ref().or(truth.as_ref());
    let sample_label = format!("{name} (measured)");
    if let Some(shown) = &shown {
        facts.push(("table".into(), shown.origin.clone()));
        facts.push(("uncertainty".into(), shown.uncertainty_origin.clone()));
        facts.extend(peak_fact(&shown.table, shown.provenance.as_ref()));
        coverage.extend(shown.rows.iter().cloned());
        if let (Some((label, brdf)), true) = (&truth, engineering) {
            report.errors = Some(errors(&shown.table, brdf.as_ref(), label, progress));
            let disk_light = session.simulated_truth().is_some()
                && session
                    .settings
                    .as_ref()
                    .is_some_and(|s| !s.point_light && !s.deblur);
            if disk_light {
                notes.push(LIGHT_DISK_NOTE.into());
            }
        }
        let resolution_deg = session.resolution_deg();
        let section = appearance::report_section(
            reference.map(|(label, brdf)| (label.as_str(), brdf.as_ref())),
            (&sample_label, &shown.table),
            Options {
                extrapolated: shown.extrapolated.clone(),
                resolution_deg,
            },
            tolerances.as_ref(),
        );
        report.tables.push(section.table);
        report
            .tables
            .extend(session.sequence.as_ref().map(batches_table));
        if engineering {
            report.tables.extend(shown.checks.clone());
        }
        verdict = section.verdict;
        warnings = section.warnings;
        report.figures.extend(renders(
            (&shown.table, &sample_label),
            reference.map(|(label, brdf)| (brdf.as_ref(), label.as_str())),
            options,
            progress,
        )?);
        if engineering {
            report.figures.extend(slice_figures(
                &shown.table,
                truth_brdf.map(|t| (t, truth_role)),
                shown.uncertainty.as_ref(),
            )?);
        }
        let mut shown_sources: Vec<crate::viewer::Shown> = vec![(
            &sample_label,
            &shown.table,
            shown.provenance.as_ref(),
            shown.uncertainty.as_ref().map(|u| u as &dyn Brdf),
        )];
        if let Some((label, brdf)) = reference {
            shown_sources.push((label, brdf.as_ref(), None, None));
        }
        // The interactive viewer is the engineer's: the customer's page keeps to the
        // figures, the verdict and the pictures.
        if engineering {
            report.viewer = Some(crate::viewer::viewer_of(&shown_sources));
        }
    }
    if let (Some(fit), false, true) = (&session.fit, session.probe.is_empty(), engineering) {
        report.figures.push(probe_figure(
            &session.probe,
            &fit.function,
            session.placed_samples(),
            session.probe_phi_h_deg.unwrap_or_default(),
            &format!("{name} (k-hat {:.2})", fit.function.k),
        )?);
    }
    if !session.main.is_empty() && engineering {
        report.figures.push(raw_samples_figure(
            &session.main,
            &format!("{name}: measured samples"),
            &format!("the main stage of {}", options.input.display()),
        )?);
    }
    report.material = Some(MaterialSection {
        name,
        source: options.input.display().to_string(),
        facts,
    });
    report.coverage = Some(CoverageSection { rows: coverage });
    report.notes = notes;
    Ok(Page {
        report,
        verdict,
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_reconstruct::consistency::{Consistency, NormalSpread, RegionFigures};
    use specula_reconstruct::safeguard::{Halves, NormalFallback};

    #[test]
    fn the_checks_say_which_half_of_phi_d_took_the_values_as_measured_at_the_normal() {
        let spread = |ratio, theta_d_deg| NormalSpread { ratio, theta_d_deg };
        let guard = Safeguard {
            consistency: Consistency {
                regions: vec![RegionFigures {
                    name: "peak",
                    samples: 10,
                    chi2_per_value: 1.0,
                    relative_error: 0.01,
                    expected_error: 0.01,
                }],
                peak_limit_deg: 2.17,
                normal_spread: spread(1.05, 0.5),
            },
            deblurred: None,
            fallback_below_deg: None,
            bounded_below_deg: None,
            reason: None,
            max_albedo: 0.5,
            energy: None,
            at_normal: AtNormal::Restored(NormalFallback {
                halves: Halves::First,
                below_deg: 20.0,
                before: spread(7.764, 74.5),
                after: spread(1.05, 0.5),
            }),
        };
        let table = checks_table(&guard);
        let normal = table
            .notes
            .iter()
            .find(|n| n.contains("varied 7.76 times"))
            .unwrap_or_else(|| panic!("{:?}", table.notes));
        assert!(
            normal.contains("theta_h below 20.00 deg of phi_d 0-90 deg"),
            "{normal}"
        );
        assert!(table.notes.last().is_some_and(|n| n.contains("albedo")));

        // Kept as it is: the note gives the spread and why.
        let kept = Safeguard {
            consistency: Consistency {
                normal_spread: spread(2.535, 74.5),
                ..guard.consistency.clone()
            },
            at_normal: AtNormal::Kept(
                "the peak below theta_h 2.17 deg is bounded, not measured".into(),
            ),
            ..guard
        };
        let table = checks_table(&kept);
        assert!(
            table.notes.iter().any(|n| n.contains("varies 2.54 times")
                && n.ends_with(
                    "kept as it is: the peak below theta_h 2.17 deg is bounded, not measured."
                )),
            "{:?}",
            table.notes
        );
    }

    #[test]
    fn unix_times_read_as_utc_dates() {
        assert_eq!(utc_text(0.0), "1970-01-01T00:00:00Z");
        assert_eq!(utc_text(1_700_000_000.0), "2023-11-14T22:13:20Z");
        assert_eq!(utc_text(951_782_400.0), "2000-02-29T00:00:00Z");
    }
}
