//! What a user asks of a practical check on the simulated device (`specula check`): the
//! truth mounted with its tilt, the seed, and the check's own settings, every range checked
//! in one place ([`CheckRequest::validate`]); one entry point ([`run_check`]) whose
//! [`CheckOutcome`] prints as the command's table and verdict.

use super::alignment::{check_alignment, AlignmentReport, AlignmentSettings};
use super::flare::{
    check_flare, most_retakes, simulated_ghosts, survey_samples, FlareReport, FlareSettings,
    SimulatedGhosts,
};
use super::orientation::{check_orientation, OrientationReport, OrientationSettings};
use super::CheckError;
use crate::device::Device;
use crate::hdr::{CaptureStats, HdrCapturer};
use crate::instrument::{Instrument, InstrumentError};
use crate::simulator::optics::LensFlare;
use crate::simulator::sample::{MountedSample, Tilt};
use crate::simulator::Simulator;
use specula_core::range::RangeError;
use specula_core::request::{
    AZIMUTH_DEG, FLARE_STRENGTH_SR, LIGHT_ELEVATION_DEG, PHI_H_STEP_DEG, ROTATIONS, TILT_DEG,
};
use specula_core::Brdf;
use std::fmt;
use std::sync::Arc;

/// Why a check is refused or fails.
#[derive(Debug, thiserror::Error)]
pub enum CheckRunError {
    /// A value outside its range.
    #[error(transparent)]
    Range(#[from] RangeError),
    /// The simulated device could not be set up.
    #[error(transparent)]
    Instrument(#[from] InstrumentError),
    /// The check failed.
    #[error(transparent)]
    Check(#[from] CheckError),
}

/// Which check, with its settings.
#[derive(Debug, Clone, Copy)]
pub enum Check {
    /// The sample's tilt from the highlight at several turntable rotations.
    Alignment {
        /// Elevation of the light, degrees ([`LIGHT_ELEVATION_DEG`]).
        light_elevation_deg: f64,
        /// Turntable rotations, evenly over a turn ([`ROTATIONS`]).
        rotations: usize,
    },
    /// A scan of phi_h for the anisotropic scratch lobe.
    Orientation {
        /// The phi_h the plan uses, degrees ([`AZIMUTH_DEG`]).
        phi_h_deg: f64,
        /// Step of the scan over [0, 180), degrees ([`PHI_H_STEP_DEG`]).
        phi_h_step_deg: f64,
    },
    /// Captures with lens flare flagged and retaken elsewhere.
    Flare {
        /// Radiance factor of the simulated ghost at full light, 1/sr (0: no flare;
        /// [`FLARE_STRENGTH_SR`]).
        strength_sr: f64,
    },
}

/// A check on the simulated device with a truth mounted.
#[derive(Clone)]
pub struct CheckRequest {
    /// The truth's name as the user gave it.
    pub name: String,
    /// The truth on the turntable.
    pub truth: Arc<dyn Brdf>,
    /// Tilt of the sample's normal from the turntable axis, degrees ([`TILT_DEG`]).
    pub tilt_deg: f64,
    /// Azimuth towards which the normal leans, degrees ([`AZIMUTH_DEG`]).
    pub tilt_azimuth_deg: f64,
    /// Seed of the simulated device.
    pub seed: u64,
    /// The device.
    pub device: Device,
    /// The check.
    pub check: Check,
}

/// What a check found.
pub enum Found {
    /// The alignment check's report and the device's positioning accuracy, degrees.
    Alignment(AlignmentReport, f64),
    /// The orientation check's report.
    Orientation(OrientationReport),
    /// The flare check's counts, the most retakes of one sample, the free arm positions
    /// with a ghost (the simulated truth) and the survey's size.
    Flare(FlareReport, usize, SimulatedGhosts, usize),
}

/// A check's outcome: what it found, the simulated truth's tilt and the effort it took.
pub struct CheckOutcome {
    /// What the check found.
    pub found: Found,
    /// The simulated tilt and its azimuth, degrees.
    pub tilt_deg: (f64, f64),
    /// The HDR effort.
    pub effort: CaptureStats,
    /// Simulated device time, seconds.
    pub device_s: f64,
}

impl CheckRequest {
    /// Checks every value against its range (named as the CLI's options' words).
    pub fn validate(&self) -> Result<(), RangeError> {
        TILT_DEG.check("tilt_deg", self.tilt_deg)?;
        AZIMUTH_DEG.check("tilt_azimuth_deg", self.tilt_azimuth_deg)?;
        match self.check {
            Check::Alignment {
                light_elevation_deg,
                rotations,
            } => {
                LIGHT_ELEVATION_DEG.check("light_elevation_deg", light_elevation_deg)?;
                ROTATIONS.check("rotations", rotations)?;
            }
            Check::Orientation {
                phi_h_deg,
                phi_h_step_deg,
            } => {
                AZIMUTH_DEG.check("phi_h_deg", phi_h_deg)?;
                PHI_H_STEP_DEG.check("phi_h_step_deg", phi_h_step_deg)?;
            }
            Check::Flare { strength_sr } => {
                FLARE_STRENGTH_SR.check("flare_strength_sr", strength_sr)?;
            }
        }
        Ok(())
    }

    /// The simulated device with the truth mounted, and its HDR capturer.
    fn simulator(
        &self,
        flare: Option<LensFlare>,
    ) -> Result<(Simulator, HdrCapturer), CheckRunError> {
        let tilt = Tilt::new(self.tilt_deg, self.tilt_azimuth_deg);
        let sample = MountedSample::new(&self.name, self.truth.clone(), tilt);
        Ok(Simulator::with_hdr(
            self.device.clone(),
            sample,
            self.seed,
            flare,
        )?)
    }
}

/// Runs the check `request` asks for on the simulated device.
pub fn run_check(request: &CheckRequest) -> Result<CheckOutcome, CheckRunError> {
    request.validate()?;
    let flare = match request.check {
        Check::Flare { strength_sr } if strength_sr > 0.0 => Some(LensFlare {
            strength_sr,
            ..LensFlare::default()
        }),
        _ => None,
    };
    let (mut sim, mut hdr) = request.simulator(flare)?;
    let device = sim.device().clone();
    let found = match request.check {
        Check::Alignment {
            light_elevation_deg,
            rotations,
        } => {
            let settings = AlignmentSettings {
                light_elevation_deg,
                rotations,
                ..AlignmentSettings::default()
            };
            let report = check_alignment(&mut sim, &mut hdr, &settings)?;
            Found::Alignment(report, device.accuracy_deg)
        }
        Check::Orientation {
            phi_h_deg,
            phi_h_step_deg,
        } => {
            let settings = OrientationSettings {
                phi_h_step_deg,
                planned_phi_h_deg: phi_h_deg,
                ..OrientationSettings::default()
            };
            Found::Orientation(check_orientation(&mut sim, &mut hdr, &device, &settings)?)
        }
        Check::Flare { .. } => {
            let samples = survey_samples();
            let ghosts = simulated_ghosts(&sim, &device, &samples);
            let settings = FlareSettings::default();
            let (report, outcomes) = check_flare(&mut sim, &mut hdr, &device, &samples, &settings)?;
            Found::Flare(report, most_retakes(&outcomes), ghosts, samples.len())
        }
    };
    Ok(CheckOutcome {
        found,
        tilt_deg: (request.tilt_deg, request.tilt_azimuth_deg),
        effort: hdr.stats.clone(),
        device_s: sim.simulated_clock_s().unwrap_or(0.0),
    })
}

impl fmt::Display for CheckOutcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.found {
            Found::Alignment(report, accuracy_deg) => {
                write_alignment(f, report, *accuracy_deg, self.tilt_deg)?
            }
            Found::Orientation(report) => write_orientation(f, report)?,
            Found::Flare(report, retakes, ghosts, surveyed) => {
                writeln!(f, "samples: {} reachable of {surveyed}", report.samples)?;
                writeln!(f, "clean at the first position: {}", report.clean_first)?;
                writeln!(
                    f,
                    "flagged, retaken at another arm position: {}",
                    report.retaken
                )?;
                writeln!(f, "flagged everywhere, excluded: {}", report.excluded)?;
                writeln!(f, "most retakes for one sample: {retakes}")?;
                writeln!(
                    f,
                    "simulated truth: a ghost in the region at {} of the {} free arm \
                     positions (harmless where the sample outshines it)",
                    ghosts.ghosted, ghosts.positions
                )?;
            }
        }
        let stats = &self.effort;
        writeln!(
            f,
            "effort: {} HDR measurements, {} captures ({:.2} per measurement, {:.0} % in one or two), \
             {:.1} min of simulated device time",
            stats.samples,
            stats.captures,
            stats.mean_captures(),
            100.0 * stats.share_at_most(2),
            self.device_s / 60.0
        )
    }
}

/// The highlight per rotation, the fitted tilt against the simulated one, the adjustment.
fn write_alignment(
    f: &mut fmt::Formatter<'_>,
    report: &AlignmentReport,
    accuracy_deg: f64,
    (tilt_deg, tilt_azimuth_deg): (f64, f64),
) -> fmt::Result {
    writeln!(f, "turntable_deg,highlight_camera_deg,fwhm_deg")?;
    for peak in &report.peaks {
        writeln!(
            f,
            "{:.1},{:.4},{:.3}",
            peak.turntable_deg, peak.camera_deg, peak.width_deg
        )?;
    }
    let fit = &report.fit;
    writeln!(
        f,
        "tilt: {:.3} deg towards azimuth {:.1} deg (fit residual {:.3} deg RMS)",
        fit.tilt_deg, fit.azimuth_deg, fit.residual_rms_deg
    )?;
    writeln!(
        f,
        "simulated truth: {tilt_deg:.3} deg towards azimuth {tilt_azimuth_deg:.1} deg"
    )?;
    writeln!(f, "adjustment: {}", report.adjustment(accuracy_deg))
}

/// The excess per phi_h, the threshold, and the verdict on the planned phi_h.
fn write_orientation(f: &mut fmt::Formatter<'_>, report: &OrientationReport) -> fmt::Result {
    writeln!(f, "phi_h_deg,excess,contaminated")?;
    let rows = report.phi_h_deg.iter().zip(&report.excess);
    for ((phi, excess), bad) in rows.zip(&report.contaminated) {
        writeln!(f, "{phi:.1},{excess:.4},{bad}")?;
    }
    writeln!(
        f,
        "threshold: excess above {:.3} counts as the scratch lobe",
        report.threshold
    )?;
    if report.anisotropic {
        writeln!(
            f,
            "anisotropic: yes; recommended phi_h = {:.1} deg (the middle of the longest clean arc)",
            report.recommended_phi_h_deg
        )?;
    } else {
        writeln!(
            f,
            "anisotropic: no lobe found; keep phi_h = {:.1} deg",
            report.planned_phi_h_deg
        )?;
    }
    if report.planned_is_clean {
        writeln!(
            f,
            "planned phi_h = {:.1} deg: clean",
            report.planned_phi_h_deg
        )
    } else {
        writeln!(
            f,
            "planned phi_h = {:.1} deg: CONTAMINATED; turn the sample by {:+.1} deg on its holder \
             (or plan at phi_h = {:.1} deg)",
            report.planned_phi_h_deg,
            report.turn_sample_deg(),
            report.recommended_phi_h_deg
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::materials::preset;

    fn request(check: Check) -> CheckRequest {
        CheckRequest {
            name: "chrome".into(),
            truth: Arc::new(preset("chrome").unwrap()),
            tilt_deg: 2.0,
            tilt_azimuth_deg: 30.0,
            seed: 1,
            device: Device::utia(),
            check,
        }
    }

    #[test]
    fn the_alignment_check_finds_the_simulated_tilt_and_prints_it() {
        let check = Check::Alignment {
            light_elevation_deg: 30.0,
            rotations: 8,
        };
        let outcome = run_check(&request(check)).unwrap();
        let Found::Alignment(report, _) = &outcome.found else {
            panic!("not an alignment");
        };
        assert!(
            (report.fit.tilt_deg - 2.0).abs() < 0.3,
            "{}",
            report.fit.tilt_deg
        );
        let text = outcome.to_string();
        assert!(
            text.starts_with("turntable_deg,highlight_camera_deg,fwhm_deg\n"),
            "{text}"
        );
        assert!(
            text.contains("simulated truth: 2.000 deg towards azimuth 30.0 deg"),
            "{text}"
        );
        assert!(
            text.lines().last().unwrap().starts_with("effort: "),
            "{text}"
        );
    }

    #[test]
    fn out_of_range_values_are_refused_before_the_simulator_runs() {
        let check = Check::Orientation {
            phi_h_deg: 45.0,
            phi_h_step_deg: 50.0,
        };
        let err = run_check(&request(check)).err().unwrap().to_string();
        assert_eq!(
            err,
            "phi_h_step_deg 50: expected degrees above 0 and at most 45"
        );
    }
}
