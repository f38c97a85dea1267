//! The lens-flare check (paper 4.3): the paper's lens shows flare "merely as a bright red
//! spot", and the authors "carefully checked all captured images for the presence of local
//! color changes so as to avoid contamination of measured data by this artifact".
//!
//! **Detection** ([`detect_flare`]). The region's pixels are cut into square blocks; each
//! block's dark-subtracted mean gives its chromaticity `(R, G, B) / (R + G + B)`. A block is
//! off-colour when its chromaticity differs from the region's median by more than
//! `min_chroma_shift` and by more than `threshold_sigma` times its noise (from the
//! [`NoiseModel`] and the block's pixel count). Chromaticity ignores a smooth change of
//! brightness across the region but not a coloured spot. Captures with saturated pixels are
//! not judged (clipping changes colour too); an HDR measurement is judged on its best
//! unsaturated capture.
//!
//! **Response** ([`measure_avoiding_flare`]). A flagged sample is retaken at the next free
//! position of the arms (the camera on the other side of the zenith turns the image, and with
//! it the ghost); when every position is flagged, the sample is excluded.

use super::{free_positions, measure_at, CheckError};
use crate::device::Device;
use crate::hdr::{HdrCapturer, HdrMeasurement, HdrValue, NoiseModel};
use crate::instrument::{Capture, Instrument, InstrumentError};
use crate::kinematics::AxisPositions;
use crate::simulator::Simulator;
use serde::Serialize;
use specula_core::HalfDiff;

/// How local colour changes are judged.
#[derive(Debug, Clone, PartialEq)]
pub struct FlareSettings {
    /// Side of a block, pixels.
    pub block_px: u32,
    /// A block is off-colour beyond this many standard deviations of its noise...
    pub threshold_sigma: f64,
    /// ...and beyond this chromaticity difference.
    pub min_chroma_shift: f64,
}

impl Default for FlareSettings {
    fn default() -> Self {
        Self {
            block_px: 6,
            threshold_sigma: 8.0,
            min_chroma_shift: 0.01,
        }
    }
}

/// The judgement of one capture.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FlareVerdict {
    /// True when the block's shift is both significant (over `threshold_sigma`) and large
    /// (over `min_chroma_shift`): the capture shows flare.
    pub flagged: bool,
    /// The largest chromaticity difference of a block from the region's median.
    pub chroma_shift: f64,
    /// That difference in standard deviations of the block's noise.
    pub significance_sigma: f64,
    /// The block's top-left pixel (column, row).
    pub block_px: (u32, u32),
}

/// Judges one capture; `None` when it has no pixels, is saturated or too dark to judge.
pub fn detect_flare(
    capture: &Capture,
    noise: &NoiseModel,
    settings: &FlareSettings,
) -> Option<FlareVerdict> {
    let pixels = capture.pixels.as_ref()?;
    if capture.saturated_fraction.iter().any(|&f| f > 0.0) {
        return None;
    }
    let side = (pixels.len() as f64).sqrt().round() as u32;
    let block = settings.block_px.max(1);
    if side * side != pixels.len() as u32 || side < 2 * block {
        return None;
    }
    let dark = noise.dark_level_dn(capture.exposure_s);
    let per_side = side / block;
    let mut blocks = Vec::with_capacity((per_side * per_side) as usize);
    for by in 0..per_side {
        for bx in 0..per_side {
            let mut sum = [0.0f64; 3];
            for y in by * block..(by + 1) * block {
                for x in bx * block..(bx + 1) * block {
                    let p = pixels[(y * side + x) as usize];
                    for c in 0..3 {
                        sum[c] += p[c] as f64;
                    }
                }
            }
            let n = (block * block) as f64;
            let mean = sum.map(|s| s / n - dark);
            let total: f64 = mean.iter().sum();
            let variance: f64 = mean
                .iter()
                .map(|m| noise.pixel_variance_dn2(*m, capture.exposure_s) / n)
                .sum();
            if total > 0.0 {
                let chroma = mean.map(|m| m / total);
                blocks.push(((bx * block, by * block), chroma, variance.sqrt() / total));
            }
        }
    }
    if blocks.len() < 4 {
        return None;
    }
    let reference: [f64; 3] = std::array::from_fn(|c| {
        let mut values: Vec<f64> = blocks.iter().map(|b| b.1[c]).collect();
        values.sort_by(f64::total_cmp);
        values[values.len() / 2]
    });
    let verdict = blocks
        .iter()
        .map(|(corner, chroma, sigma)| {
            let shift = (0..3)
                .map(|c| (chroma[c] - reference[c]).abs())
                .fold(0.0, f64::max);
            FlareVerdict {
                flagged: false,
                chroma_shift: shift,
                significance_sigma: shift / sigma,
                block_px: *corner,
            }
        })
        .max_by(|a, b| a.significance_sigma.total_cmp(&b.significance_sigma))?;
    Some(FlareVerdict {
        flagged: verdict.significance_sigma > settings.threshold_sigma
            && verdict.chroma_shift > settings.min_chroma_shift,
        ..verdict
    })
}

