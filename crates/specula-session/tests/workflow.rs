//! The measurement workflow end to end on the simulated device, with a small plan.

use specula_acquisition::device::Device;
use specula_core::materials::preset;
use specula_session::journal::Journal;
use specula_session::workflow::{
    measure, MeasureOutcome, MeasureSettings, Quiet, Source, STAGE_MAIN, STAGE_PROBE,
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
    let started = std::time::Instant::now();
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
    eprintln!("took {:?}", started.elapsed());
    let MeasureOutcome::Complete(summary) = outcome else {
        panic!("stopped")
    };
    for line in summary.lines() {
        eprintln!("{line}");
    }
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
}
