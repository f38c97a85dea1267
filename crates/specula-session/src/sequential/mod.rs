//! The main stage measured sequentially: each next batch where the table is least sure, until
//! a limit ([`SequentialSettings`]).
//!
//! The paper fixes every position before the first capture (5.3), so a flat region gets as
//! many samples as a peak's flank. Here, after the checks and the probe:
//!
//! 1. **a first design**: a coarse tensor sub-lattice of the candidates
//!    ([`lattice::CandidateLattice::choose_initial`]) that takes about [`INITIAL_SHARE`] of the
//!    time left;
//! 2. **batch by batch**: reconstruct the table from the samples so far (without the
//!    instrument's response, which the final table fits in minutes where a batch has
//!    seconds), estimate every cell's uncertainty (`specula_reconstruct::uncertainty`), forecast
//!    the error figures and credit each candidate plane with the part of them it would take
//!    from a gap ([`forecast::Forecast`]); choose the planes with the most credit per second of
//!    device time, priced by the ordering's time model and scaled by how much longer than
//!    priced the samples so far took ([`pace::Pace`]), into a batch of at most half the time
//!    left (when no plane fits in half, a last batch of at most all of it); order, price and
//!    measure it;
//! 3. **stop** at the first limit: the session's device time (`max_hours`: checks, probe and
//!    main stage), the sample count, the table's median relative uncertainty
//!    (`target_uncertainty_rel`), or
//!    when no plane is left.
//!
//! Every batch is appended to the journal's main plan together with the decision that chose it
//! ([`SequenceRecord`]) in one transaction, so a killed run finishes the batch it was in and
//! then decides exactly as an uninterrupted one: the decisions depend only on the journal
//! (the main samples' values, their planned rows and their captures priced by the time model,
//! the checks' and the probe's device time), not on the clock of a run that was stopped.

mod forecast;
mod lattice;
mod pace;

use crate::engine::{Engine, StageOutcome};
use crate::estimate::{price_captures, PredictedExposures};
use crate::journal::{
    BatchRecord, MeasureSettings, PlanOrder, PlannedRow, SequenceRecord, SequentialSettings, Stage,
};
use crate::observer::Observer;
use crate::predict::Predictor;
use crate::workflow::{measured_samples, rows_of, run_stage};
use crate::workflow_error::WorkflowError;
use forecast::{CellMap, Forecast};
use lattice::{CandidateLattice, AXES};
use pace::Pace;
use specula_acquisition::device::Device;
use specula_acquisition::ordering::order;
use specula_acquisition::plan::Plan;
use specula_core::capture::CaptureResponse;
use specula_core::sampling::SamplingFunction;
use specula_core::{GridSpec, HalfDiff};
use specula_reconstruct::phi_d_halves::reconstruct_halves;
use specula_reconstruct::uncertainty::{self, UncertaintyInputs};
use specula_reconstruct::{Method, PriorBasis};
use std::collections::BTreeSet;

/// The share of the time left that the first design takes: a uniform coarse grid that the
/// batches refine where the table is least sure.
const INITIAL_SHARE: f64 = 0.6;
/// The share of the time left that a batch may take at most.
const BATCH_SHARE: f64 = 0.5;
/// The share of the session's time limit the decisions plan with: the samples so far, priced
/// as taken, predict a batch within a few per cent (the guide's performance page), and the
/// limit is a limit.
const TIME_MARGIN: f64 = 0.97;
/// The first design's cap is searched to within this fraction of itself.
const CAP_TOLERANCE: f64 = 0.02;
/// At most this many first designs are priced while searching the cap.
const MAX_PRICINGS: usize = 16;
/// A batch is never planned for less than this, seconds: below it the reconstruction between
/// batches would cost more than it decides.
const MIN_BATCH_S: f64 = 300.0;

