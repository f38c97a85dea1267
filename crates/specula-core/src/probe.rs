//! Where and how densely the probe of paper 5.2 is taken: a dense theta_h column at fixed
//! theta_d, phi_d and phi_h, its positions placed by the square-root mapping (paper eq. 1).
//! The probe's values are [`crate::sample::ProbePoint`]s.

use crate::geometry::HalfDiff;
use crate::sampling::SamplingFunction;

/// The probe's column and its density; [`ProbeSpec::paper`] is the paper's (5.2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProbeSpec {
    /// theta_d of the column, degrees.
    pub theta_d_deg: f64,
    /// phi_d of the column, degrees.
    pub phi_d_deg: f64,
    /// phi_h of the column, degrees.
    pub phi_h_deg: f64,
    /// Number of theta_h samples, placed by the square-root mapping over `[0, 90]`.
    pub samples: usize,
}

impl ProbeSpec {
    /// The paper's probe (5.2): theta_d 40 deg, phi_d 90 deg, phi_h 45 deg, 90 samples.
    pub const fn paper() -> Self {
        Self {
            theta_d_deg: 40.0,
            phi_d_deg: 90.0,
            phi_h_deg: 45.0,
            samples: 90,
        }
    }

    /// The theta_h positions in degrees, increasing: the square-root mapping (paper eq. 1)
    /// of `samples` even steps over `[0, 90]`.
    pub fn theta_h_deg(&self) -> Vec<f64> {
        SamplingFunction::square_root().positions_deg(self.samples)
    }

    /// The configuration of the column at `theta_h_deg`.
    pub fn half_diff(&self, theta_h_deg: f64) -> HalfDiff {
        HalfDiff::from_degrees(
            theta_h_deg,
            self.phi_h_deg,
            self.theta_d_deg,
            self.phi_d_deg,
        )
    }
}

impl Default for ProbeSpec {
    fn default() -> Self {
        Self::paper()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_follow_the_square_root_mapping() {
        let spec = ProbeSpec::paper();
        let theta_h = spec.theta_h_deg();
        assert_eq!(theta_h.len(), 90);
        for (i, t) in theta_h.iter().enumerate() {
            let u = 90.0 * i as f64 / 89.0;
            assert!((t - u * u / 90.0).abs() < 1e-9, "{i}: {t}");
        }
        let hd = spec.half_diff(10.0);
        assert!((hd.theta_d.to_degrees() - 40.0).abs() < 1e-12);
        assert!((hd.phi_d.to_degrees() - 90.0).abs() < 1e-12);
        assert!((hd.phi_h.to_degrees() - 45.0).abs() < 1e-12);
    }
}
