//! The instrument's response: what one capture integrates (the forward model of a
//! measurement, after Ferrero et al., "Deconvolution of non-zero solid angles effect in BSDF
//! measurements", Proc. SPIE 8083, 2011).
//!
//! A capture does not see one pair of directions. It sees
//!
//! ```text
//! m(wi, wo) = E[ f(wi', wo') cos(theta_i') ] / cos(theta_i)
//! ```
//!
//! over three independent spreads (the calibration divides by the nominal `cos theta_i`):
//!
//! - the **light's angular profile**: the exit aperture of the source seen from the sample, a
//!   disk of angular radius `atan(light.beam.end_radius_m / light.distance_m)` (1.8 deg for
//!   UTIA), uniform or with a radial emission profile (`light.emission_profile` of the
//!   device file: relative radiance at evenly spaced radii from the centre to the edge,
//!   linear in between);
//! - the **camera's aperture**: the lens's entrance pupil seen from the sample, a uniform
//!   disk of angular radius `atan(camera.aperture_radius_m / camera.distance_m)`; a pixel
//!   focused on the sample collects every ray through the pupil;
//! - the **footprint**: the measured area (a uniform disk of radius
//!   `camera.view.sample_radius_m`); a point `p` of it sees the light's centre and the lens
//!   turned by `-p / distance` (to first order), the same `p` for both.
//!
//! [`InstrumentResponse::capture_nodes`] turns these into equal-weight quadrature nodes
//! (offsets of wi and wo in the planes orthogonal to them, radians); the simulator integrates
//! its truth over many of them ([`crate::simulator`]), and the reconstruction fits its lobe
//! through the same operator with fewer ([`specula_core::capture::measure`]). In half-vector
//! terms a spread of radius `a` about wi or wo moves `h` by `a / 2` in the plane of
//! incidence and by `a / (2 cos theta_d)` across it: [`InstrumentResponse::resolution_deg`]
//! is the former for the combined radius, the width in theta_h below which a peak is a bound,
//! not a measurement.

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};
use specula_core::capture::{self, CaptureNode, CaptureResponse};
use specula_core::{Brdf, Rgb};
use std::f64::consts::PI;

/// The light's angular profile: a disk with a radial emission profile.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LightProfile {
    /// Angular radius of the emitting disk seen from the sample, degrees.
    pub radius_deg: f64,
    /// Relative radiance at evenly spaced radii from the centre (first) to the edge (last),
    /// linear in between; empty for a uniform disk.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub emission: Vec<f64>,
}

impl LightProfile {
    /// A uniform disk of angular radius `radius_deg`.
    pub fn uniform(radius_deg: f64) -> Self {
        Self {
            radius_deg,
            emission: Vec::new(),
        }
    }

    /// Relative radiance at `u` = radius / disk radius in `[0, 1]`.
    pub fn emission_at(&self, u: f64) -> f64 {
        match self.emission.len() {
            0 => 1.0,
            1 => self.emission[0],
            n => {
                let x = u.clamp(0.0, 1.0) * (n - 1) as f64;
                let i = (x.floor() as usize).min(n - 2);
                let t = x - i as f64;
                self.emission[i] * (1.0 - t) + self.emission[i + 1] * t
            }
        }
    }

    /// The normalised radius `u` below which a fraction `q` of the disk's power lies (the
    /// inverse of the cumulative power `int_0^u e(s) s ds`, tabulated).
    fn radius_of_quantile(&self, table: &[(f64, f64)], q: f64) -> f64 {
        if self.emission.is_empty() {
            return q.sqrt();
        }
        let i = table
            .partition_point(|&(_, c)| c < q)
            .clamp(1, table.len() - 1);
        let (u0, c0) = table[i - 1];
        let (u1, c1) = table[i];
        if c1 <= c0 {
            u1
        } else {
            u0 + (u1 - u0) * (q - c0) / (c1 - c0)
        }
    }

    /// `(u, normalised cumulative power)` at fine steps of `u`.
    fn cumulative_table(&self) -> Vec<(f64, f64)> {
        const STEPS: usize = 2048;
        let mut table = Vec::with_capacity(STEPS + 1);
        let mut total = 0.0;
        table.push((0.0, 0.0));
        for k in 1..=STEPS {
            let (a, b) = ((k - 1) as f64 / STEPS as f64, k as f64 / STEPS as f64);
            let mid = 0.5 * (a + b);
            total += self.emission_at(mid).max(0.0) * mid * (b - a);
            table.push((b, total));
        }
        let total = total.max(f64::MIN_POSITIVE);
        table.iter().map(|&(u, c)| (u, c / total)).collect()
    }
}

