//! What a finished measurement reports ([`Summary`]): read from the journal when the table
//! is written, and kept beside it as `key=value` lines (`OUT.summary.txt`).

use crate::deblur_record::DeblurRecord;
use crate::journal::{
    ChecksRecord, FitRecord, Journal, MeasureSettings, PlanRecord, SequenceRecord, Stage,
};
use crate::workflow_error::WorkflowError;
use specula_core::sampling::Family;
use specula_core::GridSpec;
use specula_reconstruct::Method;
use std::path::{Path, PathBuf};

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
    /// A sequential measurement's batches and why it stopped; `None` for a fixed grid.
    pub sequence: Option<SequenceRecord>,
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
        if let Some(sequence) = &self.sequence {
            lines.extend(sequence_lines(sequence));
        }
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

/// A sequential measurement's lines: its batches' sizes, why it stopped and the error its
/// last batch's table forecast.
fn sequence_lines(sequence: &SequenceRecord) -> Vec<String> {
    let sizes: Vec<String> = sequence
        .batches
        .iter()
        .map(|b| b.samples.to_string())
        .collect();
    let uncertainties: Vec<String> = sequence
        .batches
        .iter()
        .skip(1)
        .filter_map(|b| b.median_uncertainty_rel)
        .chain(sequence.final_median_uncertainty_rel)
        .map(|u| format!("{:.2} %", 100.0 * u))
        .collect();
    let mut lines = vec![format!(
        "sequential_batches={} ({} samples)",
        sequence.batches.len(),
        sizes.join(" + ")
    )];
    if !uncertainties.is_empty() {
        lines.push(format!(
            "sequential_median_uncertainty={} (k = 1, within 75 deg, after each batch; the batch's table without the response)",
            uncertainties.join(", ")
        ));
    }
    if let Some(reason) = &sequence.stopped {
        lines.push(format!("sequential_stopped={reason}"));
    }
    lines
}

/// The summary file beside the table: `OUT.summary.txt`.
pub fn summary_path(out: &Path) -> PathBuf {
    out.with_extension("summary.txt")
}

#[allow(clippy::too_many_arguments)]
pub(crate) fn summarise(
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
        sequence: journal.record()?,
        uncertainty: Vec::new(),
    })
}
