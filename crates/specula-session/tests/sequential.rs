//! A sequential measurement on the simulated device: it keeps to its time limit, journals
//! each batch with the decision that chose it, and a stopped run resumes to the same table.

use specula_acquisition::device::Device;
use specula_core::materials::preset;
use specula_core::{GridSpec, ThetaDSteps};
use specula_session::engine::{Progress, StageOutcome};
use specula_session::journal::{Journal, SequenceRecord, SequentialSettings};
use specula_session::workflow::{measure, MeasureOutcome, MeasureSettings, Observer, Source};
use specula_session::workflow_error::WorkflowError;
use specula_session::Stage;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// The whole session's device time limit, hours.
const MAX_HOURS: f64 = 0.2;

fn settings() -> MeasureSettings {
    MeasureSettings {
        probe_samples: 30,
        grid: GridSpec {
            theta_h_samples: 8,
            theta_d: ThetaDSteps::even(6.0),
            phi_d_step_deg: 30.0,
            ..GridSpec::recommended()
        },
        checks: false,
        sequential: Some(SequentialSettings {
            max_hours: MAX_HOURS,
            ..SequentialSettings::default()
        }),
        ..MeasureSettings::default()
    }
}

/// Raises the stop flag once the main stage holds `after` samples.
struct StopAfter {
    after: usize,
    stop: Arc<AtomicBool>,
    stage: Option<Stage>,
}

impl Observer for StopAfter {
    fn step(&mut self, _: &str) {}
    fn stage_started(&mut self, stage: Stage, _: usize, _: usize) {
        self.stage = Some(stage);
    }
    fn sample(&mut self, progress: &Progress) {
        if self.stage == Some(Stage::Main) && progress.done >= self.after {
            self.stop.store(true, Ordering::SeqCst);
        }
    }
    fn stage_finished(&mut self, _: Stage, _: &StageOutcome) {}
}

/// Measures silver-925 on the simulated device into `dir`'s `s.sqlite` and `s.binary`.
fn measure_silver(
    dir: &Path,
    settings: &MeasureSettings,
    observer: &mut dyn Observer,
    stop: Arc<AtomicBool>,
) -> Result<MeasureOutcome, WorkflowError> {
    measure(
        Source::Simulated {
            truth: Arc::new(preset("silver-925").unwrap()),
            speedup: None,
        },
        &Device::utia(),
        settings,
        None,
        &dir.join("s.sqlite"),
        &dir.join("s.binary"),
        stop,
        observer,
    )
}

fn run(dir: &Path, observer: &mut dyn Observer, stop: Arc<AtomicBool>) -> MeasureOutcome {
    measure_silver(dir, &settings(), observer, stop).unwrap()
}

fn record(dir: &Path) -> SequenceRecord {
    Journal::open_read_only(&dir.join("s.sqlite"))
        .unwrap()
        .record()
        .unwrap()
        .unwrap()
}

#[test]
fn a_sequential_measurement_keeps_its_time_limit_and_resumes_to_the_same_table() {
    let whole = tempfile::tempdir().unwrap();
    let never = Arc::new(AtomicBool::new(false));
    let mut quiet = StopAfter {
        after: usize::MAX,
        stop: never.clone(),
        stage: None,
    };
    let MeasureOutcome::Complete(summary) = run(whole.path(), &mut quiet, never) else {
        panic!("stopped without a stop");
    };
    // The limit holds for the whole session, checks and probe included.
    assert!(
        summary.device_s <= MAX_HOURS * 3600.0,
        "{} s of {} h",
        summary.device_s,
        MAX_HOURS
    );
    let sequence = record(whole.path());
    assert!(sequence.batches.len() >= 2, "{sequence:?}");
    // The first design takes at most 60 % of the time the checks and the probe left (with the
    // decisions' 3 % margin).
    let first_design = &sequence.batches[0];
    let left_s = 0.97 * MAX_HOURS * 3600.0 - first_design.device_s_before;
    assert!(
        first_design.predicted_s <= 0.6 * left_s,
        "{} s of {left_s} s left",
        first_design.predicted_s
    );
    assert!(sequence.batches[0].median_uncertainty_rel.is_none());
    assert!(sequence.batches[1..]
        .iter()
        .all(|b| b.median_uncertainty_rel.is_some()));
    // The table is surer after the batches than after the first design.
    let first = sequence.batches[1].median_uncertainty_rel.unwrap();
    let last = sequence.final_median_uncertainty_rel.unwrap();
    assert!(last < first, "{first} then {last}");
    let measured: usize = sequence.batches.iter().map(|b| b.samples).sum();
    assert_eq!(measured, summary.measured_samples);
    // Fewer samples than the fixed grid of the same candidates.
    assert!(summary.measured_samples < summary.plan.measurable);
    assert!(sequence.stopped.is_some());
    let lines = summary.lines().join("\n");
    assert!(lines.contains("sequential_batches="), "{lines}");

    // Stopped inside the second batch, then resumed: the same batches and the same table.
    let resumed = tempfile::tempdir().unwrap();
    let stop = Arc::new(AtomicBool::new(false));
    let mut stopper = StopAfter {
        after: sequence.batches[0].samples + 3,
        stop: stop.clone(),
        stage: None,
    };
    let first = run(resumed.path(), &mut stopper, stop);
    assert!(matches!(first, MeasureOutcome::Stopped { .. }));
    let go_on = Arc::new(AtomicBool::new(false));
    let mut quiet = StopAfter {
        after: usize::MAX,
        stop: go_on.clone(),
        stage: None,
    };
    assert!(matches!(
        run(resumed.path(), &mut quiet, go_on),
        MeasureOutcome::Complete(_)
    ));
    assert_eq!(record(resumed.path()).batches, sequence.batches);
    let bytes = |dir: &Path| std::fs::read(dir.join("s.binary")).unwrap();
    assert!(
        bytes(whole.path()) == bytes(resumed.path()),
        "the tables differ"
    );
}

#[test]
fn a_time_limit_the_checks_and_the_probe_use_up_measures_nothing_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let mut settings = settings();
    settings.sequential = Some(SequentialSettings {
        max_hours: 0.01,
        ..SequentialSettings::default()
    });
    let never = Arc::new(AtomicBool::new(false));
    let mut quiet = StopAfter {
        after: usize::MAX,
        stop: never.clone(),
        stage: None,
    };
    let result = measure_silver(dir.path(), &settings, &mut quiet, never);
    let Err(WorkflowError::NoTimeLeft {
        limit_h,
        spent_h,
        suggested_h,
        ..
    }) = result
    else {
        panic!("measured with no time left");
    };
    assert_eq!(limit_h, 0.01);
    assert!(spent_h > limit_h, "{spent_h} h");
    assert!(suggested_h > spent_h, "{suggested_h} h after {spent_h} h");
    // Nothing of the main stage was planned, and no table was written.
    let journal = Journal::open_read_only(&dir.path().join("s.sqlite")).unwrap();
    assert!(journal.plan(Stage::Main).unwrap().is_empty());
    assert!(!dir.path().join("s.binary").exists());
}
