//! The alignment check (paper 4.2): "the alignment of a sample is adjusted and verified by
//! iterative adjustment of its position, while we test stationarity of the specular
//! highlight position for several rotations of the turntable".
//!
//! The light stays in the lab's x-z plane at elevation `theta_L` on the -x side; the camera
//! arm scans the +x side around the mirror angle. A sample whose normal leans by `tau`
//! towards the azimuth `alpha` (turntable frame) has, at turntable angle `rho`, the in-plane
//! tilt `tau cos(alpha + rho)`, which moves the mirror direction, and so the highlight, by
//! twice that:
//!
//! `c(rho) = c_0 + 2 tau cos(alpha + rho) = c_0 + A cos(rho) + B sin(rho)`,
//!
//! with `A = 2 tau cos(alpha)` and `B = -2 tau sin(alpha)`. The out-of-plane part moves the
//! highlight off the arm's plane and changes its position only to second order. A
//! least-squares fit of `c_0, A, B` over the rotations gives `tau = sqrt(A^2 + B^2) / 2` and
//! `alpha = atan2(-B, A)`; `c_0` absorbs every constant offset (the camera's zero, the
//! asymmetry of the lobe).
//!
//! The highlight's position at one rotation is the midpoint of its half-maximum crossings:
//! robust for the flat-topped profiles that the light's disk gives on sharp materials. A
//! coarse scan finds the crossings, a fine scan around each locates them.

use super::{intensity, measure_at, CheckError};
use crate::hdr::HdrCapturer;
use crate::instrument::Instrument;
use crate::kinematics::AxisPositions;
use glam::{DMat3, DVec3};
use serde::Serialize;

/// How the highlight is scanned.
#[derive(Debug, Clone, PartialEq)]
pub struct AlignmentSettings {
    /// The light's elevation, degrees; the highlight is near the camera at the same angle.
    pub light_elevation_deg: f64,
    /// Turntable rotations, evenly over a full turn.
    pub rotations: usize,
    /// Half-width of the coarse scan around the mirror angle, and its step, degrees.
    pub coarse_half_width_deg: f64,
    /// Step of the coarse scan of the camera angle, degrees.
    pub coarse_step_deg: f64,
    /// Half-width of the fine scans around each half-maximum crossing, and their step.
    pub fine_half_width_deg: f64,
    /// Step of the fine scans of the camera angle, degrees.
    pub fine_step_deg: f64,
}

impl Default for AlignmentSettings {
    fn default() -> Self {
        Self {
            light_elevation_deg: 30.0,
            rotations: 6,
            coarse_half_width_deg: 10.0,
            coarse_step_deg: 2.0,
            fine_half_width_deg: 1.0,
            fine_step_deg: 0.25,
        }
    }
}

/// The highlight at one turntable rotation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct HighlightPeak {
    /// The turntable rotation the highlight was scanned at, degrees.
    pub turntable_deg: f64,
    /// Midpoint of the half-maximum crossings, camera angle, degrees.
    pub camera_deg: f64,
    /// Full width at half maximum, degrees.
    pub width_deg: f64,
}

/// The fitted tilt.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TiltFit {
    /// Angle between the sample's normal and the turntable axis, degrees.
    pub tilt_deg: f64,
    /// Azimuth (turntable frame) towards which the normal leans, degrees in [0, 360).
    pub azimuth_deg: f64,
    /// The highlight's mean camera angle, degrees.
    pub offset_deg: f64,
    /// RMS of the fit's residuals, degrees.
    pub residual_rms_deg: f64,
}

/// The result of the alignment check.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AlignmentReport {
    /// The highlight found at each turntable rotation, in scan order.
    pub peaks: Vec<HighlightPeak>,
    /// The tilt fitted to the peaks' camera angles ([`fit_tilt`]).
    pub fit: TiltFit,
    /// HDR measurements taken.
    pub measurements: usize,
}

impl AlignmentReport {
    /// What the operator should do, in a sentence.
    pub fn adjustment(&self, accuracy_deg: f64) -> String {
        let fit = &self.fit;
        if fit.tilt_deg <= accuracy_deg {
            return format!(
                "aligned: the highlight stays within the device's accuracy ({accuracy_deg} deg); \
                 no adjustment needed"
            );
        }
        // A normal leaning towards azimuth a: the surface dips on the side at a.
        let high_side = (fit.azimuth_deg + 180.0).rem_euclid(360.0);
        format!(
            "tilt the sample back by {:.3} deg: raise its side at azimuth {:.1} deg (turntable \
             frame) or lower the side at {:.1} deg, then run the check again",
            fit.tilt_deg, fit.azimuth_deg, high_side
        )
    }
}

