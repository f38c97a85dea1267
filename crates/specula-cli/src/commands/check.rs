//! `specula check`: the paper's practical checks (4.2, 4.3) on the simulated device.

use crate::range;
use anyhow::Result;
use specula_acquisition::{run_check, CheckRequest};
use specula_core::GridSpec;
use specula_formats::source::load_brdf_scratched;
use std::path::PathBuf;

/// Run a practical check of the paper (4.2, 4.3) on the simulated device.
#[derive(clap::Args)]
pub(crate) struct Args {
    #[command(subcommand)]
    pub check: Check,
}

#[derive(clap::Subcommand)]
pub(crate) enum Check {
    /// Estimate the sample's tilt from the highlight at several turntable rotations.
    Alignment(AlignmentArgs),
    /// Scan phi_h for the anisotropic scratch lobe and recommend a phi_h free of it.
    Orientation(OrientationArgs),
    /// Flag captures with lens flare and retake them elsewhere (the simulator adds flare).
    Flare(FlareArgs),
}

/// The simulated device and what is mounted on it.
#[derive(clap::Args)]
pub(crate) struct Simulated {
    /// The ground truth on the turntable: a preset name, a material .toml, a MERL .binary or
    /// a model:name fit.
    #[arg(long)]
    pub truth: String,
    /// Tilt of the sample's normal from the turntable axis, degrees (misalignment). Range: degrees
    /// from 0 to 10.
    #[arg(long = "tilt", alias = "tilt-deg", default_value_t = 0.0, value_parser = range::TILT_DEG)]
    pub tilt_deg: f64,
    /// Azimuth towards which the normal leans, degrees (turntable frame). Range: degrees from -360
    /// to 360.
    #[arg(long = "tilt-azimuth", alias = "tilt-azimuth-deg", default_value_t = 0.0, allow_negative_numbers = true, value_parser = range::AZIMUTH_DEG)]
    pub tilt_azimuth_deg: f64,
    /// Add polishing scratches along this direction, degrees from the sample's x axis. Range:
    /// degrees from -360 to 360.
    #[arg(long = "scratch-orientation", alias = "scratch-orientation-deg", allow_negative_numbers = true, value_parser = range::AZIMUTH_DEG)]
    pub scratch_orientation_deg: Option<f64>,
    /// Seed of the simulated device: its positioning errors and its noise.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Device description TOML (default: the paper's UTIA gonioreflectometer; see
    /// `specula plan --print-device`).
    #[arg(long, alias = "device-model")]
    pub device: Option<PathBuf>,
}

#[derive(clap::Args)]
pub(crate) struct AlignmentArgs {
    #[command(flatten)]
    pub simulated: Simulated,
    /// Elevation of the light, degrees; the camera scans around the same angle. Range: degrees from
    /// 5 to 75.
    #[arg(long = "light-elevation", alias = "light-elevation-deg", default_value_t = 30.0, value_parser = range::LIGHT_ELEVATION_DEG)]
    pub light_elevation_deg: f64,
    /// Turntable rotations, evenly over a turn. Range: a whole number from 3 to 72.
    #[arg(long, default_value_t = specula_acquisition::checks::alignment::AlignmentSettings::default().rotations, value_parser = range::ROTATIONS)]
    pub rotations: usize,
}

#[derive(clap::Args)]
pub(crate) struct OrientationArgs {
    #[command(flatten)]
    pub simulated: Simulated,
    /// The phi_h the plan uses, degrees (45 in the paper). Range: degrees from -360 to 360.
    #[arg(long = "phi-h", alias = "phi-h-deg", default_value_t = GridSpec::paper().phi_h_deg, allow_negative_numbers = true, value_parser = range::AZIMUTH_DEG)]
    pub phi_h_deg: f64,
    /// Step of the phi_h scan over [0, 180), degrees. Range: degrees above 0 and at most 45.
    #[arg(long = "phi-h-step", alias = "phi-h-step-deg", default_value_t = 3.0, value_parser = range::PHI_H_STEP_DEG)]
    pub phi_h_step_deg: f64,
}

#[derive(clap::Args)]
pub(crate) struct FlareArgs {
    #[command(flatten)]
    pub simulated: Simulated,
    /// Radiance factor of the simulated ghost at full light, 1/sr (0 = no flare). Range: 1/sr from
    /// 0 to 10.
    #[arg(long = "flare-strength", alias = "flare-strength-sr", default_value_t = 0.05, value_parser = range::FLARE_STRENGTH_SR)]
    pub flare_strength_sr: f64,
}

impl Simulated {
    /// The request of `check` on the simulated device with the truth mounted.
    fn request(self, check: specula_acquisition::Check) -> Result<CheckRequest> {
        Ok(CheckRequest {
            truth: load_brdf_scratched(&self.truth, self.scratch_orientation_deg)?,
            name: self.truth,
            tilt_deg: self.tilt_deg,
            tilt_azimuth_deg: self.tilt_azimuth_deg,
            seed: self.seed,
            device: specula_acquisition::device::Device::load_or_utia(self.device.as_deref())?,
            check,
        })
    }
}

pub(crate) fn run(args: Args) -> Result<()> {
    use specula_acquisition::Check as Asked;
    let (name, request) = match args.check {
        Check::Alignment(a) => (
            "alignment",
            a.simulated.request(Asked::Alignment {
                light_elevation_deg: a.light_elevation_deg,
                rotations: a.rotations,
            })?,
        ),
        Check::Orientation(a) => (
            "orientation",
            a.simulated.request(Asked::Orientation {
                phi_h_deg: a.phi_h_deg,
                phi_h_step_deg: a.phi_h_step_deg,
            })?,
        ),
        Check::Flare(a) => (
            "flare",
            a.simulated.request(Asked::Flare {
                strength_sr: a.flare_strength_sr,
            })?,
        ),
    };
    let spinner = crate::progress::spinner(name);
    let outcome = run_check(&request)?;
    spinner.finish_and_clear();
    out!("{outcome}");
    Ok(())
}