/// What a sequential measurement is made of.
pub(crate) struct SequentialSpec<'a> {
    /// The candidates' grid (the fixed plan's).
    pub grid: &'a GridSpec,
    /// The fitted theta_h sampling function (paper 5.2).
    pub function: &'a SamplingFunction,
    /// The sample's orientation, degrees.
    pub phi_h_deg: f64,
    /// The session's settings (order, HDR, method).
    pub settings: &'a MeasureSettings,
    /// When to stop.
    pub limits: SequentialSettings,
    /// Device time spent before the main stage (checks and probe), seconds.
    pub before_main_s: f64,
    /// The `prior` method's basis, when that is the method.
    pub prior: Option<&'a PriorBasis>,
}

/// How the main stage ended.
pub(crate) enum SequenceOutcome {
    /// No further batch (the journal's record says why).
    Complete,
    /// The stop flag ended a batch.
    Stopped(StageOutcome),
}

/// Measures the main stage sequentially (see the module documentation).
pub(crate) fn run(
    engine: &mut Engine,
    device: &Device,
    spec: &SequentialSpec,
    predictor: &Predictor,
    observer: &mut dyn Observer,
) -> Result<SequenceOutcome, WorkflowError> {
    let mut lattice = CandidateLattice::new(
        spec.function.positions_deg(spec.grid.theta_h_samples),
        spec.grid.theta_d_deg(),
        spec.grid.phi_d_deg(),
        spec.phi_h_deg,
        device,
    );
    let mut record: SequenceRecord = engine.journal.record()?.unwrap_or_default();
    let stored = engine.journal.plan(Stage::Main)?;
    if stored.is_empty() {
        let budget_s = TIME_MARGIN * spec.limits.max_hours * 3600.0 - spec.before_main_s;
        let rows = first_design(&mut lattice, device, spec, predictor, engine, budget_s);
        let first_s = priced_s(&rows);
        if first_s > budget_s {
            return Err(no_time_left(engine, spec, budget_s, first_s));
        }
        observer.step(&format!(
            "sequential: a first design of {} samples, then batches where the table is least sure",
            rows.len()
        ));
        record.batches.push(BatchRecord {
            planes: lattice.design_text(),
            ..batch_record(&[], &rows, spec.before_main_s, None)
        });
        record.chosen = lattice.chosen.to_vec();
        engine.journal.append_plan(Stage::Main, &rows, &record)?;
    } else if !lattice.restore(&record.chosen) {
        let counts = |c: Vec<usize>| format!("{c:?}");
        return Err(WorkflowError::SequenceDamaged {
            session: engine.journal.path().to_path_buf(),
            recorded: counts(record.chosen.iter().map(Vec::len).collect()),
            candidates: counts(lattice.nodes_deg.iter().map(Vec::len).collect()),
        });
    }
    let map = CellMap::new(&lattice);
    loop {
        let outcome = run_stage(engine, Stage::Main, predictor, observer)?;
        if !outcome.complete() {
            return Ok(SequenceOutcome::Stopped(outcome));
        }
        if record.stopped.is_some() {
            return Ok(SequenceOutcome::Complete);
        }
        let plan = engine.journal.plan(Stage::Main)?;
        let forecast = forecast_of(engine, &plan, &lattice, &map, spec)?;
        let pace = Pace::of(&plan, &engine.journal.stage_captures(Stage::Main)?, device);
        let spent_s = spec.before_main_s + pace.taken_s;
        observer.step(&format!(
            "sequential: {} samples, {:.2} h: median relative uncertainty {:.2} % (k = 1)",
            plan.len(),
            spent_s / 3600.0,
            100.0 * forecast.median_relative
        ));
        let decision = next_batch(
            &lattice, &forecast, &plan, &pace, spent_s, device, spec, predictor, engine,
        );
        record.final_median_uncertainty_rel = Some(forecast.median_relative);
        match decision {
            Decision::Stop(reason) => {
                observer.step(&format!("sequential: stopped: {reason}"));
                record.stopped = Some(reason);
                engine.journal.put_record(&record)?;
                return Ok(SequenceOutcome::Complete);
            }
            Decision::Batch { chosen, rows } => {
                let planes = lattice.planes_added_by(&chosen);
                lattice.chosen = chosen;
                record.chosen = lattice.chosen.to_vec();
                record.batches.push(BatchRecord {
                    planes,
                    ..batch_record(&plan, &rows, spent_s, Some(&forecast))
                });
                engine.journal.append_plan(Stage::Main, &rows, &record)?;
            }
        }
    }
}

