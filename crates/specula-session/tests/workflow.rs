//! The measurement workflow end to end on the simulated device, with a small plan.

use glam::DVec3;
use specula_acquisition::device::Device;
use specula_core::grid::{PhiDSpan, UnresolvedPeak};
use specula_core::materials::preset;
use specula_core::merl::Bin;
use specula_core::{Brdf, GridSpec, MerlBrdf, Rgb, ThetaDSteps};
use specula_reconstruct::Method;
use specula_session::journal::{Journal, Record, SessionState};
use specula_session::workflow::{
    measure, measured_samples, session_grid, session_main_samples, MeasureOutcome, MeasureSettings,
    Quiet, Source,
};
use specula_session::Stage;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

fn small() -> MeasureSettings {
    MeasureSettings {
        probe_samples: 30,
        grid: GridSpec {
            theta_h_samples: 8,
            theta_d: ThetaDSteps::even(15.0),
            phi_d_step_deg: 45.0,
            ..GridSpec::paper()
        },
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
        None,
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
        journal.samples(Stage::Main).unwrap().len(),
        summary.measured_samples
    );
    assert_eq!(
        journal.samples(Stage::Probe).unwrap().len(),
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

/// silver-925's neighbour green-paint, made not reciprocal: brighter when the camera is
/// nearer the normal than the light, darker the other way round, as the RGL measurements
/// are near grazing (docs/book/src/results.md, "The two halves of phi_d").
struct NotReciprocal(specula_core::materials::Material);

impl Brdf for NotReciprocal {
    fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
        let swap = 1.0 + 0.6 * (wo.z - wi.z);
        self.0.eval(wi, wo).map(|f| f * swap)
    }
    fn name(&self) -> String {
        "not-reciprocal".into()
    }
}

fn simulated(truth: Arc<dyn Brdf>) -> Source {
    Source::Simulated {
        truth,
        speedup: None,
    }
}

#[test]
fn a_half_turn_plan_is_measured_and_reconstructed_by_halves() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("tilted.binary");
    let session = dir.path().join("tilted.sqlite");
    let truth = Arc::new(NotReciprocal(preset("green-paint").unwrap()));
    let grid = GridSpec {
        theta_h_samples: 8,
        theta_d: "15:5@60".parse().unwrap(),
        phi_d_step_deg: 45.0,
        phi_d_span: PhiDSpan::HalfTurn,
        ..GridSpec::recommended()
    };
    let settings = MeasureSettings {
        grid,
        ideal: true,
        point_light: true,
        ..small()
    };
    let outcome = measure(
        simulated(truth.clone()),
        &Device::utia(),
        &settings,
        None,
        &session,
        &out,
        Arc::new(AtomicBool::new(false)),
        &mut Quiet,
    )
    .unwrap();
    let MeasureOutcome::Complete(summary) = outcome else {
        panic!("stopped")
    };
    // theta_d 0, 15, 30, 45, 60, 65, ..., 85; phi_d 0, 45, ..., 180.
    assert_eq!(summary.plan.total, 8 * 10 * 5);
    assert!(summary.phi_d_halves);
    let lines = summary.lines();
    assert!(
        lines.contains(&"phi_d_halves=true".to_string()),
        "{lines:?}"
    );
    // The summary gives the grid measured, without the rule for an unresolved peak (the
    // point light resolves every peak).
    assert!(
        lines.contains(&format!("grid={}", grid.fixed())),
        "{lines:?}"
    );
    let journal = Journal::open_read_only(&session).unwrap();
    let samples = measured_samples(
        &journal.plan(Stage::Main).unwrap(),
        &journal.samples(Stage::Main).unwrap(),
        None,
    );
    let beyond_90 = samples
        .iter()
        .filter(|s| s.hd.phi_d.to_degrees() > 91.0)
        .count();
    assert!(
        beyond_90 > samples.len() / 3,
        "{beyond_90} of {}",
        samples.len()
    );

    // A cell and its light/camera swap (phi_d 45.5 and 134.5 deg at theta_h 20, theta_d
    // 45.5): the measured table keeps most of the truth's difference; the fold, none.
    let table = MerlBrdf::read(&out).unwrap();
    let cell = |phi_d_i| Bin {
        theta_h_i: 42,
        theta_d_i: 45,
        phi_d_i,
    };
    let ratio = |f: &dyn Fn(Bin) -> f64| f(cell(45)) / f(cell(134)) - 1.0;
    let phi_h = settings.grid.phi_h_deg.to_radians();
    let truth_ratio = ratio(&|b| truth.eval_half_diff(b.centre(phi_h)).unwrap().y);
    let measured_ratio = ratio(&|b| table.cell(b.index()).unwrap().y);
    assert!(truth_ratio > 0.3, "{truth_ratio}");
    assert!(
        (0.7..1.3).contains(&(measured_ratio / truth_ratio)),
        "{measured_ratio} vs {truth_ratio}"
    );
    let folded = specula_reconstruct::reconstruct(&samples, Method::Lobe, "folded").unwrap();
    assert_eq!(ratio(&|b| folded.brdf.cell(b.index()).unwrap().y), 0.0);
}

/// A settings record as a journal written before the graded theta_d and the half turn of
/// phi_d kept it: without their keys.
struct OldSettings(serde_json::Value);

impl serde::Serialize for OldSettings {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.0.serialize(s)
    }
}

impl Record for OldSettings {
    const KEY: &'static str = <MeasureSettings as Record>::KEY;
}