/// What one capture integrates (see the module documentation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InstrumentResponse {
    /// The light's angular profile seen from the sample.
    pub light: LightProfile,
    /// Angular radius of the camera's entrance pupil seen from the sample, degrees.
    pub camera_aperture_deg: f64,
    /// Radius of the measured area, metres.
    pub footprint_radius_m: f64,
    /// Light and camera distances from the sample, metres (they turn the footprint into
    /// angles).
    pub light_distance_m: f64,
    /// Camera distance from the sample, metres.
    pub camera_distance_m: f64,
}

impl InstrumentResponse {
    /// A point light, a pinhole camera and a point footprint: no blur.
    pub fn point(light_distance_m: f64, camera_distance_m: f64) -> Self {
        Self {
            light: LightProfile::uniform(0.0),
            camera_aperture_deg: 0.0,
            footprint_radius_m: 0.0,
            light_distance_m,
            camera_distance_m,
        }
    }

    /// True when a capture sees exactly one pair of directions.
    pub fn is_point(&self) -> bool {
        self.light.radius_deg == 0.0
            && self.camera_aperture_deg == 0.0
            && self.footprint_radius_m == 0.0
    }

    /// The same response with another light radius (what the calibration fits).
    pub fn with_light_radius_deg(&self, radius_deg: f64) -> Self {
        Self {
            light: LightProfile {
                radius_deg,
                ..self.light.clone()
            },
            ..self.clone()
        }
    }

    /// The combined angular radius of the spreads of wi and wo, degrees: the light's disk,
    /// the camera's pupil and the footprint seen from both.
    pub fn spread_radius_deg(&self) -> f64 {
        let footprint = (self.footprint_radius_m / self.light_distance_m
            + self.footprint_radius_m / self.camera_distance_m)
            .to_degrees();
        self.light.radius_deg + self.camera_aperture_deg + footprint
    }

    /// The instrument's resolution in theta_h, degrees: half the combined spread (a spread
    /// of radius `a` about wi moves the half vector by `a / 2` in the plane of incidence). A
    /// peak whose half width at half maximum is below this is not resolved.
    pub fn resolution_deg(&self) -> f64 {
        0.5 * self.spread_radius_deg()
    }

    /// `count` equal-weight nodes (at least 1): the light's disk by a sunflower pattern over
    /// its cumulative power (equal-power rings), the camera's pupil and the footprint by
    /// the R2 low-discrepancy sequence (Roberts 2018), centred.
    pub fn capture_nodes(&self, count: usize) -> Vec<CaptureNode> {
        let count = count.max(1);
        if self.is_point() {
            return vec![CaptureNode {
                light: DVec2::ZERO,
                camera: DVec2::ZERO,
            }];
        }
        let golden_angle = PI * (3.0 - 5f64.sqrt());
        let table = self.light.cumulative_table();
        let light_rad = self.light.radius_deg.to_radians().tan();
        let aperture_rad = self.camera_aperture_deg.to_radians().tan();
        // R2: the plastic number's reciprocals.
        let g = 1.324_717_957_244_746;
        let (a1, a2) = (1.0 / g, 1.0 / (g * g));
        let unit_disk = |u: f64, v: f64| {
            let (s, c) = (2.0 * PI * v).sin_cos();
            DVec2::new(c, s) * u.sqrt()
        };
        let mut nodes: Vec<CaptureNode> = (0..count)
            .map(|k| {
                let q = (k as f64 + 0.5) / count as f64;
                let r = self.light.radius_of_quantile(&table, q);
                let a = k as f64 * golden_angle;
                let light = DVec2::new(a.cos(), a.sin()) * r * light_rad;
                let x = ((0.5 + a1 * k as f64).fract(), (0.5 + a2 * k as f64).fract());
                let y = ((0.3 + a2 * k as f64).fract(), (0.7 + a1 * k as f64).fract());
                let camera = unit_disk(x.0, x.1) * aperture_rad;
                let p = unit_disk(y.0, y.1) * self.footprint_radius_m;
                CaptureNode {
                    light: light - p / self.light_distance_m,
                    camera: camera - p / self.camera_distance_m,
                }
            })
            .collect();
        // Low-discrepancy patterns are off their centre by about 1 / count of the radius;
        // shift them back so that no side is favoured.
        let n = count as f64;
        let light_mean = nodes.iter().map(|p| p.light).sum::<DVec2>() / n;
        let camera_mean = nodes.iter().map(|p| p.camera).sum::<DVec2>() / n;
        for node in &mut nodes {
            node.light -= light_mean;
            node.camera -= camera_mean;
        }
        nodes
    }
}