/// Judges an HDR measurement on its best-exposed unsaturated capture.
pub fn judge(
    measurement: &HdrMeasurement,
    noise: &NoiseModel,
    settings: &FlareSettings,
) -> Option<FlareVerdict> {
    let signal = |c: &Capture| {
        c.mean_raw.iter().fold(f64::MIN, |m, v| m.max(*v)) - noise.dark_level_dn(c.exposure_s)
    };
    measurement
        .captures
        .iter()
        .filter(|c| c.pixels.is_some() && c.saturated_fraction.iter().all(|&f| f == 0.0))
        .max_by(|a, b| signal(a).total_cmp(&signal(b)))
        .and_then(|c| detect_flare(c, noise, settings))
}

/// What became of a sample.
#[derive(Debug, Clone, PartialEq)]
pub enum FlareOutcome {
    /// Measured without flare at `axes`, after `retakes` flagged positions.
    Clean {
        /// The merged HDR value of the clean capture.
        value: HdrValue,
        /// The position it was measured at.
        axes: AxisPositions,
        /// Positions tried before it and flagged for flare.
        retakes: usize,
    },
    /// Every free position was flagged.
    Excluded {
        /// The free positions tried, all flagged.
        positions: usize,
    },
}

/// Measures a sample at the first of `positions` whose capture shows no flare (see the
/// module documentation). The capturer must ask for pixels (`with_pixels`).
pub fn measure_avoiding_flare(
    instrument: &mut dyn Instrument,
    hdr: &mut HdrCapturer,
    positions: &[AxisPositions],
    predicted_rate_dn_s: Option<f64>,
    settings: &FlareSettings,
) -> Result<FlareOutcome, InstrumentError> {
    for (retakes, axes) in positions.iter().enumerate() {
        let measurement = measure_at(instrument, hdr, axes, predicted_rate_dn_s)?;
        let flagged = judge(&measurement, &hdr.noise, settings).is_some_and(|v| v.flagged);
        if !flagged {
            return Ok(FlareOutcome::Clean {
                value: measurement.value,
                axes: *axes,
                retakes,
            });
        }
    }
    Ok(FlareOutcome::Excluded {
        positions: positions.len(),
    })
}

/// Counts of the flare check over a set of samples.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct FlareReport {
    /// Samples with at least one free position.
    pub samples: usize,
    /// Clean at the first position.
    pub clean_first: usize,
    /// Flagged at the first position and clean at another.
    pub retaken: usize,
    /// Flagged at every free position.
    pub excluded: usize,
    /// Samples with no free position (not measured).
    pub unreachable: usize,
}

/// Runs the flare check over `samples`: each measured at its first free position, retaken
/// elsewhere when flagged. Returns the counts and each sample's outcome (`None` when
/// unreachable).
pub fn check_flare(
    instrument: &mut dyn Instrument,
    hdr: &mut HdrCapturer,
    device: &Device,
    samples: &[HalfDiff],
    settings: &FlareSettings,
) -> Result<(FlareReport, Vec<Option<FlareOutcome>>), CheckError> {
    hdr.settings.with_pixels = true;
    let mut report = FlareReport::default();
    let mut outcomes = Vec::with_capacity(samples.len());
    let mut previous: Option<AxisPositions> = None;
    let mut predicted = None;
    for hd in samples {
        let (wi, wo) = hd.to_directions();
        let positions = free_positions(device, wi, wo, previous.as_ref());
        if positions.is_empty() {
            report.unreachable += 1;
            outcomes.push(None);
            continue;
        }
        report.samples += 1;
        let outcome = measure_avoiding_flare(instrument, hdr, &positions, predicted, settings)?;
        match &outcome {
            FlareOutcome::Clean {
                retakes: 0,
                value,
                axes,
            } => {
                report.clean_first += 1;
                predicted = Some(value.brightest_rate_dn_s());
                previous = Some(*axes);
            }
            FlareOutcome::Clean { value, axes, .. } => {
                report.retaken += 1;
                predicted = Some(value.brightest_rate_dn_s());
                previous = Some(*axes);
            }
            FlareOutcome::Excluded { .. } => report.excluded += 1,
        }
        outcomes.push(Some(outcome));
    }
    Ok((report, outcomes))
}