/// The device time the time model predicts for `rows`, seconds.
fn priced_s(rows: &[PlannedRow]) -> f64 {
    rows.iter().map(|r| r.predicted_s).sum()
}

/// The record of a batch of `rows` chosen after `plan`.
fn batch_record(
    plan: &[PlannedRow],
    rows: &[PlannedRow],
    spent_s: f64,
    forecast: Option<&Forecast>,
) -> BatchRecord {
    BatchRecord {
        samples_before: plan.len(),
        samples: rows.len(),
        device_s_before: spent_s,
        predicted_s: priced_s(rows),
        median_uncertainty_rel: forecast.map(|f| f.median_relative),
        planes: String::new(),
    }
}

/// The error of a session whose checks and probe left `budget_s` for a main stage whose
/// coarsest first design takes `first_s`, with the time limit (to a tenth of an hour, up)
/// that would hold that design as [`INITIAL_SHARE`] of the time left.
fn no_time_left(
    engine: &Engine,
    spec: &SequentialSpec,
    budget_s: f64,
    first_s: f64,
) -> WorkflowError {
    let hours = |s: f64| s / 3600.0;
    let holding_h = hours(spec.before_main_s + first_s / INITIAL_SHARE) / TIME_MARGIN;
    WorkflowError::NoTimeLeft {
        session: engine.journal.path().to_path_buf(),
        limit_h: spec.limits.max_hours,
        spent_h: hours(spec.before_main_s),
        left_h: hours(budget_s.max(0.0)),
        needed_h: hours(first_s),
        suggested_h: (holding_h * 10.0).ceil() / 10.0,
    }
}

/// The first design: the best-ranked coarse sub-lattice
/// ([`CandidateLattice::choose_initial`]) whose priced time is at most [`INITIAL_SHARE`] of
/// `budget_s`, as journal rows; the coarsest when none is.
///
/// The design is chosen by a sample cap, and its time grows with the cap, so the cap is
/// found by bisection: shrunk in proportion to the time until a design fits, then halved
/// between the largest cap that fits and the smallest design that does not, until they are
/// within [`CAP_TOLERANCE`] of each other. A single proportional step lands well under the
/// share when the designs' counts jump (nbrdf:aluminium: 351 samples, 79 % of the share,
/// where the search takes 432, 97 %).
fn first_design(
    lattice: &mut CandidateLattice,
    device: &Device,
    spec: &SequentialSpec,
    predictor: &Predictor,
    engine: &Engine,
    budget_s: f64,
) -> Vec<PlannedRow> {
    let share_s = INITIAL_SHARE * budget_s;
    let price = |lattice: &mut CandidateLattice, cap: usize| {
        lattice.choose_initial(cap);
        let positions = lattice.chosen_product();
        let rows = priced_rows(lattice, &positions, 0, device, spec, predictor, engine);
        (priced_s(&rows), positions.len(), rows)
    };
    // The largest cap known to fit, with its design; the smallest count known not to.
    let mut fitting: Option<(usize, [Vec<bool>; AXES], Vec<PlannedRow>)> = None;
    let mut too_long: Option<usize> = None;
    let mut cap = spec.limits.max_samples;
    for _ in 0..MAX_PRICINGS {
        let (time_s, count, rows) = price(lattice, cap);
        if time_s <= share_s {
            fitting = Some((cap, lattice.chosen.clone(), rows));
        } else {
            too_long = Some(count);
        }
        let next = match (&fitting, too_long) {
            // The largest cap fits, or nothing is left between the two.
            (Some(_), None) => break,
            (Some((lo, ..)), Some(hi))
                if hi <= lo + ((*lo as f64 * CAP_TOLERANCE) as usize).max(1) =>
            {
                break
            }
            (Some((lo, ..)), Some(hi)) => lo + (hi - lo) / 2,
            (None, _) => (count as f64 * (share_s / time_s).clamp(0.1, 0.9)) as usize,
        };
        // With nothing fitting, a design larger than its cap is the coarsest: no smaller one.
        if fitting.is_none() && (next == 0 || count > cap) {
            break;
        }
        cap = next;
    }
    match fitting {
        Some((_, chosen, rows)) => {
            lattice.chosen = chosen;
            rows
        }
        // None fits: the coarsest.
        None => price(lattice, 1).2,
    }
}