impl CaptureResponse for InstrumentResponse {
    fn capture_nodes(&self, count: usize) -> Vec<CaptureNode> {
        InstrumentResponse::capture_nodes(self, count)
    }

    fn is_point(&self) -> bool {
        InstrumentResponse::is_point(self)
    }

    fn resolution_deg(&self) -> f64 {
        InstrumentResponse::resolution_deg(self)
    }
}

/// A BRDF as the instrument measures it: each value is what a capture at the nominal
/// directions gives of `truth`, integrated over the response's quadrature `nodes`
/// ([`capture::measure_brdf`]); `None` where the truth itself is not measured.
/// The accuracy harness measures its truths through it, so that methods are compared on
/// the samples a device gives.
pub struct ThroughResponse<'a> {
    /// The BRDF being measured.
    pub truth: &'a dyn Brdf,
    /// The capture's quadrature nodes ([`InstrumentResponse::capture_nodes`]).
    pub nodes: Vec<CaptureNode>,
}

impl Brdf for ThroughResponse<'_> {
    fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
        self.truth.eval(wi, wo)?;
        Some(capture::measure_brdf(&self.nodes, self.truth, wi, wo))
    }

    fn name(&self) -> String {
        self.truth.name()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn utia_like() -> InstrumentResponse {
        InstrumentResponse {
            light: LightProfile::uniform((0.035f64 / 1.1).atan().to_degrees()),
            camera_aperture_deg: 0.0,
            footprint_radius_m: 0.0,
            light_distance_m: 1.1,
            camera_distance_m: 2.0,
        }
    }

    #[test]
    fn a_uniform_disk_has_the_second_moment_of_a_disk() {
        // E[r^2] = a^2 / 2 for a uniform disk of radius a (in the tangent plane).
        let response = utia_like();
        let nodes = response.capture_nodes(1000);
        let a = response.light.radius_deg.to_radians().tan();
        let m2 = nodes.iter().map(|p| p.light.length_squared()).sum::<f64>() / 1000.0;
        assert!(
            (m2 / (a * a / 2.0) - 1.0).abs() < 0.005,
            "{}",
            m2 / (a * a / 2.0)
        );
        let max = nodes.iter().map(|p| p.light.length()).fold(0.0, f64::max);
        assert!(max <= a * 1.002, "{max} vs {a}");
        assert!(nodes.iter().all(|p| p.camera == DVec2::ZERO));
    }

    #[test]
    fn an_emission_profile_moves_power_to_the_centre() {
        // Emission falling linearly to 0 at the edge: e(u) = 1 - u, so
        // E[u^2] = int u^3 (1-u) / int u (1-u) = (1/20) / (1/6) = 0.3.
        let response = InstrumentResponse {
            light: LightProfile {
                radius_deg: 2.0,
                emission: vec![1.0, 0.0],
            },
            ..utia_like()
        };
        let a = 2f64.to_radians().tan();
        let nodes = response.capture_nodes(4000);
        let m2 = nodes.iter().map(|p| p.light.length_squared()).sum::<f64>() / 4000.0;
        assert!((m2 / (a * a) - 0.3).abs() < 0.003, "{}", m2 / (a * a));
    }

    #[test]
    fn a_constant_brdf_is_measured_as_itself() {
        // The mean of cos theta_i' over a symmetric spread is cos theta_i to second order.
        let response = InstrumentResponse {
            camera_aperture_deg: 0.4,
            footprint_radius_m: 0.002,
            ..utia_like()
        };
        let nodes = response.capture_nodes(500);
        let wi = DVec3::new(0.5, 0.1, 0.8).normalize();
        let wo = DVec3::new(-0.3, 0.2, 0.9).normalize();
        let m = capture::measure(&nodes, wi, wo, |_, _| Rgb::splat(0.3));
        assert!((m.x / 0.3 - 1.0).abs() < 1e-3, "{m}");
        assert_eq!(
            InstrumentResponse::point(1.1, 2.0).capture_nodes(50).len(),
            1
        );
    }

    #[test]
    fn the_resolution_adds_the_spreads() {
        let r = InstrumentResponse {
            camera_aperture_deg: 0.3,
            footprint_radius_m: 0.0,
            ..utia_like()
        };
        assert!((r.resolution_deg() - 0.5 * (r.light.radius_deg + 0.3)).abs() < 1e-12);
    }
}