/// The most retakes any sample of [`check_flare`]'s outcomes needed before a clean capture
/// (0 when none was retaken; excluded and unreachable samples do not count).
pub fn most_retakes(outcomes: &[Option<FlareOutcome>]) -> usize {
    outcomes
        .iter()
        .flatten()
        .filter_map(|o| match o {
            FlareOutcome::Clean { retakes, .. } => Some(*retakes),
            FlareOutcome::Excluded { .. } => None,
        })
        .max()
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hdr::HdrSettings;
    use crate::simulator::optics::LensFlare;
    use crate::simulator::sample::{MountedSample, Tilt};
    use crate::simulator::{Simulator, SimulatorConfig};
    use specula_core::materials::preset;
    use std::sync::Arc;

    fn simulator(flare: bool, seed: u64) -> (Simulator, HdrCapturer) {
        let device = Device::utia();
        let mut config = SimulatorConfig::new(seed, &device);
        config.flare = flare.then(LensFlare::default);
        let truth = Arc::new(preset("silver-925").unwrap());
        let mut sim = Simulator::new(
            device,
            MountedSample::new("silver", truth, Tilt::default()),
            config,
        );
        let mut settings = HdrSettings::for_device(&sim.info().unwrap());
        settings.with_pixels = true;
        let hdr = HdrCapturer::new(settings, sim.config().camera.noise_model());
        (sim, hdr)
    }

    /// A sparse grid over the paper's plan: theta_h, theta_d, phi_d at phi_h = 45 deg.
    fn grid() -> Vec<HalfDiff> {
        let mut samples = Vec::new();
        for theta_h in [0.5, 2.0, 5.0, 12.0, 25.0, 45.0] {
            for theta_d in [5.0, 20.0, 35.0, 50.0, 65.0] {
                for phi_d in [0.0, 45.0, 90.0] {
                    samples.push(HalfDiff::from_degrees(theta_h, 45.0, theta_d, phi_d));
                }
            }
        }
        samples
    }

    /// The ghost's share of the region's mean in the red channel at a position.
    fn ghost_share(sim: &Simulator, axes: &AxisPositions) -> f64 {
        let Some(ghost) = sim.ghost(axes, 1.0) else {
            return 0.0;
        };
        let side = sim.config().camera.roi_side_px;
        let covered = (0..side)
            .flat_map(|y| (0..side).map(move |x| (x, y)))
            .filter(|&(x, y)| ghost.covers(x, y))
            .count() as f64;
        let area = covered / (side * side) as f64;
        let added = sim.config().camera.signal_rate_dn_s(ghost.radiance * area)[0];
        added / sim.expected_rate_dn_s(axes)[0].max(1e-300)
    }

    #[test]
    fn flare_is_flagged_where_it_matters_and_nowhere_else() {
        let (mut sim, mut hdr) = simulator(true, 5);
        let device = sim.device().clone();
        let settings = FlareSettings::default();
        let (mut flared, mut caught, mut false_alarms, mut clean) = (0, 0, 0, 0);
        for hd in grid() {
            let (wi, wo) = hd.to_directions();
            for axes in free_positions(&device, wi, wo, None) {
                let measurement = measure_at(&mut sim, &mut hdr, &axes, None).unwrap();
                let verdict = judge(&measurement, &hdr.noise, &settings).unwrap();
                let share = ghost_share(&sim, &axes);
                if share > 0.01 {
                    flared += 1;
                    caught += verdict.flagged as usize;
                } else if sim.ghost(&axes, 1.0).is_none() {
                    clean += 1;
                    false_alarms += verdict.flagged as usize;
                }
            }
        }
        assert!(
            flared >= 10 && clean >= 50,
            "flared {flared}, clean {clean}"
        );
        assert_eq!(
            caught, flared,
            "every capture biased by more than 1 % is flagged"
        );
        assert_eq!(false_alarms, 0, "of {clean} captures without a ghost");
    }

    #[test]
    fn flagged_samples_are_retaken_at_another_position_and_come_out_right() {
        let (mut sim, mut hdr) = simulator(true, 6);
        let device = sim.device().clone();
        let settings = FlareSettings::default();
        let mut retaken = 0;
        for hd in grid() {
            let (wi, wo) = hd.to_directions();
            let mut positions = free_positions(&device, wi, wo, None);
            // The flared positions first, to make the check work for its living.
            positions.sort_by_key(|a| sim.ghost(a, 1.0).is_none());
            let Some(first) = positions.first().copied() else {
                continue;
            };
            let outcome =
                measure_avoiding_flare(&mut sim, &mut hdr, &positions, None, &settings).unwrap();
            let FlareOutcome::Clean {
                value,
                axes,
                retakes,
            } = outcome
            else {
                panic!("{hd:?}: excluded although a position without a ghost exists");
            };
            if ghost_share(&sim, &first) > 0.01 {
                assert!(retakes >= 1, "{hd:?}: flared first position kept");
                retaken += 1;
            }
            let truth = sim.expected_rate_dn_s(&axes);
            for (c, (rate, expected)) in value.rate_dn_s.iter().zip(truth).enumerate() {
                let error = rate / expected - 1.0;
                assert!(error.abs() < 0.01, "{hd:?}: channel {c} off by {error}");
            }
        }
        assert!(retaken >= 10, "only {retaken} samples needed a retake");
    }

    #[test]
    fn check_counts_every_sample_once() {
        let (mut sim, mut hdr) = simulator(true, 8);
        let device = sim.device().clone();
        let samples = grid();
        let (report, outcomes) = check_flare(
            &mut sim,
            &mut hdr,
            &device,
            &samples,
            &FlareSettings::default(),
        )
        .unwrap();
        assert_eq!(outcomes.len(), samples.len());
        assert_eq!(report.samples + report.unreachable, samples.len());
        assert_eq!(
            report.samples,
            report.clean_first + report.retaken + report.excluded
        );
        assert!(report.retaken >= 1, "{report:?}");
        assert!(most_retakes(&outcomes) >= 1);
        assert_eq!(most_retakes(&outcomes[..0]), 0);
    }

    #[test]
    fn without_flare_nothing_is_flagged() {
        let (mut sim, mut hdr) = simulator(false, 7);
        let device = sim.device().clone();
        let (report, outcomes) = check_flare(
            &mut sim,
            &mut hdr,
            &device,
            &grid(),
            &FlareSettings::default(),
        )
        .unwrap();
        assert_eq!(report.retaken + report.excluded, 0, "{report:?}");
        assert_eq!(most_retakes(&outcomes), 0);
    }
}

