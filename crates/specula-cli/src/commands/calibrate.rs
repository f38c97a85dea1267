//! `specula calibrate`: the camera's noise model, gains to 1/sr, colour matrix and the
//! instrument's response, on a device through the driver protocol or on the simulated
//! device, stored for later runs.

use super::connect_args::ConnectArgs;
use anyhow::{Context, Result};
use specula_acquisition::device::Device;
use specula_acquisition::instrument::{Instrument, InstrumentError, MountTarget};
use specula_formats::load_brdf;
use specula_session::calibrate::{run_calibrate, CalibrateRequest};
use specula_session::{CalibrationText, CheckTable};
use std::io::BufRead;
use std::path::PathBuf;

/// Calibrate a device (simulated, or through --connect) and store the result (TOML).
#[derive(clap::Args)]
#[command(group(clap::ArgGroup::new("source").required(true).args(["truth", "connect"])))]
pub(crate) struct Args {
    /// Calibrate the simulated device with this sample on it (measured after calibrating, as
    /// a check): a preset name, a material .toml, a MERL .binary or a model:name fit.
    #[arg(long)]
    pub truth: Option<String>,
    /// Calibrate a device through the driver protocol: tcp://HOST:PORT or exec:COMMAND.
    #[arg(long)]
    pub connect: Option<String>,
    #[command(flatten)]
    pub connect_args: ConnectArgs,
    /// Where to write the calibration (TOML).
    #[arg(long, value_parser = crate::output::OUTPUT_FILE)]
    pub out: PathBuf,
    /// Reflectance of the white reference (0.99 for a Spectralon tile). Range: a fraction above 0
    /// and at most 1.
    #[arg(long, default_value_t = 0.99, value_parser = crate::range::REFLECTANCE)]
    pub white_reflectance: f64,
    /// The white reference's certificate (TOML): reflectance and uncertainty per channel, or
    /// a spectrum integrated per channel.
    #[arg(long, conflicts_with = "white_reflectance")]
    pub white_certificate: Option<PathBuf>,
    /// Assume each target is in place when the device cannot mount it (no prompt).
    #[arg(long)]
    pub yes: bool,
    /// Seed of the simulated device: its positioning errors and its noise.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Device description TOML (default: the paper's UTIA gonioreflectometer).
    #[arg(long, alias = "device-model")]
    pub device: Option<PathBuf>,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let device = Device::load_or_utia(args.device.as_deref())?;
    let request = CalibrateRequest {
        white_reflectance: args.white_reflectance,
        white_certificate: args.white_certificate.clone(),
        seed: args.seed,
        out: args.out.clone(),
    };
    request.validate()?;
    let truth = args.truth.as_deref().map(load_brdf).transpose()?;
    let mut instrument: Box<dyn Instrument> = match (&truth, &args.connect) {
        (Some(truth), _) => Box::new(request.simulator(truth.clone(), &device)),
        (None, spec) => {
            let spec = spec.as_deref().context("give --truth or --connect")?;
            Box::new(args.connect_args.client(spec)?)
        }
    };
    let spinner = crate::progress::spinner("calibrating");
    let yes = args.yes;
    let mut operator = |target: &MountTarget| spinner.suspend(|| mount_by_operator(target, yes));
    let run = run_calibrate(
        &request,
        instrument.as_mut(),
        &mut operator,
        &device,
        &mut |step| spinner.set_message(step.to_string()),
    )?;
    spinner.finish_and_clear();
    let calibration = &run.calibration;
    out!(
        "{}",
        CalibrationText {
            calibration,
            device: &device
        }
    );
    outln!("written: {}", args.out.display());
    let truth = truth.as_deref();
    out!(
        "{}",
        CheckTable {
            run: &run,
            truth,
            device: &device
        }
    );
    Ok(())
}

/// The operator mounts `target`: a prompt on the terminal answered with Enter, or with
/// `yes` nothing asked. A closed input is an error saying how to go without a prompt.
fn mount_by_operator(target: &MountTarget, yes: bool) -> Result<(), InstrumentError> {
    if yes {
        eprintln!("assuming {target} is mounted (--yes)");
        return Ok(());
    }
    eprintln!("mount {target} on the turntable, then press Enter");
    let mut line = String::new();
    match std::io::stdin().lock().read_line(&mut line) {
        Ok(0) | Err(_) => Err(InstrumentError::Disconnected(format!(
            "mounting {target}: no answer from the operator (the input is closed); give --yes when the targets are mounted without a prompt"
        ))),
        Ok(_) => Ok(()),
    }
}
