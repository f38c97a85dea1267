//! `specula calibrate`: the camera's noise model, gains to 1/sr and colour matrix on the
//! simulated device, stored for later runs.

use anyhow::Result;
use specula_acquisition::calibration::truth_check::{
    check_against_truth, TRUTH_CHECK_PHI_D_DEG, TRUTH_CHECK_PHI_H_DEG, TRUTH_CHECK_THETA_D_DEG,
    TRUTH_CHECK_THETA_H_DEG,
};
use specula_acquisition::calibration::{calibrate, mount_in_simulator, CalibrationOptions};
use specula_acquisition::simulator::sample::{MountedSample, Tilt};
use specula_acquisition::simulator::{Simulator, SimulatorConfig};
use specula_session::workflow::simulated_response;
use std::path::PathBuf;

/// Calibrate the simulated device's camera and store the result (TOML) for later runs.
///
/// With a white reference and the 24 ColorChecker patches mounted in turn at the 45/0
/// geometry: dark frames and the photon transfer curve give the noise model (black level,
/// dark current, read noise, conversion gain); the white reference gives each channel's gain
/// to 1/sr; the patches' published values give the 3x3 colour matrix by least squares. Then
/// the --truth sample is mounted and a few of its values are measured and compared with the
/// truth.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The sample measured after calibrating, as a check: a preset name, a material .toml, a
    /// MERL .binary or a model:name fit.
    #[arg(long)]
    pub truth: String,
    /// Where to write the calibration (TOML).
    #[arg(long, value_parser = crate::output::OUTPUT_FILE)]
    pub out: PathBuf,
    /// Reflectance of the white reference (0.99 for a Spectralon tile). Range: a fraction
    /// above 0 and at most 1.
    #[arg(long, default_value_t = 0.99, value_parser = crate::range::REFLECTANCE)]
    pub white_reflectance: f64,
    /// Seed of the simulated device: its positioning errors and its noise.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Device description TOML (default: the paper's UTIA gonioreflectometer).
    #[arg(long, alias = "device-model")]
    pub device: Option<PathBuf>,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let truth = specula_formats::load_brdf(&args.truth)?;
    let device = super::load_device(args.device.as_deref())?;
    let config = SimulatorConfig::new(args.seed, &device);
    let sample = MountedSample::new(&args.truth, truth.clone(), Tilt::default());
    let mut sim = Simulator::new(device.clone(), sample.clone(), config);

    let options = CalibrationOptions {
        white_reflectance: args.white_reflectance,
        ..CalibrationOptions::default()
    };
    let spinner = crate::progress::spinner("calibrating");
    let mut cal = calibrate(&mut sim, mount_in_simulator, &options)?;
    spinner.set_message("calibrating: the response, a mirror across the light");
    let fit = simulated_response(&mut sim, &cal, &device)?;
    cal.response = Some(fit);
    spinner.finish_and_clear();
    cal.save(&args.out)?;

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
    outln!("written: {}", args.out.display());

    // The truth back on the turntable: calibrated values against the truth.
    sim.mount(sample);
    let checks = check_against_truth(
        &mut sim,
        &device,
        &cal,
        truth.as_ref(),
        &TRUTH_CHECK_THETA_H_DEG,
    )?;
    outln!(
        "check on {} (theta_d {TRUTH_CHECK_THETA_D_DEG}, phi_d {TRUTH_CHECK_PHI_D_DEG}, phi_h {TRUTH_CHECK_PHI_H_DEG} deg):",
        args.truth
    );
    outln!("theta_h_deg,measured_r,measured_g,measured_b,truth_r,truth_g,truth_b,ratio_g");
    for check in &checks {
        let (measured, expected) = (check.measured, check.truth);
        outln!(
            "{},{:.4e},{:.4e},{:.4e},{:.4e},{:.4e},{:.4e},{:.4}",
            check.theta_h_deg,
            measured.x,
            measured.y,
            measured.z,
            expected.x,
            expected.y,
            expected.z,
            check.green_ratio()
        );
    }
    outln!(
        "(near the highlight the light's {:.1} deg disk blurs a sharp lobe: ratios below 1 there \
         are the source's size, not the calibration)",
        device.light_radius_deg()
    );
    Ok(())
}
