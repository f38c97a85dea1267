//! The orientation check (paper 4.3): polishing leaves scratches whose anisotropic lobe an
//! isotropic half-difference table cannot hold; "these artifacts can be often avoided by
//! selecting a proper value of the phi_h parameter, i.e., by an appropriate initial
//! orientation of a sample".
//!
//! An isotropic BRDF does not depend on `phi_h`. The check measures rings of `phi_h` over
//! `[0, 180)` deg (the scratch lobe repeats every 180 deg) at a few `theta_h` just off the
//! highlight, where the lobe across the scratches stands out against the isotropic base, at
//! fixed `theta_d` and `phi_d`. At each `theta_h` a value's excess over the ring's median is
//! the anisotropy; a `phi_h` is contaminated where the excess at any `theta_h` exceeds
//! `max(min_excess, 5 robust sigma)` of the ring. The recommended `phi_h` is the middle of
//! the longest clean arc: the farthest from the lobe. The report says whether the plan's
//! `phi_h` (45 deg in the paper) is clean, and by how much to turn the sample on its holder to
//! measure at the recommended one instead.

use super::{free_positions, intensity, measure_at, CheckError};
use crate::device::Device;
use crate::hdr::HdrCapturer;
use crate::instrument::Instrument;
use serde::Serialize;
use specula_core::statistics::{median, normal_scale_of_absolute};
use specula_core::HalfDiff;

/// Where the rings are measured.
#[derive(Debug, Clone, PartialEq)]
pub struct OrientationSettings {
    /// The rings' theta_h, degrees: just off the highlight.
    pub theta_h_deg: Vec<f64>,
    /// The rings' theta_d, degrees.
    pub theta_d_deg: f64,
    /// The rings' phi_d, degrees.
    pub phi_d_deg: f64,
    /// Step of phi_h over [0, 180), degrees.
    pub phi_h_step_deg: f64,
    /// The phi_h the plan uses (45 deg in the paper).
    pub planned_phi_h_deg: f64,
    /// The smallest relative excess counted as contamination.
    pub min_excess: f64,
}

impl Default for OrientationSettings {
    fn default() -> Self {
        Self {
            theta_h_deg: vec![4.0, 8.0],
            theta_d_deg: 30.0,
            phi_d_deg: 90.0,
            phi_h_step_deg: 3.0,
            planned_phi_h_deg: specula_core::GridSpec::paper().phi_h_deg,
            min_excess: 0.05,
        }
    }
}

/// The result of the orientation check.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OrientationReport {
    /// The ring's phi_h, degrees.
    pub phi_h_deg: Vec<f64>,
    /// Largest relative excess over the ring's median across the theta_h rings.
    pub excess: Vec<f64>,
    /// The excess above which a phi_h counts as contaminated.
    pub threshold: f64,
    /// For each phi_h, whether its excess is above `threshold`.
    pub contaminated: Vec<bool>,
    /// True when some phi_h is contaminated.
    pub anisotropic: bool,
    /// The middle of the longest clean arc (the plan's phi_h when nothing is contaminated),
    /// degrees in [0, 180).
    pub recommended_phi_h_deg: f64,
    /// The plan's phi_h and whether it and its neighbours are clean.
    pub planned_phi_h_deg: f64,
    /// True when the planned phi_h and its neighbours on the ring are all clean.
    pub planned_is_clean: bool,
    /// HDR measurements taken.
    pub measurements: usize,
}

impl OrientationReport {
    /// The turn of the sample on its holder about its normal (degrees, counter-clockwise seen
    /// from above) that brings what is now at the recommended phi_h to the plan's phi_h; in
    /// (-90, 90], since the lobe repeats every 180 deg.
    pub fn turn_sample_deg(&self) -> f64 {
        let turn = (self.planned_phi_h_deg - self.recommended_phi_h_deg).rem_euclid(180.0);
        if turn > 90.0 {
            turn - 180.0
        } else {
            turn
        }
    }
}

