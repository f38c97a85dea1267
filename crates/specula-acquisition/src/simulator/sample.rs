//! The simulated sample on the turntable: its ground-truth BRDF, its misalignment (tilt,
//! paper 4.2) and the positioning error of the axes that carry it (0.03 deg, paper 4.1).
//!
//! **Tilt.** The paper aligns the measured area's normal with the turntable's axis by
//! watching the highlight while turning the turntable. A misaligned sample's normal leans by
//! `tilt_deg` towards the azimuth `azimuth_deg` of the turntable frame (the frame that turns
//! with the turntable, equal to the lab at turntable angle 0). The sample frame is the
//! turntable frame turned by `R = Rz(azimuth) Ry(tilt) Rz(-azimuth)`, so a turntable-frame
//! direction `w` is `R^T w` in the sample frame.
//!
//! **Positioning error.** Each axis stops a little off its command. The error is repeatable:
//! a fixed pseudo-random function of the axis and its commanded angle, normal with standard
//! deviation `sigma_deg`, so that the same command gives the same geometry in any order and
//! after a restart. The encoders read back the command (to 0.001 deg): the error is what the
//! device does not know about itself.
//!
//! **Scratches.** The anisotropic scratch lobe (paper 4.3) comes with the material model
//! ([`specula_core::materials::Material::with_scratch`]): a truth with a scratch lobe makes
//! the values depend on `phi_h`.

use super::rng;
use crate::kinematics::AxisPositions;
use glam::DVec3;
use rand::Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};
use specula_core::geometry::{rotate_y, rotate_z};
use specula_core::Brdf;
use std::sync::Arc;

/// The sample's misalignment.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tilt {
    /// Angle between the sample's normal and the turntable's axis, degrees.
    pub tilt_deg: f64,
    /// Azimuth, in the turntable frame, towards which the normal leans, degrees.
    pub azimuth_deg: f64,
}

impl Tilt {
    /// A tilt of `tilt_deg` towards azimuth `azimuth_deg`, degrees.
    pub fn new(tilt_deg: f64, azimuth_deg: f64) -> Self {
        Self {
            tilt_deg,
            azimuth_deg,
        }
    }

    /// The sample's normal in the turntable frame.
    pub fn normal(&self) -> DVec3 {
        self.to_turntable_frame(DVec3::Z)
    }

    /// A sample-frame direction in the turntable frame (`R w`).
    pub fn to_turntable_frame(&self, w: DVec3) -> DVec3 {
        let a = self.azimuth_deg.to_radians();
        rotate_z(rotate_y(rotate_z(w, -a), self.tilt_deg.to_radians()), a)
    }

    /// A turntable-frame direction in the sample frame (`R^T w`).
    pub fn to_sample_frame(&self, w: DVec3) -> DVec3 {
        let a = self.azimuth_deg.to_radians();
        rotate_z(rotate_y(rotate_z(w, -a), -self.tilt_deg.to_radians()), a)
    }
}

/// What is on the turntable: a named BRDF, tilted.
#[derive(Clone)]
pub struct MountedSample {
    /// A name that keys the sample's noise (two targets never share their noise).
    pub name: String,
    /// The sample's BRDF, in its own frame.
    pub brdf: Arc<dyn Brdf>,
    /// How the sample is misaligned on the turntable.
    pub tilt: Tilt,
}

impl MountedSample {
    /// A sample named `name` with BRDF `brdf`, mounted with `tilt`.
    pub fn new(name: impl Into<String>, brdf: Arc<dyn Brdf>, tilt: Tilt) -> Self {
        Self {
            name: name.into(),
            brdf,
            tilt,
        }
    }

    /// `f_r cos(theta_i)` for turntable-frame directions `wi`, `wo` (unit), in the sample's
    /// own frame; zero where the truth has no value or a direction is below the surface.
    pub fn reflected(&self, wi_turntable: DVec3, wo_turntable: DVec3) -> DVec3 {
        let wi = self.tilt.to_sample_frame(wi_turntable);
        let wo = self.tilt.to_sample_frame(wo_turntable);
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return DVec3::ZERO;
        }
        self.brdf.eval(wi, wo).unwrap_or(DVec3::ZERO) * wi.z
    }
}