#[test]
fn an_old_journal_reads_as_the_paper_grid_and_resumes_on_it() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("silver.binary");
    let session = dir.path().join("silver.sqlite");
    let truth: Arc<dyn Brdf> = Arc::new(preset("silver-925").unwrap());
    let run = |settings: &MeasureSettings, stop: bool| {
        measure(
            simulated(truth.clone()),
            &Device::utia(),
            settings,
            None,
            &session,
            &out,
            Arc::new(AtomicBool::new(stop)),
            &mut Quiet,
        )
    };
    assert_eq!(session_grid(&session).unwrap(), None);
    let stopped = run(&small(), true).unwrap();
    assert!(matches!(stopped, MeasureOutcome::Stopped { .. }));
    let mut old = serde_json::to_value(small()).unwrap();
    let keys = old.as_object_mut().unwrap();
    assert!(keys.remove("theta_d_grazing").is_some() && keys.remove("phi_d_span").is_some());
    Journal::open(&session)
        .unwrap()
        .put_record(&OldSettings(old))
        .unwrap();

    // Read back as the paper's shape, the grid it was started on.
    assert_eq!(session_grid(&session).unwrap(), Some(small().grid));
    let today = MeasureSettings {
        grid: GridSpec::recommended(),
        ..small()
    };
    let refused = run(&today, false).unwrap_err().to_string();
    assert!(
        refused.contains("--phi-d-span: quarter in the session, half-turn asked"),
        "{refused}"
    );
    let resumed = run(&small(), false).unwrap();
    let MeasureOutcome::Complete(summary) = resumed else {
        panic!("stopped")
    };
    assert_eq!(summary.plan.total, 8 * 6 * 3);
    assert!(!summary.phi_d_halves);
}

/// A measurement of `truth` through the simulated light's disk (noise-free) on a small grid
/// whose rule for an unresolved peak allows 6 theta_h positions instead of 4 within `budget`
/// samples; the summary's grid.
fn grid_through_the_disk(truth: &str, budget: usize) -> GridSpec {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m.binary");
    let rule = UnresolvedPeak {
        theta_h_samples: 6,
        theta_d: ThetaDSteps::even(15.0),
        budget_samples: budget,
    };
    let settings = MeasureSettings {
        grid: GridSpec {
            theta_h_samples: 4,
            theta_d: ThetaDSteps::even(30.0),
            unresolved_peak: Some(rule),
            ..small().grid
        },
        ideal: true,
        ..small()
    };
    let outcome = measure(
        simulated(Arc::new(preset(truth).unwrap())),
        &Device::utia(),
        &settings,
        None,
        &dir.path().join("m.sqlite"),
        &out,
        Arc::new(AtomicBool::new(false)),
        &mut Quiet,
    )
    .unwrap();
    let MeasureOutcome::Complete(summary) = outcome else {
        panic!("stopped")
    };
    summary.grid
}

#[test]
fn a_peak_the_disk_hides_gets_more_theta_h_within_the_budget() {
    // green-paint's clear coat (GGX 0.008, half width 0.3 deg) is narrower than the UTIA
    // disk's resolution (1.09 deg): the plan takes the rule's grid, the most theta_h that
    // fit the budget; silver-925 (GGX 0.038, 1.4 deg) keeps the grid it was given.
    let wide = grid_through_the_disk("green-paint", 10_000);
    assert_eq!(
        (wide.theta_h_samples, wide.theta_d),
        (6, ThetaDSteps::even(15.0))
    );
    assert_eq!(wide.unresolved_peak, None);
    let resolved = grid_through_the_disk("silver-925", 10_000);
    assert_eq!(
        (resolved.theta_h_samples, resolved.theta_d),
        (4, ThetaDSteps::even(30.0))
    );
    // A budget no grid of the rule fits: the grid as given.
    let tight = grid_through_the_disk("green-paint", 1);
    assert_eq!(
        (tight.theta_h_samples, tight.theta_d),
        (4, ThetaDSteps::even(30.0))
    );
}

#[test]
fn a_session_from_an_older_specula_resumes_and_records_the_newer_one() {
    use specula_session::journal::NewestVersionRecord;
    let dir = tempfile::tempdir().unwrap();
    let session = dir.path().join("old.sqlite");
    Journal::open(&session)
        .unwrap()
        .put_record(&NewestVersionRecord("0.0.1".into()))
        .unwrap();
    let stopped = measure(
        Source::Simulated {
            truth: Arc::new(preset("silver-925").unwrap()),
            speedup: None,
        },
        &Device::utia(),
        &small(),
        None,
        &session,
        &dir.path().join("old.binary"),
        Arc::new(AtomicBool::new(true)),
        &mut Quiet,
    )
    .unwrap();
    assert!(matches!(stopped, MeasureOutcome::Stopped { .. }));
    let journal = Journal::open_read_only(&session).unwrap();
    assert_eq!(
        journal.record::<NewestVersionRecord>().unwrap(),
        Some(NewestVersionRecord(env!("CARGO_PKG_VERSION").into()))
    );
    assert_eq!(journal.status().unwrap().events.get("version"), Some(&1));
}

#[test]
fn the_prior_method_without_its_basis_is_refused_before_measuring() {
    let dir = tempfile::tempdir().unwrap();
    let session = dir.path().join("prior.sqlite");
    let settings = MeasureSettings {
        method: Method::Prior,
        ..small()
    };
    let refused = measure(
        Source::Simulated {
            truth: Arc::new(preset("silver-925").unwrap()),
            speedup: None,
        },
        &Device::utia(),
        &settings,
        None,
        &session,
        &dir.path().join("prior.binary"),
        Arc::new(AtomicBool::new(false)),
        &mut Quiet,
    )
    .unwrap_err();
    assert_eq!(
        refused.to_string(),
        "reconstructing the samples: the prior method needs a prior basis, and none was given"
    );
    assert!(!session.exists(), "no journal is opened");
}
