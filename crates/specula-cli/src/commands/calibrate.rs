//! `specula calibrate`: the camera's noise model, gains to 1/sr, colour matrix and the
//! instrument's response, on a device through the driver protocol or on the simulated
//! device, stored for later runs.

use super::connect_args::ConnectArgs;
use anyhow::{Context, Result};
use specula_acquisition::calibration::truth_check::{
    TRUTH_CHECK_PHI_D_DEG, TRUTH_CHECK_PHI_H_DEG, TRUTH_CHECK_THETA_D_DEG,
};
use specula_acquisition::calibration::white::WhiteCertificate;
use specula_acquisition::calibration::{Calibration, CalibrationOptions};
use specula_acquisition::device::Device;
use specula_acquisition::instrument::{Instrument, InstrumentError, MountTarget};
use specula_acquisition::simulator::sample::{MountedSample, Tilt};
use specula_acquisition::simulator::{Simulator, SimulatorConfig};
use specula_core::Brdf;
use specula_session::calibrate::{calibrate_device, CalibrationRun};
use std::io::BufRead;
use std::path::PathBuf;
use std::sync::Arc;

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
    let device = super::load_device(args.device.as_deref())?;
    let options = CalibrationOptions {
        white_reflectance: args.white_reflectance,
        white_certificate: args
            .white_certificate
            .as_deref()
            .map(WhiteCertificate::load)
            .transpose()?,
        ..CalibrationOptions::default()
    };
    let (mut instrument, truth) = instrument(&args, &device)?;
    let spinner = crate::progress::spinner("calibrating");
    let yes = args.yes;
    let mut operator = |target: &MountTarget| spinner.suspend(|| mount_by_operator(target, yes));
    let run = calibrate_device(
        instrument.as_mut(),
        &mut operator,
        &device,
        &options,
        &mut |step| spinner.set_message(step.to_string()),
    )?;
    spinner.finish_and_clear();
    run.calibration.save(&args.out)?;
    print_calibration(&run.calibration, &device);
    outln!("written: {}", args.out.display());
    print_check(&run, truth.as_deref(), &device);
    Ok(())
}

/// The device to calibrate and the truth on its turntable, when it is simulated.
type Calibrated = (Box<dyn Instrument>, Option<Arc<dyn Brdf>>);

/// The device to calibrate: the simulator with the truth on its turntable, or a client of
/// `--connect`; and the truth, when there is one.
fn instrument(args: &Args, device: &Device) -> Result<Calibrated> {
    if let Some(truth_name) = &args.truth {
        let truth = specula_formats::load_brdf(truth_name)?;
        let config = SimulatorConfig::new(args.seed, device);
        let sample = MountedSample::new(truth.name(), truth.clone(), Tilt::default());
        let simulator = Simulator::new(device.clone(), sample, config);
        return Ok((Box::new(simulator), Some(truth)));
    }
    let spec = args
        .connect
        .as_deref()
        .context("give --truth or --connect")?;
    Ok((Box::new(args.connect_args.client(spec)?), None))
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

fn print_calibration(cal: &Calibration, device: &Device) {
    let n = &cal.noise;
    outln!(
        "noise model: black {:.2} DN, dark current {:.3} DN/s, read noise {:.3} DN, gain {:.4} DN/e-",
        n.black_level_dn, n.dark_current_dn_s, n.read_noise_dn, n.gain_dn_per_e
    );
    let g = cal.gain_dn_s_per_sr;
    outln!(
        "gain to 1/sr: R {:.5e}  G {:.5e}  B {:.5e} DN/s per 1/sr",
        g[0],
        g[1],
        g[2]
    );
    if let Some(c) = &cal.white_certificate {
        let (r, u) = (c.reflectance, c.uncertainty);
        outln!(
            "white reference: R {:.4} +- {:.4}  G {:.4} +- {:.4}  B {:.4} +- {:.4} (certificate)",
            r[0],
            u[0],
            r[1],
            u[1],
            r[2],
            u[2]
        );
    }
    outln!("colour matrix (camera to linear sRGB):");
    for row in cal.colour_matrix {
        outln!("  {:+.4} {:+.4} {:+.4}", row[0], row[1], row[2]);
    }
    outln!(
        "ColorChecker fit: {:.4} RMS (linear sRGB reflectance)",
        cal.colour_rms_error
    );
    if let Some(fit) = &cal.response {
        outln!(
            "response ({}): light radius {:.4} deg (device file {:.4} deg), scan centre {:+.4} deg, fit residual {:.4} of the peak; resolution {:.3} deg in theta_h",
            fit.reference,
            fit.response.light.radius_deg,
            device.response().light.radius_deg,
            fit.centre_offset_deg,
            fit.rms_relative,
            fit.response.resolution_deg()
        );
    }
}

/// The check measurement, beside the truth's values when there is one.
fn print_check(run: &CalibrationRun, truth: Option<&dyn Brdf>, device: &Device) {
    outln!(
        "check on the sample (theta_d {TRUTH_CHECK_THETA_D_DEG}, phi_d {TRUTH_CHECK_PHI_D_DEG}, phi_h {TRUTH_CHECK_PHI_H_DEG} deg):"
    );
    let truth_of = |check: &specula_acquisition::calibration::truth_check::CheckValue| {
        truth.and_then(|t| t.eval(check.wi, check.wo))
    };
    match truth {
        Some(_) => {
            outln!("theta_h_deg,measured_r,measured_g,measured_b,truth_r,truth_g,truth_b,ratio_g")
        }
        None => outln!("theta_h_deg,measured_r,measured_g,measured_b"),
    }
    for check in &run.checks {
        let m = check.measured;
        match truth_of(check) {
            Some(t) => outln!(
                "{},{:.4e},{:.4e},{:.4e},{:.4e},{:.4e},{:.4e},{:.4}",
                check.theta_h_deg,
                m.x,
                m.y,
                m.z,
                t.x,
                t.y,
                t.z,
                m.y / t.y
            ),
            None => outln!("{},{:.4e},{:.4e},{:.4e}", check.theta_h_deg, m.x, m.y, m.z),
        }
    }
    if truth.is_some() {
        outln!(
            "(near the highlight the light's {:.1} deg disk blurs a sharp lobe: ratios below 1 there \
             are the source's size, not the calibration)",
            device.light_radius_deg()
        );
    }
}
