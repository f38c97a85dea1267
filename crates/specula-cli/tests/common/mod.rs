//! Shared by the report tests: a small measurement of silver-925 on the simulated device,
//! possibly stopped part way as Ctrl-C stops one, and `specula report` run on its journal.

use specula_acquisition::device::Device;
use specula_core::materials::preset;
use specula_core::{GridSpec, ThetaDSteps};
use specula_session::engine::{Progress, StageOutcome};
use specula_session::workflow::{measure, MeasureSettings, Observer, Source};
use specula_session::Stage;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Raises the stop flag once `stage` has `samples` samples, as Ctrl-C would.
struct StopAfter {
    stage: Option<Stage>,
    samples: usize,
    current: Option<Stage>,
    stop: Arc<AtomicBool>,
}

impl Observer for StopAfter {
    fn step(&mut self, _: &str) {}
    fn stage_started(&mut self, stage: Stage, _: usize, _: usize) {
        self.current = Some(stage);
    }
    fn sample(&mut self, progress: &Progress) {
        if self.current == self.stage && progress.done >= self.samples {
            self.stop.store(true, Ordering::SeqCst);
        }
    }
    fn stage_finished(&mut self, _: Stage, _: &StageOutcome) {}
}

/// Measures silver-925 with a small plan (30 probe samples, 8 theta_h x 6 theta_d x 3 phi_d,
/// no checks, seed 3) into `dir`; with `stop_after` = (stage, n) it stops once that stage
/// has n samples. Returns the session journal and the table (written only when complete).
pub(crate) fn measure_small(dir: &Path, stop_after: Option<(Stage, usize)>) -> (PathBuf, PathBuf) {
    let settings = MeasureSettings {
        seed: 3,
        probe_samples: 30,
        grid: GridSpec {
            theta_h_samples: 8,
            theta_d: ThetaDSteps::even(15.0),
            phi_d_step_deg: 45.0,
            ..GridSpec::paper()
        },
        checks: false,
        ..MeasureSettings::default()
    };
    let table = dir.join("silver.binary");
    let session = dir.join("silver.session.sqlite");
    let stop = Arc::new(AtomicBool::new(false));
    let mut observer = StopAfter {
        stage: stop_after.map(|(stage, _)| stage),
        samples: stop_after.map_or(usize::MAX, |(_, samples)| samples),
        current: None,
        stop: stop.clone(),
    };
    let truth = Arc::new(preset("silver-925").expect("a preset"));
    measure(
        Source::Simulated {
            truth,
            speedup: None,
        },
        &Device::utia(),
        &settings,
        None,
        &session,
        &table,
        stop,
        &mut observer,
    )
    .expect("the simulated measurement runs");
    (session, table)
}

/// `specula report INPUT --out OUT` with renders of `render_px` square at 2 samples per
/// pixel, and `extra`.
pub(crate) fn report(input: &Path, out: &Path, render_px: usize, extra: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_specula"))
        .arg("report")
        .arg(input)
        .arg("--out")
        .arg(out)
        .args(["--size", &render_px.to_string(), "--spp", "2"])
        .args(extra)
        .output()
        .expect("specula runs")
}