/// The repeatable positioning error of the four axes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PositioningError {
    /// Standard deviation of each axis's error, degrees.
    pub sigma_deg: f64,
}

/// Commanded angles are keyed to this quantum, radians (about 6e-6 deg).
const ANGLE_QUANTUM_RAD: f64 = 1e-7;
/// Encoders read back to this resolution, degrees.
pub const ENCODER_RESOLUTION_DEG: f64 = 0.001;

impl PositioningError {
    /// Where the axes really stop for a command (`seed` picks the device).
    pub fn actual(&self, seed: u64, commanded: &AxisPositions) -> AxisPositions {
        let mut angles = commanded.as_array();
        for (axis, angle) in angles.iter_mut().enumerate() {
            let mut stream = rng::stream(&[
                seed,
                rng::text("positioning"),
                axis as u64,
                rng::quantised(*angle, ANGLE_QUANTUM_RAD),
            ]);
            let z: f64 = stream.sample(StandardNormal);
            *angle += z * self.sigma_deg.to_radians();
        }
        AxisPositions::new(angles[0], angles[1], angles[2], angles[3])
    }

    /// What the encoders report for a command: the command to their resolution.
    pub fn read_back(commanded: &AxisPositions) -> AxisPositions {
        let step = ENCODER_RESOLUTION_DEG.to_radians();
        let a = commanded.as_array().map(|x| (x / step).round() * step);
        AxisPositions::new(a[0], a[1], a[2], a[3])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::geometry::Spherical;

    #[test]
    fn tilt_rotations_are_inverse_and_lean_the_normal() {
        let tilt = Tilt::new(0.4, 35.0);
        let n = tilt.normal();
        assert!((n.z.acos().to_degrees() - 0.4).abs() < 1e-9);
        assert!((n.y.atan2(n.x).to_degrees() - 35.0).abs() < 1e-6);
        let w = Spherical::from_degrees(40.0, 200.0).to_vector();
        let back = tilt.to_sample_frame(tilt.to_turntable_frame(w));
        assert!((back - w).length() < 1e-12);
        assert!((tilt.to_sample_frame(n) - DVec3::Z).length() < 1e-12);
    }

    #[test]
    fn positioning_error_is_repeatable_and_has_the_stated_spread() {
        let error = PositioningError { sigma_deg: 0.03 };
        let mut deviations = Vec::new();
        for k in 0..2000 {
            let commanded = AxisPositions::from_degrees(k as f64 * 0.17, 10.0, -50.0, 20.0);
            let a = error.actual(3, &commanded);
            assert_eq!(a, error.actual(3, &commanded), "same command, same stop");
            deviations.push((a.turntable_rad - commanded.turntable_rad).to_degrees());
        }
        let n = deviations.len() as f64;
        let mean = deviations.iter().sum::<f64>() / n;
        let sd = (deviations.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / n).sqrt();
        assert!(mean.abs() < 0.003, "{mean}");
        assert!((sd / 0.03 - 1.0).abs() < 0.08, "{sd}");
        // Another device (seed) stops elsewhere.
        let c = AxisPositions::from_degrees(1.0, 2.0, 3.0, 4.0);
        assert_ne!(error.actual(3, &c), error.actual(4, &c));
    }

    #[test]
    fn read_back_is_the_command_to_the_encoder_resolution() {
        let c = AxisPositions::from_degrees(12.34567, -0.0004, 90.0, 45.0006);
        let r = PositioningError::read_back(&c).to_degrees();
        let expected = [12.346, 0.0, 90.0, 45.001];
        for (a, b) in r.iter().zip(expected) {
            assert!((a - b).abs() < 1e-9, "{a} vs {b}");
        }
    }
}