/// Fits `c(rho) = c_0 + A cos(rho) + B sin(rho)` to `(turntable_deg, camera_deg)` pairs (see
/// the module documentation). Needs three or more rotations that are not all alike.
pub fn fit_tilt(peaks: &[(f64, f64)]) -> Option<TiltFit> {
    let rows: Vec<(DVec3, f64)> = peaks
        .iter()
        .map(|&(rho, c)| {
            let rho = rho.to_radians();
            (DVec3::new(1.0, rho.cos(), rho.sin()), c)
        })
        .collect();
    let normal = rows.iter().fold(DMat3::ZERO, |m, (x, _)| {
        m + DMat3::from_cols(*x * x.x, *x * x.y, *x * x.z)
    });
    if rows.len() < 3 || normal.determinant().abs() < 1e-9 {
        return None;
    }
    let rhs = rows.iter().fold(DVec3::ZERO, |s, (x, c)| s + *x * *c);
    let p = normal.inverse() * rhs;
    let (a, b) = (p.y, p.z);
    let residual = rows
        .iter()
        .map(|(x, c)| (x.dot(p) - c).powi(2))
        .sum::<f64>();
    Some(TiltFit {
        tilt_deg: a.hypot(b) / 2.0,
        azimuth_deg: (-b).atan2(a).to_degrees().rem_euclid(360.0),
        offset_deg: p.x,
        residual_rms_deg: (residual / rows.len() as f64).sqrt(),
    })
}

/// The half-maximum crossings of a profile sorted by angle: `(left, right)`, or `None` when
/// the profile does not fall below half its maximum on both sides.
pub fn half_maximum_crossings(profile: &[(f64, f64)]) -> Option<(f64, f64)> {
    let top = profile
        .iter()
        .enumerate()
        .max_by(|a, b| a.1 .1.total_cmp(&b.1 .1))?
        .0;
    let half = profile[top].1 / 2.0;
    let crossing = |inside: usize, outside: usize| {
        let (x0, y0) = profile[inside];
        let (x1, y1) = profile[outside];
        x0 + (x1 - x0) * (y0 - half) / (y0 - y1)
    };
    let left = (0..top).rev().find(|&i| profile[i].1 < half)?;
    let right = (top + 1..profile.len()).find(|&i| profile[i].1 < half)?;
    Some((crossing(left + 1, left), crossing(right - 1, right)))
}

/// Camera angles from `centre - half_width` to `centre + half_width` by `step`.
fn angles(centre: f64, half_width: f64, step: f64) -> Vec<f64> {
    let n = (half_width / step).round() as i64;
    (-n..=n).map(|k| centre + k as f64 * step).collect()
}

/// Measures the intensity at each camera angle (degrees) at one rotation.
fn scan(
    instrument: &mut dyn Instrument,
    hdr: &mut HdrCapturer,
    turntable_deg: f64,
    light_elevation_deg: f64,
    cameras_deg: &[f64],
    profile: &mut Vec<(f64, f64)>,
) -> Result<(), CheckError> {
    let mut predicted = None;
    for &camera_deg in cameras_deg {
        let axes =
            AxisPositions::from_degrees(turntable_deg, camera_deg, 180.0, light_elevation_deg);
        let measurement = measure_at(instrument, hdr, &axes, predicted)?;
        predicted = Some(measurement.value.brightest_rate_dn_s());
        profile.push((camera_deg, intensity(&measurement)));
    }
    Ok(())
}

/// Locates the highlight at one turntable rotation.
fn locate(
    instrument: &mut dyn Instrument,
    hdr: &mut HdrCapturer,
    turntable_deg: f64,
    settings: &AlignmentSettings,
) -> Result<(HighlightPeak, usize), CheckError> {
    let light = settings.light_elevation_deg;
    let mut profile = Vec::new();
    let coarse = angles(
        light,
        settings.coarse_half_width_deg,
        settings.coarse_step_deg,
    );
    scan(instrument, hdr, turntable_deg, light, &coarse, &mut profile)?;
    let not_found = || {
        CheckError::NotFound(format!(
            "no highlight within {} deg of the mirror angle at turntable {turntable_deg} deg: \
             the sample is tilted further than that, or not specular",
            settings.coarse_half_width_deg
        ))
    };
    let (left, right) = half_maximum_crossings(&profile).ok_or_else(not_found)?;
    for crossing in [left, right] {
        let fine = angles(
            crossing,
            settings.fine_half_width_deg,
            settings.fine_step_deg,
        );
        scan(instrument, hdr, turntable_deg, light, &fine, &mut profile)?;
    }
    profile.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (left, right) = half_maximum_crossings(&profile).ok_or_else(not_found)?;
    let peak = HighlightPeak {
        turntable_deg,
        camera_deg: (left + right) / 2.0,
        width_deg: right - left,
    };
    Ok((peak, profile.len()))
}