/// The positions as journal rows from `first_seq` on: planned, ordered as the session
/// orders, and priced with its HDR scheme.
fn priced_rows(
    lattice: &CandidateLattice,
    positions: &[[usize; AXES]],
    first_seq: usize,
    device: &Device,
    spec: &SequentialSpec,
    predictor: &Predictor,
    engine: &Engine,
) -> Vec<PlannedRow> {
    let hds: Vec<HalfDiff> = positions.iter().map(|&p| lattice.half_diff(p)).collect();
    let nested = Plan::from_half_diffs(&hds, device);
    let mut chosen = match spec.settings.order {
        PlanOrder::Optimized => order(&nested),
        PlanOrder::Nested => nested,
    };
    price_captures(
        &mut chosen,
        device,
        spec.settings.hdr,
        &PredictedExposures {
            predictor,
            capturer: engine.hdr,
        },
    );
    rows_of(&chosen)
        .into_iter()
        .map(|row| PlannedRow {
            seq: (first_seq + row.seq as usize) as u32,
            ..row
        })
        .collect()
}

/// The forecast of the table the samples so far make, without the instrument's response.
fn forecast_of(
    engine: &Engine,
    plan: &[PlannedRow],
    lattice: &CandidateLattice,
    map: &CellMap,
    spec: &SequentialSpec,
) -> Result<Forecast, WorkflowError> {
    let records = engine.journal.samples(Stage::Main)?;
    let samples = measured_samples(plan, &records, Some(engine.calibration));
    let method = batch_method(spec.settings.method);
    let reconstruct = |cause| WorkflowError::Reconstruct { cause };
    let table = reconstruct_halves(
        &samples,
        method,
        "batch",
        None::<&dyn CaptureResponse>,
        spec.prior,
    )
    .map_err(reconstruct)?;
    let inputs = UncertaintyInputs {
        samples: &samples,
        method,
        prior: spec.prior,
    };
    let u = uncertainty::estimate(&inputs, &table).map_err(reconstruct)?;
    Ok(Forecast::new(map, &table.brdf, &u.relative, lattice))
}

/// The method a batch's table is made with: the session's, except the paper's `linear`
/// baseline, whose table has no model to forecast with (`lobe` decides where it samples).
fn batch_method(method: Method) -> Method {
    match method {
        Method::Linear => Method::Lobe,
        m => m,
    }
}

/// What to do after a batch.
enum Decision {
    /// Measure these rows, the product of `chosen`.
    Batch {
        chosen: [Vec<bool>; AXES],
        rows: Vec<PlannedRow>,
    },
    /// No further batch, for this reason.
    Stop(String),
}