/// The analysis of measured rings: `rings[k][i]` is the value at `theta_h[k]`, `phi_h[i]`.
pub fn analyse(
    phi_h_deg: &[f64],
    rings: &[Vec<f64>],
    settings: &OrientationSettings,
) -> OrientationReport {
    let n = phi_h_deg.len();
    let mut excess = vec![f64::MIN; n];
    let mut threshold = settings.min_excess;
    for ring in rings {
        let baseline = median(&mut ring.clone());
        let relative: Vec<f64> = ring.iter().map(|v| v / baseline - 1.0).collect();
        let mut deviations: Vec<f64> = relative.iter().map(|r| r.abs()).collect();
        threshold = threshold.max(5.0 * normal_scale_of_absolute(&mut deviations));
        for (e, r) in excess.iter_mut().zip(&relative) {
            *e = e.max(*r);
        }
    }
    let contaminated: Vec<bool> = excess.iter().map(|e| *e > threshold).collect();
    let anisotropic = contaminated.iter().any(|&c| c);
    let step = settings.phi_h_step_deg;
    let recommended = if anisotropic {
        longest_clean_arc_middle(phi_h_deg, &contaminated, step)
    } else {
        settings.planned_phi_h_deg.rem_euclid(180.0)
    };
    // The plan's phi_h is clean when the scanned phi_h within a step of it are.
    let planned = settings.planned_phi_h_deg.rem_euclid(180.0);
    let planned_is_clean = phi_h_deg.iter().zip(&contaminated).all(|(&phi, &bad)| {
        let gap = (phi - planned).rem_euclid(180.0);
        !(bad && gap.min(180.0 - gap) <= step)
    });
    OrientationReport {
        phi_h_deg: phi_h_deg.to_vec(),
        excess,
        threshold,
        contaminated,
        anisotropic,
        recommended_phi_h_deg: recommended,
        planned_phi_h_deg: settings.planned_phi_h_deg,
        planned_is_clean,
        measurements: phi_h_deg.len() * rings.len(),
    }
}

