//! `specula measure`: the paper's whole measurement in one command, resumable.

use super::connect_args::ConnectArgs;
use super::grid_args::GridArgs;
use crate::interrupt::{blame_stop, stop_on_ctrl_c, Interrupted};
use crate::range;
use anyhow::{bail, Context, Result};
use indicatif::ProgressBar;
use specula_accuracy::merl_prior::basis_for;
use specula_acquisition::calibration::Calibration;
use specula_core::request::ProbeRequest;
use specula_core::shown::duration_text;
use specula_core::ProbeSpec;
use specula_session::engine::{Progress, StageOutcome};
use specula_session::journal::SequentialSettings;
use specula_session::protocol::Endpoint;
use specula_session::workflow::{
    summary_path, HdrChoice, MeasureOutcome, Observer, PlanOrder, Source,
};
use specula_session::Stage;
use specula_session::{run_measure, MeasureRequest};
use std::path::PathBuf;

/// Measure a BRDF on the simulated device or on real hardware into a MERL table.
#[derive(clap::Args)]
#[command(group(clap::ArgGroup::new("source").required(true).args(["truth", "connect"])))]
pub(crate) struct Args {
    /// Measure the simulated device with this ground truth (any BRDF).
    #[arg(long)]
    pub truth: Option<String>,
    /// Measure a device through the driver protocol: tcp://HOST:PORT or exec:COMMAND.
    #[arg(long)]
    pub connect: Option<String>,
    /// The camera calibration of a real device (from `specula calibrate`).
    #[arg(long)]
    pub calibration: Option<PathBuf>,
    /// The session journal (SQLite); default OUT.session.sqlite.
    #[arg(long)]
    pub session: Option<PathBuf>,
    /// Seed of the simulated device: its positioning errors and its noise.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Simulated device without noise or positioning error.
    #[arg(hide_short_help = true, long)]
    pub ideal: bool,
    /// Simulate the light as a point instead of its disk.
    #[arg(hide_short_help = true, long)]
    pub point_light: bool,
    /// Probe samples along theta_h. Range: a whole number from 2 to 10000.
    #[arg(hide_short_help = true, long, default_value_t = ProbeSpec::paper().samples, value_parser = range::PROBE_SAMPLES)]
    pub probe_samples: usize,
    #[command(flatten)]
    pub grid: GridArgs,
    /// Order of the samples: optimized or nested (the paper's).
    #[arg(hide_short_help = true, long, default_value_t = PlanOrder::Optimized)]
    pub order: PlanOrder,
    /// HDR at each sample: predicted or bracket (the paper's).
    #[arg(hide_short_help = true, long, default_value_t = HdrChoice::Predicted)]
    pub hdr: HdrChoice,
    /// Reconstruction method (see `specula reconstruct --help`).
    #[arg(long, default_value = "lobe")]
    pub method: specula_reconstruct::Method,
    /// Do not fit through the instrument's response.
    #[arg(hide_short_help = true, long)]
    pub no_deblur: bool,
    /// Skip the alignment and orientation checks.
    #[arg(long)]
    pub skip_checks: bool,
    /// Device time of the whole session at most, hours; the main stage is sequential.
    ///
    /// The session's device time at most (checks, probe and main stage): the main stage is
    /// measured batch by batch where the table is least sure until this, --max-samples or
    /// --target-uncertainty. With --grid-preset the whole grid is measured instead, every
    /// position fixed before the first capture. Range: hours above 0 and at most 1000.
    #[arg(long, default_value_t = SequentialSettings::default().max_hours, value_parser = range::MAX_HOURS, conflicts_with = "grid_preset")]
    pub max_hours: f64,
    /// The main stage's samples at most. Range: a whole number from 10 to 1000000.
    #[arg(hide_short_help = true, long, default_value_t = SequentialSettings::default().max_samples, value_parser = range::MAX_SAMPLES, conflicts_with = "grid_preset")]
    pub max_samples: usize,
    /// Stop when the median relative uncertainty of the table's cells within 75 deg is this,
    /// percent. Range: percent above 0 and at most 100.
    #[arg(hide_short_help = true, long, value_parser = range::TARGET_UNCERTAINTY_PERCENT, conflicts_with = "grid_preset")]
    pub target_uncertainty: Option<f64>,
    /// Tilt of the simulated sample. Range: degrees from 0 to 10.
    #[arg(hide_short_help = true, long, default_value_t = 0.0, value_parser = range::TILT_DEG, alias = "tilt-deg")]
    pub tilt: f64,
    /// Azimuth of that tilt. Range: degrees from -360 to 360.
    #[arg(hide_short_help = true, long, default_value_t = 0.0, allow_negative_numbers = true, value_parser = range::AZIMUTH_DEG, alias = "tilt-azimuth-deg")]
    pub tilt_azimuth: f64,
    /// Device description (TOML); default: the paper's UTIA gonioreflectometer.
    #[arg(long, alias = "device-model")]
    pub device: Option<PathBuf>,
    #[command(flatten)]
    pub connect_args: ConnectArgs,
    /// Run the simulated device in real time / this factor. Range: a factor above 0 and at most 1000000.
    #[arg(hide_short_help = true, long, value_parser = range::SPEEDUP)]
    pub speedup: Option<f64>,
    /// The MERL .binary to write.
    #[arg(long, value_parser = crate::output::OUTPUT_FILE)]
    pub out: PathBuf,
}