/// The next batch: the planes with the most credit per second, within the limits and at most
/// [`BATCH_SHARE`] of the time left (all of it when no plane fits in that share); its price
/// scaled by how much longer than priced the samples so far took (`pace`).
#[allow(clippy::too_many_arguments)]
fn next_batch(
    lattice: &CandidateLattice,
    forecast: &Forecast,
    plan: &[PlannedRow],
    pace: &Pace,
    spent_s: f64,
    device: &Device,
    spec: &SequentialSpec,
    predictor: &Predictor,
    engine: &Engine,
) -> Decision {
    let limits = &spec.limits;
    if let Some(target) = limits.target_uncertainty_rel {
        if forecast.median_relative <= target {
            return Decision::Stop(format!(
                "the median relative uncertainty {:.2} % is within the target {:.2} %",
                100.0 * forecast.median_relative,
                100.0 * target
            ));
        }
    }
    let left_s = TIME_MARGIN * limits.max_hours * 3600.0 - spent_s;
    let samples_left = limits.max_samples.saturating_sub(plan.len());
    let per_sample_s = pace.taken_s / plan.len().max(1) as f64;
    let measured: BTreeSet<[usize; AXES]> = lattice.chosen_product().into_iter().collect();
    // The planes with the most credit per second whose samples take at most `cap_s`, priced;
    // `None` when no plane's do.
    let batch_within = |cap_s: f64| -> Option<Decision> {
        let mut chosen = lattice.chosen.clone();
        let mut picks: Vec<[Vec<bool>; AXES]> = Vec::new();
        loop {
            let current = lattice.product(&chosen).len() - measured.len();
            let room = samples_left.saturating_sub(current).min(
                ((cap_s / per_sample_s.max(f64::MIN_POSITIVE)) as usize).saturating_sub(current),
            );
            let Some((axis, node)) = best_plane(lattice, forecast, &chosen, per_sample_s, room)
            else {
                break;
            };
            chosen[axis][node] = true;
            picks.push(chosen.clone());
        }
        while let Some(candidate) = picks.pop() {
            let positions: Vec<[usize; AXES]> = lattice
                .product(&candidate)
                .into_iter()
                .filter(|p| !measured.contains(p))
                .collect();
            let rows = priced_rows(
                lattice,
                &positions,
                plan.len(),
                device,
                spec,
                predictor,
                engine,
            );
            let time_s = pace.ratio() * priced_s(&rows);
            if !rows.is_empty() && time_s <= left_s {
                return Some(Decision::Batch {
                    chosen: candidate,
                    rows,
                });
            }
        }
        None
    };
    // A batch takes at most BATCH_SHARE of the time left, so that the next one decides on
    // its samples; when no plane fits in that, the last batch may take all of it.
    let batch_s = (BATCH_SHARE * left_s).max(MIN_BATCH_S.min(left_s));
    if let Some(decision) = batch_within(batch_s).or_else(|| batch_within(left_s)) {
        return decision;
    }
    Decision::Stop(if samples_left == 0 {
        format!("{} samples, the most allowed", plan.len())
    } else if forecast.credit.iter().flatten().all(|&c| c <= 0.0) {
        "every candidate plane is measured".to_string()
    } else {
        format!(
            "{:.2} h of {:.2} h spent: no further plane fits the time left",
            spent_s / 3600.0,
            limits.max_hours
        )
    })
}

/// The open plane with the most credit per second of the positions it adds to `chosen`,
/// among those that add at most `room` positions; `None` when no open plane with credit adds
/// a position within it.
fn best_plane(
    lattice: &CandidateLattice,
    forecast: &Forecast,
    chosen: &[Vec<bool>; AXES],
    per_sample_s: f64,
    room: usize,
) -> Option<(usize, usize)> {
    let mut best: Option<(f64, usize, usize)> = None;
    for (axis, (credits, taken)) in forecast.credit.iter().zip(chosen).enumerate() {
        for (node, &credit) in credits.iter().enumerate() {
            if taken[node] || credit <= 0.0 {
                continue;
            }
            let added = lattice.added_by(chosen, axis, node);
            if added == 0 || added > room {
                continue;
            }
            let value = credit / (added as f64 * per_sample_s.max(f64::MIN_POSITIVE));
            if best.is_none_or(|(v, ..)| value > v) {
                best = Some((value, axis, node));
            }
        }
    }
    best.map(|(_, axis, node)| (axis, node))
}