/// Runs the alignment check with the sample mounted (see the module documentation).
pub fn check_alignment(
    instrument: &mut dyn Instrument,
    hdr: &mut HdrCapturer,
    settings: &AlignmentSettings,
) -> Result<AlignmentReport, CheckError> {
    let mut peaks = Vec::with_capacity(settings.rotations);
    let mut measurements = 0;
    for k in 0..settings.rotations {
        // Turntable angles in (-180, 180], the UTIA turntable's range.
        let turntable_deg = 180.0 - 360.0 * k as f64 / settings.rotations as f64;
        let (peak, count) = locate(instrument, hdr, turntable_deg, settings)?;
        peaks.push(peak);
        measurements += count;
    }
    let pairs: Vec<(f64, f64)> = peaks
        .iter()
        .map(|p| (p.turntable_deg, p.camera_deg))
        .collect();
    let fit = fit_tilt(&pairs).ok_or_else(|| {
        CheckError::NotFound("need three or more turntable rotations to fit a tilt".into())
    })?;
    Ok(AlignmentReport {
        peaks,
        fit,
        measurements,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::device::Device;
    use crate::simulator::sample::{MountedSample, Tilt};
    use crate::simulator::Simulator;
    use specula_core::materials::preset;
    use std::sync::Arc;

    #[test]
    fn fit_recovers_a_synthetic_tilt() {
        let (tau, alpha) = (0.25f64, 130f64);
        let peaks: Vec<(f64, f64)> = (0..8)
            .map(|k| {
                let rho = 180.0 - 45.0 * k as f64;
                (rho, 30.2 + 2.0 * tau * (alpha + rho).to_radians().cos())
            })
            .collect();
        let fit = fit_tilt(&peaks).unwrap();
        assert!((fit.tilt_deg - tau).abs() < 1e-12);
        assert!((fit.azimuth_deg - alpha).abs() < 1e-9);
        assert!((fit.offset_deg - 30.2).abs() < 1e-12 && fit.residual_rms_deg < 1e-12);
        assert!(fit_tilt(&peaks[..2]).is_none());
    }

    #[test]
    fn crossings_of_a_triangle() {
        let profile: Vec<(f64, f64)> = (0..=20)
            .map(|i| (i as f64, 10.0 - (i as f64 - 12.0).abs()))
            .collect();
        let (l, r) = half_maximum_crossings(&profile).unwrap();
        assert!(
            (l - 7.0).abs() < 1e-12 && (r - 17.0).abs() < 1e-12,
            "{l} {r}"
        );
        assert!(half_maximum_crossings(&profile[5..15]).is_none());
    }

    fn tilted(tilt: Tilt, seed: u64) -> (Simulator, HdrCapturer) {
        let truth = Arc::new(preset("silver-925").unwrap());
        let sample = MountedSample::new("silver", truth, tilt);
        Simulator::with_hdr(Device::utia(), sample, seed, None).unwrap()
    }

    /// Error of the estimate as a vector (tilt towards azimuth), degrees.
    fn vector_error(fit: &TiltFit, truth: Tilt) -> f64 {
        let v =
            |t: f64, a: f64| DVec3::new(t * a.to_radians().cos(), t * a.to_radians().sin(), 0.0);
        (v(fit.tilt_deg, fit.azimuth_deg) - v(truth.tilt_deg, truth.azimuth_deg)).length()
    }

    #[test]
    fn a_known_tilt_is_estimated_within_five_hundredths_of_a_degree() {
        for (k, truth) in [Tilt::new(0.3, 40.0), Tilt::new(0.12, 250.0)]
            .into_iter()
            .enumerate()
        {
            let (mut sim, mut hdr) = tilted(truth, 100 + k as u64);
            let report =
                check_alignment(&mut sim, &mut hdr, &AlignmentSettings::default()).unwrap();
            let error = vector_error(&report.fit, truth);
            assert!(error < 0.05, "{truth:?}: {:?}, error {error}", report.fit);
            assert!(report.adjustment(0.03).contains("tilt the sample back"));
        }
    }

    #[test]
    fn an_aligned_sample_is_reported_aligned() {
        let (mut sim, mut hdr) = tilted(Tilt::default(), 7);
        let report = check_alignment(&mut sim, &mut hdr, &AlignmentSettings::default()).unwrap();
        assert!(report.fit.tilt_deg < 0.05, "{:?}", report.fit);
        assert!(report
            .peaks
            .iter()
            .all(|p| p.width_deg > 1.0 && p.width_deg < 12.0));
    }
}
