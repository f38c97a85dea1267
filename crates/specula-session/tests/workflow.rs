//! The measurement workflow end to end on the simulated device, with a small plan.

use specula_acquisition::device::Device;
use specula_core::materials::preset;
use specula_session::journal::{Journal, SessionState};
use specula_session::workflow::{
    measure, session_main_samples, MeasureOutcome, MeasureSettings, Quiet, Source, STAGE_MAIN,
    STAGE_PROBE,
};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

fn small() -> MeasureSettings {
    MeasureSettings {
        probe_samples: 30,
        theta_h_samples: 8,
        theta_d_step_deg: 15.0,
        phi_d_step_deg: 45.0,
        checks: false,
        ..MeasureSettings::default()
    }
}

#[test]
fn a_small_measurement_completes_and_summarises() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("silver.binary");
    let session = dir.path().join("silver.sqlite");
    let truth = Arc::new(preset("silver-925").unwrap());
    let outcome = measure(
        Source::Simulated {
            truth,
            speedup: None,
        },
        &Device::utia(),
        &small(),
        &session,
        &out,
        Arc::new(AtomicBool::new(false)),
        &mut Quiet,
    )
    .unwrap();
    let MeasureOutcome::Complete(summary) = outcome else {
        panic!("stopped")
    };
    let lines = summary.lines();
    let line = |key: &str| lines.iter().find(|l| l.starts_with(key)).cloned();
    assert_eq!(
        line("measured_samples="),
        Some(format!("measured_samples={}", summary.measured_samples))
    );
    assert!(line("simulated_hours=").is_some(), "{lines:?}");
    assert!((2.0..10.0).contains(&summary.k_hat), "{}", summary.k_hat);
    // The plan's counts add up, and every measurable sample was measured.
    let plan = summary.plan;
    assert_eq!(plan.total, 8 * 6 * 3);
    assert_eq!(plan.measurable + plan.limit + plan.occluded, plan.total);
    assert_eq!(summary.measured_samples, plan.measurable);
    assert!(summary.captures >= summary.measured_samples);
    assert_eq!(
        std::fs::read_to_string(specula_session::workflow::summary_path(&out)).unwrap(),
        lines.join("\n") + "\n"
    );
    let journal = Journal::open_read_only(&session).unwrap();
    assert_eq!(
        journal.samples(STAGE_MAIN).unwrap().len(),
        summary.measured_samples
    );
    assert_eq!(
        journal.samples(STAGE_PROBE).unwrap().len(),
        summary.probe_samples
    );
    assert!(out.exists());
    assert_eq!(journal.status().unwrap().state(), SessionState::Complete);
    let (samples, response) = session_main_samples(&session).unwrap();
    assert_eq!(samples.len(), summary.measured_samples);
    assert!(
        response.is_some(),
        "the simulator's calibration measures its response"
    );
}

#[test]
fn a_session_without_main_samples_has_nothing_to_reconstruct() {
    let dir = tempfile::tempdir().unwrap();
    let session = dir.path().join("empty.sqlite");
    drop(Journal::open(&session).unwrap());
    let err = session_main_samples(&session).unwrap_err().to_string();
    assert!(
        err.contains("empty.sqlite: the session has no measured sample in its main stage"),
        "{err}"
    );
}