impl Args {
    /// The request the options describe.
    fn request(&self) -> MeasureRequest {
        MeasureRequest {
            seed: self.seed,
            ideal: self.ideal,
            point_light: self.point_light,
            probe: ProbeRequest {
                samples: self.probe_samples,
                tilt_deg: self.tilt,
                tilt_azimuth_deg: self.tilt_azimuth,
            },
            family: self.grid.family,
            grid: self.grid.request(),
            order: self.order,
            hdr: self.hdr,
            method: self.method,
            deblur: !self.no_deblur,
            checks: !self.skip_checks,
            sequential: self
                .grid
                .grid_preset
                .is_none()
                .then_some(SequentialSettings {
                    max_hours: self.max_hours,
                    max_samples: self.max_samples,
                    target_uncertainty_rel: self.target_uncertainty.map(|p| p / 100.0),
                }),
            out: self.out.clone(),
            session: self.session.clone(),
        }
    }
}

pub(crate) fn run(args: Args) -> Result<()> {
    let request = args.request();
    request.validate()?;
    if let Some(path) = &args.device {
        let text = path.to_string_lossy();
        if text.starts_with("tcp://") || text.starts_with("exec:") {
            bail!("--device {text}: --device is the device description (TOML); to measure a device through the driver protocol give --connect {text}");
        }
    }
    let device = specula_acquisition::device::Device::load_or_utia(args.device.as_deref())?;
    let source = source(&args)?;
    let session = request.session_path();
    let grid = request.grid()?;
    let stop = stop_on_ctrl_c().context("cannot watch for Ctrl-C")?;
    outln!("session: {}", session.display());
    outln!("grid: {grid}");
    if let Some(limits) = request.sequential()? {
        outln!("main stage: {limits}");
    }
    let mut observer = Bars::default();
    let prior = basis_for(request.method)?;
    let outcome = run_measure(
        &request,
        source,
        &device,
        prior.as_deref(),
        stop.clone(),
        &mut observer,
    )
    .map_err(|e| blame_stop(e.into(), &stop))?;
    observer.finish();
    match outcome {
        MeasureOutcome::Complete(summary) => {
            for line in summary.lines() {
                outln!("{line}");
            }
            outln!(
                "wrote {} and {}",
                args.out.display(),
                summary_path(&args.out).display()
            );
        }
        MeasureOutcome::Stopped {
            stage,
            done,
            planned,
        } => {
            outln!(
                "stopped: {stage} {done} of {planned} samples measured and journaled in {}; run the same command to resume",
                session.display()
            );
            return Err(Interrupted(format!(
                "{done} of {planned} {stage} samples are in {}; run the same command to resume",
                session.display()
            ))
            .into());
        }
    }
    Ok(())
}

fn source(args: &Args) -> Result<Source> {
    if let Some(truth) = &args.truth {
        if args.calibration.is_some() {
            bail!("--calibration is for a real device; the simulated device is calibrated in the session");
        }
        let brdf = specula_formats::source::load_brdf(truth)?;
        return Ok(Source::Simulated {
            truth: brdf,
            speedup: args.speedup,
        });
    }
    let spec = args
        .connect
        .as_deref()
        .context("give --truth or --connect")?;
    let endpoint: Endpoint = spec.parse().map_err(anyhow::Error::msg)?;
    let path = args.calibration.as_ref().with_context(|| {
        format!("{endpoint}: a real device needs --calibration FILE (its camera calibration, from `specula calibrate`)")
    })?;
    let calibration = Calibration::load(path)?;
    Ok(Source::Remote {
        endpoint,
        client: args.connect_args.client_settings()?,
        calibration: Box::new(calibration),
    })
}

/// Progress bars per stage, with the device time left from the time model; without a
/// terminal, progress lines ([`crate::progress::LogLines`]).
#[derive(Default)]
pub(crate) struct Bars {
    bar: Option<ProgressBar>,
    lines: Option<crate::progress::LogLines>,
    stage: String,
}

impl Bars {
    pub(crate) fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
        self.lines = None;
    }
}

impl Observer for Bars {
    fn step(&mut self, message: &str) {
        match &self.bar {
            Some(bar) => bar.println(message),
            None => eprintln!("{message}"),
        }
    }

    fn stage_started(&mut self, stage: Stage, planned: usize, done: usize) {
        self.finish();
        let bar = crate::progress::bar(planned as u64, stage.name());
        bar.set_position(done as u64);
        if done > 0 {
            bar.println(format!(
                "{stage}: resuming, {done} of {planned} samples already measured"
            ));
        }
        self.bar = Some(bar);
        self.lines = crate::progress::LogLines::start(crate::progress::StageState {
            stage: stage.to_string(),
            done,
            planned,
            eta_s: None,
        });
        self.stage = stage.to_string();
    }

    fn sample(&mut self, progress: &Progress) {
        if let Some(lines) = &self.lines {
            lines.update(progress.done, progress.eta_device_s());
        }
        if let Some(bar) = &self.bar {
            bar.set_position(progress.done as u64);
            bar.set_message(format!(
                "{}: device time {} done, {} left",
                self.stage,
                duration_text(progress.device_s_done),
                duration_text(progress.eta_device_s())
            ));
        }
    }

    fn stage_finished(&mut self, stage: Stage, outcome: &StageOutcome) {
        self.finish();
        eprintln!(
            "{stage}: {} samples ({} measured now, {} from the journal){}",
            outcome.resumed + outcome.measured,
            outcome.measured,
            outcome.resumed,
            if outcome.stopped { ", stopped" } else { "" }
        );
    }
}
