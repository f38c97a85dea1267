//! A measured BRDF value and a point of the probe: the two shapes in which measurements
//! travel between the crates (measurement, the samples CSV file, reconstruction, plots).

use crate::brdf::Rgb;
use crate::geometry::HalfDiff;
use glam::DVec3;

/// One measured BRDF value (f_r in 1/sr per channel) at one configuration of light and
/// camera, held in Rusinkiewicz's half-difference angles (radians; paper 3, 5.3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Where the value was measured, half-difference angles in radians.
    pub hd: HalfDiff,
    /// f_r in 1/sr per channel.
    pub value: Rgb,
    /// The relative standard deviation of the value in each channel from the camera's noise
    /// (its HDR merge's shot, read and dark noise through the colour matrix, type A), when the
    /// measurement recorded it; infinite in a channel that holds a lower bound.
    pub noise_rel: Option<Rgb>,
}

impl Sample {
    /// The value `value` (1/sr) measured at `hd`, its noise not known.
    pub fn new(hd: HalfDiff, value: Rgb) -> Self {
        Self {
            hd,
            value,
            noise_rel: None,
        }
    }

    /// The sample with the relative standard deviation `noise_rel` of its value, per channel.
    pub fn with_noise_rel(self, noise_rel: Rgb) -> Self {
        Self {
            noise_rel: Some(noise_rel),
            ..self
        }
    }

    /// The largest channel's relative standard deviation ([`Sample::noise_rel`]), when known.
    pub fn largest_noise_rel(&self) -> Option<f64> {
        self.noise_rel.map(Rgb::max_element)
    }

    /// The directions `(to the light, to the camera)` of the sample, unit vectors in the
    /// sample's frame.
    pub fn directions(&self) -> (DVec3, DVec3) {
        self.hd.to_directions()
    }

    /// theta_h in degrees.
    pub fn theta_h_deg(&self) -> f64 {
        self.hd.theta_h.to_degrees()
    }

    /// theta_d in degrees.
    pub fn theta_d_deg(&self) -> f64 {
        self.hd.theta_d.to_degrees()
    }

    /// phi_d in degrees.
    pub fn phi_d_deg(&self) -> f64 {
        self.hd.phi_d.to_degrees()
    }
}

/// One point of the probe's theta_h column (paper 5.2): theta_h in degrees and the value
/// measured there (f_r in 1/sr per channel), at the probe's fixed theta_d, phi_d and phi_h
/// ([`crate::probe::ProbeSpec`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProbePoint {
    /// theta_h in degrees.
    pub theta_h_deg: f64,
    /// f_r in 1/sr per channel.
    pub value: Rgb,
}

impl ProbePoint {
    /// The value `value` (1/sr) at `theta_h_deg`.
    pub fn new(theta_h_deg: f64, value: Rgb) -> Self {
        Self { theta_h_deg, value }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_and_degrees_come_from_the_angles() {
        let hd = HalfDiff::from_degrees(10.0, 45.0, 40.0, 90.0);
        let sample = Sample::new(hd, Rgb::ONE);
        let (wi, wo) = sample.directions();
        let back = HalfDiff::from_directions(wi, wo);
        assert!((back.theta_h - hd.theta_h).abs() < 1e-12);
        assert!((back.theta_d - hd.theta_d).abs() < 1e-12);
        assert!((sample.theta_h_deg() - 10.0).abs() < 1e-12);
        assert!((sample.theta_d_deg() - 40.0).abs() < 1e-12);
        assert!((sample.phi_d_deg() - 90.0).abs() < 1e-12);
    }
}