/// The middle of the longest run of clean entries, the ring being circular over 180 deg.
fn longest_clean_arc_middle(phi_h_deg: &[f64], contaminated: &[bool], step: f64) -> f64 {
    let n = contaminated.len();
    let start = contaminated.iter().position(|&c| c).unwrap_or(0);
    let (mut best_start, mut best_len) = (0, 0);
    let mut run_start = None;
    // Walk one full turn starting at a contaminated entry, so no run wraps.
    for k in 1..=n {
        let i = (start + k) % n;
        match (contaminated[i], run_start) {
            (false, None) => run_start = Some(k),
            (true, Some(s)) => {
                if k - s > best_len {
                    (best_start, best_len) = (s, k - s);
                }
                run_start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = run_start {
        if n + 1 - s > best_len {
            (best_start, best_len) = (s, n + 1 - s);
        }
    }
    let first = phi_h_deg[(start + best_start) % n];
    (first + (best_len as f64 - 1.0) * step / 2.0).rem_euclid(180.0)
}

/// Runs the orientation check with the sample mounted (see the module documentation).
pub fn check_orientation(
    instrument: &mut dyn Instrument,
    hdr: &mut HdrCapturer,
    device: &Device,
    settings: &OrientationSettings,
) -> Result<OrientationReport, CheckError> {
    let count = (180.0 / settings.phi_h_step_deg).round() as usize;
    let phi_h_deg: Vec<f64> = (0..count)
        .map(|i| i as f64 * settings.phi_h_step_deg)
        .collect();
    let mut rings = Vec::with_capacity(settings.theta_h_deg.len());
    let mut position = None;
    for &theta_h in &settings.theta_h_deg {
        let mut ring = Vec::with_capacity(count);
        let mut predicted = None;
        for &phi_h in &phi_h_deg {
            let hd =
                HalfDiff::from_degrees(theta_h, phi_h, settings.theta_d_deg, settings.phi_d_deg);
            let (wi, wo) = hd.to_directions();
            let axes = *free_positions(device, wi, wo, position.as_ref())
                .first()
                .ok_or_else(|| {
                    CheckError::NotFound(format!(
                        "theta_h {theta_h}, phi_h {phi_h} deg: no free position of the arms"
                    ))
                })?;
            let measurement = measure_at(instrument, hdr, &axes, predicted)?;
            predicted = Some(measurement.value.brightest_rate_dn_s());
            position = Some(axes);
            ring.push(intensity(&measurement));
        }
        rings.push(ring);
    }
    Ok(analyse(&phi_h_deg, &rings, settings))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulator::sample::{MountedSample, Tilt};
    use crate::simulator::Simulator;
    use specula_core::materials::preset;
    use specula_core::materials::scratch::ScratchLobe;
    use specula_core::materials::Material;
    use specula_core::Brdf;
    use std::sync::Arc;

    fn scratched(orientation_deg: f64) -> Material {
        preset("silver-925")
            .unwrap()
            .with_scratch(ScratchLobe::polishing(orientation_deg))
    }

    fn run(truth: Material, seed: u64) -> OrientationReport {
        let device = Device::utia();
        let sample = MountedSample::new("silver", Arc::new(truth), Tilt::default());
        let (mut sim, mut hdr) = Simulator::with_hdr(device.clone(), sample, seed, None).unwrap();
        check_orientation(&mut sim, &mut hdr, &device, &OrientationSettings::default()).unwrap()
    }

    /// The scratch lobe's share of the truth at phi_h over theta_h 1..12 deg: how much the
    /// isotropic measurement would be contaminated there.
    fn lobe_share(truth: &Material, phi_h_deg: f64) -> f64 {
        let clean = Material {
            scratch: None,
            ..truth.clone()
        };
        let weight = truth.scratch.as_ref().unwrap().weight;
        (1..=12)
            .map(|t| {
                let hd = HalfDiff::from_degrees(t as f64, phi_h_deg, 30.0, 90.0);
                let with = truth.eval_half_diff(hd).unwrap().y;
                let base = clean.eval_half_diff(hd).unwrap().y * (1.0 - weight);
                with / base - 1.0
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn scratches_along_30_deg_keep_the_plan_and_recommend_the_along_direction() {
        let truth = scratched(30.0);
        let report = run(truth.clone(), 1);
        assert!(report.anisotropic, "{report:?}");
        // The lobe lights up across the scratches (120 deg); the cleanest phi_h is along.
        let peak = report.phi_h_deg[report
            .excess
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .unwrap()
            .0];
        assert!((peak - 120.0).abs() <= 6.0, "peak at {peak}");
        let along_gap = (report.recommended_phi_h_deg - 30.0).rem_euclid(180.0);
        assert!(
            along_gap.min(180.0 - along_gap) <= 15.0,
            "{}",
            report.recommended_phi_h_deg
        );
        assert!(lobe_share(&truth, report.recommended_phi_h_deg) < 0.01);
        assert!(report.planned_is_clean, "45 deg is 75 deg from the lobe");
        assert!(lobe_share(&truth, 45.0) < 0.01);
    }

    #[test]
    fn scratches_that_spoil_the_planned_phi_h_are_reported() {
        // Scratches along 135 deg: the lobe across them sits at 45 deg, the plan's phi_h.
        let truth = scratched(135.0);
        assert!(
            lobe_share(&truth, 45.0) > 0.5,
            "the lobe really is at 45 deg"
        );
        let report = run(truth.clone(), 2);
        assert!(!report.planned_is_clean, "{report:?}");
        assert!(lobe_share(&truth, report.recommended_phi_h_deg) < 0.01);
        assert!(
            report.turn_sample_deg().abs() > 45.0,
            "{}",
            report.turn_sample_deg()
        );
    }

    #[test]
    fn an_isotropic_sample_keeps_the_plans_phi_h() {
        let report = run(preset("silver-925").unwrap(), 3);
        assert!(!report.anisotropic, "{:?}", report.excess);
        assert_eq!(report.recommended_phi_h_deg, 45.0);
        assert!(report.planned_is_clean);
    }

    #[test]
    fn longest_clean_arc_wraps_around() {
        let phi: Vec<f64> = (0..12).map(|i| i as f64 * 15.0).collect();
        let mut bad = vec![false; 12];
        bad[5] = true;
        bad[6] = true;
        // Clean: 7..11 and 0..4 (10 entries across the wrap from 105 deg): middle at 172.5.
        let middle = longest_clean_arc_middle(&phi, &bad, 15.0);
        assert!((middle - 172.5).abs() < 1e-9, "{middle}");
    }
}
