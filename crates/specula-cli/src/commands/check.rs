//! `specula check`: the paper's practical checks (4.2, 4.3) on the simulated device.

use crate::range;
use anyhow::Result;
use specula_acquisition::checks::alignment::{check_alignment, AlignmentSettings};
use specula_acquisition::checks::flare::{
    check_flare, most_retakes, simulated_ghosts, survey_samples, FlareSettings,
};
use specula_acquisition::checks::orientation::{check_orientation, OrientationSettings};
use specula_acquisition::hdr::HdrCapturer;
use specula_acquisition::instrument::Instrument;
use specula_acquisition::simulator::optics::LensFlare;
use specula_acquisition::simulator::sample::{MountedSample, Tilt};
use specula_acquisition::simulator::Simulator;
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
    #[arg(long, default_value_t = 8, value_parser = range::ROTATIONS)]
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
    /// The simulated device with the truth mounted, and its HDR capturer.
    fn build(&self, flare: Option<LensFlare>) -> Result<(Simulator, HdrCapturer)> {
        let truth = load_brdf_scratched(&self.truth, self.scratch_orientation_deg)?;
        let device = super::load_device(self.device.as_deref())?;
        let tilt = Tilt::new(self.tilt_deg, self.tilt_azimuth_deg);
        let sample = MountedSample::new(&self.truth, truth, tilt);
        Ok(Simulator::with_hdr(device, sample, self.seed, flare)?)
    }
}

pub(crate) fn run(args: Args) -> Result<()> {
    match args.check {
        Check::Alignment(a) => alignment(a),
        Check::Orientation(a) => orientation(a),
        Check::Flare(a) => flare(a),
    }
}

fn print_effort(sim: &Simulator, hdr: &HdrCapturer) {
    let stats = &hdr.stats;
    outln!(
        "effort: {} HDR measurements, {} captures ({:.2} per measurement, {:.0} % in one or two), \
         {:.1} min of simulated device time",
        stats.samples,
        stats.captures,
        stats.mean_captures(),
        100.0 * stats.share_at_most(2),
        sim.simulated_clock_s().unwrap_or(0.0) / 60.0
    );
}

fn alignment(args: AlignmentArgs) -> Result<()> {
    let (mut sim, mut hdr) = args.simulated.build(None)?;
    let settings = AlignmentSettings {
        light_elevation_deg: args.light_elevation_deg,
        rotations: args.rotations,
        ..AlignmentSettings::default()
    };
    let spinner = crate::progress::spinner("alignment");
    let report = check_alignment(&mut sim, &mut hdr, &settings)?;
    spinner.finish_and_clear();
    outln!("turntable_deg,highlight_camera_deg,fwhm_deg");
    for peak in &report.peaks {
        outln!(
            "{:.1},{:.4},{:.3}",
            peak.turntable_deg,
            peak.camera_deg,
            peak.width_deg
        );
    }
    let fit = &report.fit;
    outln!(
        "tilt: {:.3} deg towards azimuth {:.1} deg (fit residual {:.3} deg RMS)",
        fit.tilt_deg,
        fit.azimuth_deg,
        fit.residual_rms_deg
    );
    let truth = &args.simulated;
    outln!(
        "simulated truth: {:.3} deg towards azimuth {:.1} deg",
        truth.tilt_deg,
        truth.tilt_azimuth_deg
    );
    outln!(
        "adjustment: {}",
        report.adjustment(sim.device().accuracy_deg)
    );
    print_effort(&sim, &hdr);
    Ok(())
}

fn orientation(args: OrientationArgs) -> Result<()> {
    let (mut sim, mut hdr) = args.simulated.build(None)?;
    let settings = OrientationSettings {
        phi_h_step_deg: args.phi_h_step_deg,
        planned_phi_h_deg: args.phi_h_deg,
        ..OrientationSettings::default()
    };
    let device = sim.device().clone();
    let spinner = crate::progress::spinner("orientation");
    let report = check_orientation(&mut sim, &mut hdr, &device, &settings)?;
    spinner.finish_and_clear();
    outln!("phi_h_deg,excess,contaminated");
    for ((phi, excess), bad) in report
        .phi_h_deg
        .iter()
        .zip(&report.excess)
        .zip(&report.contaminated)
    {
        outln!("{phi:.1},{excess:.4},{bad}");
    }
    outln!(
        "threshold: excess above {:.3} counts as the scratch lobe",
        report.threshold
    );
    if report.anisotropic {
        outln!(
            "anisotropic: yes; recommended phi_h = {:.1} deg (the middle of the longest clean arc)",
            report.recommended_phi_h_deg
        );
    } else {
        outln!(
            "anisotropic: no lobe found; keep phi_h = {:.1} deg",
            report.planned_phi_h_deg
        );
    }
    if report.planned_is_clean {
        outln!("planned phi_h = {:.1} deg: clean", report.planned_phi_h_deg);
    } else {
        outln!(
            "planned phi_h = {:.1} deg: CONTAMINATED; turn the sample by {:+.1} deg on its holder \
             (or plan at phi_h = {:.1} deg)",
            report.planned_phi_h_deg,
            report.turn_sample_deg(),
            report.recommended_phi_h_deg
        );
    }
    print_effort(&sim, &hdr);
    Ok(())
}

fn flare(args: FlareArgs) -> Result<()> {
    let flare = (args.flare_strength_sr > 0.0).then(|| LensFlare {
        strength_sr: args.flare_strength_sr,
        ..LensFlare::default()
    });
    let (mut sim, mut hdr) = args.simulated.build(flare)?;
    let device = sim.device().clone();
    let samples = survey_samples();
    let truth = simulated_ghosts(&sim, &device, &samples);
    let spinner = crate::progress::spinner("flare");
    let (report, outcomes) = check_flare(
        &mut sim,
        &mut hdr,
        &device,
        &samples,
        &FlareSettings::default(),
    )?;
    spinner.finish_and_clear();
    outln!("samples: {} reachable of {}", report.samples, samples.len());
    outln!("clean at the first position: {}", report.clean_first);
    outln!(
        "flagged, retaken at another arm position: {}",
        report.retaken
    );
    outln!("flagged everywhere, excluded: {}", report.excluded);
    outln!("most retakes for one sample: {}", most_retakes(&outcomes));
    outln!(
        "simulated truth: a ghost in the region at {} of the {} free arm \
         positions (harmless where the sample outshines it)",
        truth.ghosted,
        truth.positions
    );
    print_effort(&sim, &hdr);
    Ok(())
}
