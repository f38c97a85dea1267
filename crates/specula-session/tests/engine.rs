//! The acquisition loop on the simulated device in process: stopping after the sample in
//! progress, recovering from device faults, giving up on errors no retry fixes, and pacing.

use common::{events, planned_rows, run_main_stage, values, MainStage};
use specula_acquisition::instrument::{Instrument, InstrumentError};
use specula_acquisition::kinematics::AxisPositions;
use specula_acquisition::simulator::Simulator;
use specula_session::engine::{EngineError, StageOutcome};
use specula_session::ideal::exact_calibration;
use specula_session::journal::Journal;
use specula_session::pace::Paced;
use specula_session::Stage;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

mod common;

fn simulator() -> Simulator {
    common::simulator("silver-925", 5)
}

/// Runs stage `main` of a 3 x 3 x 2 plan with `stop`, calling `after_sample` with the count
/// after each sample.
fn acquire(
    instrument: &mut dyn Instrument,
    path: &Path,
    stop: Arc<AtomicBool>,
    after_sample: &mut dyn FnMut(usize),
) -> Result<StageOutcome, EngineError> {
    let rows = planned_rows(&[0.3, 3.0, 15.0], &[5.0, 30.0, 55.0], &[0.0, 60.0]);
    let calibration = exact_calibration(&simulator().config().camera, "sim");
    let stage = MainStage {
        rows: &rows,
        calibration: &calibration,
        stop,
        link_notes: None,
    };
    run_main_stage(instrument, path, stage, after_sample)
}

/// The whole stage without interruption.
fn acquire_all(instrument: &mut dyn Instrument, path: &Path) -> Result<StageOutcome, EngineError> {
    acquire(
        instrument,
        path,
        Arc::new(AtomicBool::new(false)),
        &mut |_| {},
    )
}

#[test]
fn a_stop_finishes_the_sample_in_progress_and_the_rest_resumes_identically() {
    let dir = tempfile::tempdir().unwrap();
    let whole = dir.path().join("whole.sqlite");
    acquire_all(&mut simulator(), &whole).unwrap();
    let expected = values(&whole);

    let path = dir.path().join("stopped.sqlite");
    let stop = Arc::new(AtomicBool::new(false));
    let flag = stop.clone();
    // The flag goes up while sample 3 is the last finished: it is journaled, then the loop
    // stops before the next one.
    let outcome = acquire(&mut simulator(), &path, stop, &mut |done| {
        if done == 3 {
            flag.store(true, Ordering::SeqCst);
        }
    })
    .unwrap();
    assert!(outcome.stopped && !outcome.complete());
    assert_eq!(outcome.measured, 3);
    assert_eq!(values(&path).len(), 3);
    assert_eq!(events(&path).get("interrupted"), Some(&1));

    // A new process (a new simulator) resumes: the rest only, and the same values.
    let outcome = acquire_all(&mut simulator(), &path).unwrap();
    assert_eq!((outcome.resumed, outcome.measured), (3, expected.len() - 3));
    assert_eq!(values(&path), expected);
}

#[test]
fn a_motor_fault_costs_a_home_and_a_retry_not_a_different_value() {
    let dir = tempfile::tempdir().unwrap();
    let whole = dir.path().join("whole.sqlite");
    acquire_all(&mut simulator(), &whole).unwrap();

    let mut faulty = simulator();
    // Calls: info, then per sample a move, light changes and captures: the 9th and 20th are
    // somewhere inside samples.
    faulty.schedule_fault(9, InstrumentError::MotorFault("following error".into()));
    faulty.schedule_fault(20, InstrumentError::CameraFault("frame lost".into()));
    let path = dir.path().join("faulty.sqlite");
    let outcome = acquire_all(&mut faulty, &path).unwrap();
    assert!(outcome.complete());
    let events = events(&path);
    assert_eq!(events.get("fault"), Some(&2), "{events:?}");
    assert_eq!(
        events.get("recovered"),
        Some(&1),
        "homed after the motor fault only: {events:?}"
    );
    // Homing moves the axes away, so the retried sample's captures are the fault-free ones.
    // The camera fault's retry repeats a capture at the same position: another noisy frame.
    let (got, expected) = (values(&path), values(&whole));
    let identical = got.iter().filter(|(k, v)| expected[k] == **v).count();
    assert!(identical >= 2, "{identical} of {}", got.len());
    for (k, v) in &got {
        let relative = (*v - expected[k]).abs() / expected[k];
        assert!(
            relative.max_element() < 0.01,
            "sample {k}: {v} vs {}",
            expected[k]
        );
    }
    let journal = Journal::open_read_only(&path).unwrap();
    let tries: u32 = journal
        .samples(Stage::Main)
        .unwrap()
        .values()
        .map(|s| s.attempts)
        .sum();
    assert_eq!(tries as usize, got.len() + 2, "one extra try per fault");
}

/// A device whose every move fails the same way.
struct Stuck;
impl Instrument for Stuck {
    fn home(&mut self) -> Result<AxisPositions, InstrumentError> {
        Ok(AxisPositions::new(0.0, 0.0, 0.0, 0.0))
    }
    fn move_to(&mut self, _: &AxisPositions) -> Result<AxisPositions, InstrumentError> {
        Err(InstrumentError::MotorFault(
            "turntable: amplifier over temperature".into(),
        ))
    }
    fn set_light(&mut self, _: f64) -> Result<(), InstrumentError> {
        Ok(())
    }
    fn capture(
        &mut self,
        _: f64,
        _: bool,
    ) -> Result<specula_acquisition::instrument::Capture, InstrumentError> {
        Err(InstrumentError::CameraFault("no frame".into()))
    }
    fn info(&mut self) -> Result<specula_acquisition::instrument::InstrumentInfo, InstrumentError> {
        simulator().info()
    }
}

#[test]
fn a_persistent_fault_stops_with_an_error_naming_the_sample() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("stuck.sqlite");
    let err = acquire_all(&mut Stuck, &path).unwrap_err();
    let text = err.to_string();
    assert!(
        text.starts_with("main sample 0: motor fault: turntable"),
        "{text}"
    );
    assert!(
        text.contains("after 3 tries") && text.contains("run the same command again"),
        "{text}"
    );
    assert!(values(&path).is_empty());
    assert_eq!(events(&path).get("fault"), Some(&3));
}

#[test]
fn pacing_takes_the_device_time_over_the_speedup() {
    let mut paced = Paced::new(simulator(), 1000.0);
    let before = paced.simulated_clock_s().unwrap();
    let started = Instant::now();
    paced
        .move_to(&AxisPositions::from_degrees(90.0, 40.0, 180.0, -40.0))
        .unwrap();
    let device_s = paced.simulated_clock_s().unwrap() - before;
    assert!(device_s > 5.0, "a long move: {device_s} s");
    assert!(started.elapsed() >= Duration::from_secs_f64(device_s / 1000.0));
}
