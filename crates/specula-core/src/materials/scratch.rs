//! The anisotropic scratch lobe: the polishing artifact of paper section 4.3.
//!
//! A mechanically polished surface keeps fine parallel scratches. Across a scratch the surface
//! normal tilts a lot, along it hardly at all, so the scratched part of the surface has a
//! narrow anisotropic normal distribution, stretched perpendicular to the scratch direction.
//! It lights up when the light and the camera lie in a plane perpendicular to the scratches
//! (paper Fig. 6-7) and makes the BRDF depend on the half vector's azimuth `phi_h`, which an
//! isotropic half-difference table cannot hold.
//!
//! The lobe is a microfacet lobe `D(h') G(wi', wo', h') / (4 cos_i cos_o)` (Fresnel supplied by
//! the material underneath) evaluated in the scratch frame: the sample frame turned about the
//! normal by `orientation_deg`, whose x axis runs along the scratches (roughness
//! `alpha_along`) and y axis across them (`alpha_across`).

use super::microfacet::{Distribution, Microfacet};
use crate::geometry::rotate_z;
use glam::DVec3;

/// A scratch lobe covering a fraction `weight` of the surface.
#[derive(Debug, Clone, PartialEq)]
pub struct ScratchLobe {
    /// Fraction of the surface that is scratched, in `[0, 1]`.
    pub weight: f64,
    /// Direction of the scratches, degrees from the sample frame's x axis towards y.
    pub orientation_deg: f64,
    microfacet: Microfacet,
}

impl ScratchLobe {
    /// A lobe of the given distribution, roughness along and across the scratches.
    pub fn new(
        distribution: Distribution,
        weight: f64,
        alpha_along: f64,
        alpha_across: f64,
        orientation_deg: f64,
    ) -> Self {
        Self {
            weight,
            orientation_deg,
            microfacet: Microfacet::anisotropic(distribution, alpha_along, alpha_across),
        }
    }

    /// The polishing scratches of paper Fig. 6 and 7-c along `orientation_deg`: 3 % of the
    /// surface, GGX alpha 0.005 along the scratches and 0.15 across (the lobe of the
    /// `silver-925-scratched` preset, which lies along 30 degrees).
    pub fn polishing(orientation_deg: f64) -> Self {
        Self::new(Distribution::Ggx, 0.03, 0.005, 0.15, orientation_deg)
    }

    /// The same lobe (weight, distribution, roughness) with its scratches along
    /// `orientation_deg`.
    pub fn turned(&self, orientation_deg: f64) -> Self {
        Self {
            orientation_deg,
            ..self.clone()
        }
    }

    /// The lobe's microfacet distribution's shape.
    pub fn distribution(&self) -> Distribution {
        self.microfacet.distribution
    }

    /// Roughness along the scratches (the narrow direction).
    pub fn alpha_along(&self) -> f64 {
        self.microfacet.alpha_u
    }

    /// Roughness across the scratches (the wide direction).
    pub fn alpha_across(&self) -> f64 {
        self.microfacet.alpha_v
    }

    /// The lobe's microfacet factor without Fresnel, in 1/sr; zero below the horizon.
    pub fn reflection(&self, wi: DVec3, wo: DVec3) -> f64 {
        let to_scratch_frame = -self.orientation_deg.to_radians();
        self.microfacet.reflection(
            rotate_z(wi, to_scratch_frame),
            rotate_z(wo, to_scratch_frame),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::HalfDiff;

    #[test]
    fn lobe_is_brightest_across_the_scratches() {
        // Scratches along 30 deg. A half vector tilted towards 120 deg (across) sees the wide
        // roughness, one tilted towards 30 deg (along) the narrow one.
        let lobe = ScratchLobe::new(Distribution::Ggx, 0.1, 0.01, 0.2, 30.0);
        let across = HalfDiff::from_degrees(5.0, 120.0, 30.0, 90.0).to_directions();
        let along = HalfDiff::from_degrees(5.0, 30.0, 30.0, 90.0).to_directions();
        let (a, b) = (
            lobe.reflection(across.0, across.1),
            lobe.reflection(along.0, along.1),
        );
        assert!(a > 100.0 * b, "across {a}, along {b}");
    }

    #[test]
    fn a_turned_lobe_keeps_its_weight_and_roughness() {
        let lobe = ScratchLobe::new(Distribution::Beckmann, 0.1, 0.02, 0.3, 0.0);
        let turned = lobe.turned(50.0);
        assert_eq!(turned.orientation_deg, 50.0);
        assert_eq!(
            (turned.weight, turned.alpha_along(), turned.alpha_across()),
            (0.1, 0.02, 0.3)
        );
        assert_eq!(turned.distribution(), Distribution::Beckmann);
        let polishing = ScratchLobe::polishing(30.0);
        assert_eq!(
            (
                polishing.weight,
                polishing.alpha_along(),
                polishing.alpha_across()
            ),
            (0.03, 0.005, 0.15)
        );
    }

    #[test]
    fn turning_the_scratches_with_the_sample_keeps_the_value() {
        let lobe = ScratchLobe::new(Distribution::Beckmann, 0.1, 0.02, 0.3, 0.0);
        let turned = ScratchLobe::new(Distribution::Beckmann, 0.1, 0.02, 0.3, 50.0);
        let (wi, wo) = HalfDiff::from_degrees(8.0, 10.0, 40.0, 70.0).to_directions();
        let turn = 50f64.to_radians();
        let a = lobe.reflection(wi, wo);
        let b = turned.reflection(rotate_z(wi, turn), rotate_z(wo, turn));
        assert!((a - b).abs() < 1e-12 * a.max(1.0), "{a} vs {b}");
    }
}