/// The sparse grid over the paper's plan at phi_h = 45 deg that `specula check flare`
/// visits: 10 theta_h with square-root spacing to 60 deg, theta_d 5 to 80 deg by 15, phi_d
/// 0, 45 and 90 deg.
pub fn survey_samples() -> Vec<HalfDiff> {
    let mut samples = Vec::new();
    for i in 0..10 {
        let theta_h_deg = (i as f64 + 0.5).powi(2) * 60.0 / 100.0;
        for theta_d_deg in [5.0, 20.0, 35.0, 50.0, 65.0, 80.0] {
            for phi_d_deg in [0.0, 45.0, 90.0] {
                samples.push(HalfDiff::from_degrees(
                    theta_h_deg,
                    45.0,
                    theta_d_deg,
                    phi_d_deg,
                ));
            }
        }
    }
    samples
}

/// The simulator's ground truth for the flare check: how many of the free arm positions of
/// the samples put a ghost in the sample's region.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SimulatedGhosts {
    /// Free arm positions of all the samples.
    pub positions: usize,
    /// Those with a ghost in the region (harmless where the sample outshines it).
    pub ghosted: usize,
}

/// Count, on the simulator, the free arm positions of `samples` and those whose lens-flare
/// ghost falls in the region (the truth [`check_flare`] is judged against).
pub fn simulated_ghosts(sim: &Simulator, device: &Device, samples: &[HalfDiff]) -> SimulatedGhosts {
    let mut truth = SimulatedGhosts {
        positions: 0,
        ghosted: 0,
    };
    for hd in samples {
        let (wi, wo) = hd.to_directions();
        for axes in free_positions(device, wi, wo, None) {
            truth.positions += 1;
            truth.ghosted += sim.ghost(&axes, 1.0).is_some() as usize;
        }
    }
    truth
}
