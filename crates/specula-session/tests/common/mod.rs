//! What the session's integration tests share: a simulated device, a small plan, running
//! the stage `main` into a journal, and reading the journal back.

use specula_acquisition::calibration::Calibration;
use specula_acquisition::device::Device;
use specula_acquisition::hdr::{HdrCapturer, HdrSettings};
use specula_acquisition::instrument::Instrument;
use specula_acquisition::plan::Plan;
use specula_acquisition::simulator::sample::{MountedSample, Tilt};
use specula_acquisition::simulator::{Simulator, SimulatorConfig};
use specula_core::materials::preset;
use specula_core::Rgb;
use specula_session::engine::{Engine, EngineError, EngineSettings, StageOutcome};
use specula_session::journal::{Journal, PlannedRow};
use specula_session::predict::Predictor;
use specula_session::protocol::client::LinkNotes;
use specula_session::Stage;
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// The UTIA device simulated with a flat-mounted preset and a fixed seed.
pub(crate) fn simulator(material: &str, seed: u64) -> Simulator {
    let device = Device::utia();
    let truth = Arc::new(preset(material).unwrap());
    let sample = MountedSample::new(material, truth, Tilt::default());
    Simulator::new(device.clone(), sample, SimulatorConfig::new(seed, &device))
}

/// The measurable samples of a small grid (degrees; phi_h 45), in plan order.
pub(crate) fn planned_rows(
    theta_h_deg: &[f64],
    theta_d_deg: &[f64],
    phi_d_deg: &[f64],
) -> Vec<PlannedRow> {
    let plan = Plan::from_grid(theta_h_deg, theta_d_deg, phi_d_deg, 45.0, &Device::utia());
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

/// How one run of the stage `main` is set up.
pub(crate) struct MainStage<'a> {
    pub rows: &'a [PlannedRow],
    pub calibration: &'a Calibration,
    /// Raised to stop after the sample in progress.
    pub stop: Arc<AtomicBool>,
    pub link_notes: Option<LinkNotes>,
}

/// Runs the stage `main` into the journal at `path` (created or resumed), calling
/// `after_sample` with the count of samples done after each one.
pub(crate) fn run_main_stage(
    instrument: &mut dyn Instrument,
    path: &Path,
    stage: MainStage,
    after_sample: &mut dyn FnMut(usize),
) -> Result<StageOutcome, EngineError> {
    let mut journal = Journal::open(path).unwrap();
    journal.set_plan(Stage::Main, stage.rows).unwrap();
    let info = instrument.info().unwrap();
    let mut hdr = HdrCapturer::new(HdrSettings::for_device(&info), stage.calibration.noise);
    let mut engine = Engine {
        instrument,
        journal: &mut journal,
        hdr: &mut hdr,
        calibration: stage.calibration,
        settings: EngineSettings::default(),
        stop: stage.stop,
        link_notes: stage.link_notes,
        ran: Vec::new(),
    };
    let predictor = Predictor::new(stage.calibration.clone(), None);
    engine.run_stage(Stage::Main, &predictor, &mut |p| after_sample(p.done))
}

/// The journaled value of every sample of `main`, by sequence number.
pub(crate) fn values(path: &Path) -> BTreeMap<u32, Rgb> {
    let journal = Journal::open_read_only(path).unwrap();
    journal
        .samples(Stage::Main)
        .unwrap()
        .into_iter()
        .map(|(k, s)| (k, s.value))
        .collect()
}

/// How many events of each kind the journal holds.
pub(crate) fn events(path: &Path) -> BTreeMap<String, usize> {
    Journal::open_read_only(path)
        .unwrap()
        .status()
        .unwrap()
        .events
}
