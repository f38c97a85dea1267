//! The proxy lobe that importance-samples any BRDF, analytic or measured.
//!
//! A measured table cannot be sampled directly, and a mirror-like peak sampled by the cosine
//! alone sparkles forever. So each material gets a proxy: a GGX lobe (sampled by its visible
//! normals, Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4)) whose
//! roughness `alpha` is estimated from the material's own theta_h fall-off, mixed with a cosine
//! lobe for the diffuse part. The renderer combines it with light sampling by multiple
//! importance sampling, so the proxy needs only to be roughly right to converge quickly.

use glam::DVec3;
use specula_core::brdf::Brdf;
use specula_core::geometry::HalfDiff;
use specula_core::merl::{theta_h_centre_deg, THETA_H_BINS};
use specula_core::scattering::{masking, ndf};
use std::f64::consts::{FRAC_1_PI, PI};

/// theta_d at which the fall-off along theta_h is read, degrees (phi_d = 90 deg).
const FIT_THETA_D_DEG: f64 = 20.0;
/// Smallest cosine of light and camera directions of a column entry the fit uses.
const MIN_COSINE: f64 = 0.1;
/// Bounds of the fitted roughness.
const ALPHA_RANGE: (f64, f64) = (5e-4, 1.0);
/// Bounds of the probability of sampling the GGX part rather than the cosine part.
const SPECULAR_PROBABILITY_RANGE: (f64, f64) = (0.1, 0.99);

/// A GGX lobe of roughness `alpha` chosen with `specular_probability`, else a cosine lobe.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProxyLobe {
    /// GGX roughness of the specular part.
    pub alpha: f64,
    /// Probability of sampling the GGX part rather than the cosine part.
    pub specular_probability: f64,
}

impl ProxyLobe {
    /// Estimates the proxy from a BRDF's characteristic column (theta_d = 20 deg,
    /// phi_d = 90 deg, theta_h at MERL's bin centres, light and camera at least 5.7 deg above
    /// the horizon), averaged over R, G and B:
    ///
    /// - `alpha` from the half-maximum width of the peak above the column's far level;
    /// - the diffuse floor: what remains of the column's far half once the GGX lobe of that
    ///   alpha, scaled to the peak, is taken away (the median of the remainder);
    /// - the GGX share from the peak's energy against the floor's: a GGX peak holds about
    ///   `F = 4 pi alpha^2 cos^2(theta_d) f_peak`, a diffuse floor `pi floor`.
    pub fn fit(brdf: &dyn Brdf) -> Self {
        let column: Vec<ColumnEntry> = (0..THETA_H_BINS)
            .filter_map(|i| {
                let theta_h_deg = theta_h_centre_deg(i);
                let hd = HalfDiff::from_degrees(theta_h_deg, 0.0, FIT_THETA_D_DEG, 90.0);
                let (wi, wo) = hd.to_directions();
                // Near and below the horizon the cosines, not the material, shape the value.
                if wi.z.min(wo.z) < MIN_COSINE {
                    return None;
                }
                let mean = brdf.eval_half_diff(hd)?.element_sum() / 3.0;
                mean.is_finite().then_some(ColumnEntry {
                    theta_h_rad: theta_h_deg.to_radians(),
                    value: mean.max(0.0),
                    cosines: wi.z * wo.z,
                })
            })
            .collect();
        Self::from_column(&column)
    }

    /// The proxy of a column sorted by theta_h.
    fn from_column(column: &[ColumnEntry]) -> Self {
        let Some(peak_at) =
            (0..column.len()).max_by(|a, b| column[*a].value.total_cmp(&column[*b].value))
        else {
            return Self {
                alpha: 0.5,
                specular_probability: 0.5,
            };
        };
        let peak = column[peak_at];
        let far = &column[column.len() / 2..];
        let far_level = median(far.iter().map(|c| c.value));
        if peak.value.is_nan() || peak.value <= 0.0 || peak.value < 2.0 * far_level {
            return Self {
                alpha: 0.5,
                specular_probability: SPECULAR_PROBABILITY_RANGE.0,
            };
        }
        let half = far_level + 0.5 * (peak.value - far_level);
        let theta_half = column[peak_at..]
            .windows(2)
            .find(|w| w[1].value <= half)
            .map(|w| {
                let (a, b) = (w[0], w[1]);
                a.theta_h_rad
                    + (b.theta_h_rad - a.theta_h_rad) * (a.value - half)
                        / (a.value - b.value).max(f64::MIN_POSITIVE)
            })
            .unwrap_or(column[column.len() - 1].theta_h_rad);
        let alpha = alpha_of_half_width(theta_half).clamp(ALPHA_RANGE.0, ALPHA_RANGE.1);
        let peak_d = ggx_d(alpha, DVec3::Z);
        let lobe_at = |c: &ColumnEntry| {
            let m = DVec3::new(c.theta_h_rad.sin(), 0.0, c.theta_h_rad.cos());
            peak.value * ggx_d(alpha, m) / peak_d * peak.cosines / c.cosines
        };
        let floor = median(far.iter().map(|c| (c.value - lobe_at(c)).max(0.0)));
        let cos_d = FIT_THETA_D_DEG.to_radians().cos();
        let specular = 4.0 * PI * alpha * alpha * cos_d * cos_d * peak.value;
        let diffuse = PI * floor;
        let p = specular / (specular + diffuse);
        Self {
            alpha,
            specular_probability: p
                .clamp(SPECULAR_PROBABILITY_RANGE.0, SPECULAR_PROBABILITY_RANGE.1),
        }
    }

    /// Draws an incident direction for the outgoing `wo` (local frame, `wo.z > 0`) from three
    /// uniform numbers; `None` when the sample falls below the surface (it carries no light).
    pub fn sample(&self, wo: DVec3, u: [f64; 3]) -> Option<DVec3> {
        let wi = if u[0] < self.specular_probability {
            let m = sample_visible_normal(self.alpha, wo, u[1], u[2]);
            2.0 * wo.dot(m) * m - wo
        } else {
            sample_cosine(u[1], u[2])
        };
        (wi.z > 0.0).then_some(wi)
    }

    /// The density per steradian with which [`ProxyLobe::sample`] draws `wi` given `wo`.
    pub fn pdf(&self, wo: DVec3, wi: DVec3) -> f64 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let m = (wi + wo).normalize();
        let specular = ggx_d(self.alpha, m) * smith_g1(self.alpha, wo) / (4.0 * wo.z);
        self.specular_probability * specular + (1.0 - self.specular_probability) * wi.z * FRAC_1_PI
    }
}

/// One theta_h entry of the column the proxy is fitted to.
#[derive(Debug, Clone, Copy)]
struct ColumnEntry {
    theta_h_rad: f64,
    /// f_r, mean of R, G and B, 1/sr.
    value: f64,
    /// `cos(theta_i) cos(theta_o)`.
    cosines: f64,
}

/// The median of some values (0 for none).
fn median(values: impl Iterator<Item = f64>) -> f64 {
    let mut v: Vec<f64> = values.collect();
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(0.0)
}

/// The GGX roughness whose normal distribution falls to half its peak at `theta_rad`:
/// `D(theta)/D(0) = alpha^4 / (cos^4 (alpha^2 + tan^2)^2) = 1/2`.
pub fn alpha_of_half_width(theta_rad: f64) -> f64 {
    let (s, c) = theta_rad.sin_cos();
    s / (std::f64::consts::SQRT_2 - c * c).sqrt()
}

/// The GGX (Trowbridge-Reitz) normal distribution `D(m)` of roughness `alpha` for a
/// microfacet normal `m` ([`ndf::ggx_d_of_normal`]).
pub fn ggx_d(alpha: f64, m: DVec3) -> f64 {
    ndf::ggx_d_of_normal(m, alpha, alpha)
}

/// Smith's masking function of GGX for a direction `w` ([`masking::ggx_g1_of_direction`]).
pub fn smith_g1(alpha: f64, w: DVec3) -> f64 {
    masking::ggx_g1_of_direction(w, alpha)
}

/// A microfacet normal drawn from the GGX distribution of normals visible from `wo`
/// (Heitz 2018, listing 1), with density `G1(wo) max(0, wo.m) D(m) / wo.z`.
pub fn sample_visible_normal(alpha: f64, wo: DVec3, u1: f64, u2: f64) -> DVec3 {
    let vh = DVec3::new(alpha * wo.x, alpha * wo.y, wo.z).normalize();
    let len2 = vh.x * vh.x + vh.y * vh.y;
    let t1 = if len2 > 0.0 {
        DVec3::new(-vh.y, vh.x, 0.0) / len2.sqrt()
    } else {
        DVec3::X
    };
    let t2 = vh.cross(t1);
    let r = u1.sqrt();
    let phi = 2.0 * PI * u2;
    let p1 = r * phi.cos();
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * phi.sin();
    let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * vh;
    DVec3::new(alpha * nh.x, alpha * nh.y, nh.z.max(1e-12)).normalize()
}

/// A cosine-distributed direction of the upper hemisphere (density `cos / pi`).
pub fn sample_cosine(u1: f64, u2: f64) -> DVec3 {
    let r = u1.sqrt();
    let phi = 2.0 * PI * u2;
    DVec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u1).max(0.0).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::brdf::Rgb;

    /// A test material: GGX microfacet reflection with a constant Fresnel plus a Lambertian
    /// floor.
    struct Microfacet {
        alpha: f64,
        fresnel: f64,
        diffuse: f64,
    }

    impl Brdf for Microfacet {
        fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
            if wi.z <= 0.0 || wo.z <= 0.0 {
                return Some(Rgb::ZERO);
            }
            let m = (wi + wo).normalize();
            let g = smith_g1(self.alpha, wi) * smith_g1(self.alpha, wo);
            let spec = self.fresnel * ggx_d(self.alpha, m) * g / (4.0 * wi.z * wo.z);
            Some(Rgb::splat(spec + self.diffuse * FRAC_1_PI))
        }
        fn name(&self) -> String {
            "microfacet".into()
        }
    }

    fn quasi_random(k: usize) -> [f64; 3] {
        let g = [
            0.819_172_513_396_164_4,
            0.671_043_606_703_789_2,
            0.549_700_477_901_970_6,
        ];
        [0, 1, 2].map(|i| (0.5 + g[i] * (k + 1) as f64) % 1.0)
    }

    #[test]
    fn ggx_d_is_normalised_in_projected_area() {
        for alpha in [0.05, 0.3, 0.9] {
            // integral D(m) cos(theta_m) d omega = 1.
            let n = 20_000;
            let mut total = 0.0;
            for i in 0..n {
                let t = (i as f64 + 0.5) / n as f64 * PI / 2.0;
                let m = DVec3::new(t.sin(), 0.0, t.cos());
                total += ggx_d(alpha, m) * t.cos() * t.sin() * 2.0 * PI * (PI / 2.0 / n as f64);
            }
            assert!((total - 1.0).abs() < 2e-3, "alpha {alpha}: {total}");
        }
    }

    #[test]
    fn sampled_directions_follow_the_pdf() {
        // The expectation of g(wi)/pdf(wi) under the sampler must equal the integral of g over
        // the hemisphere for any g; with g = pdf restricted to a cone, the estimator gives the
        // cone's probability, which must match quadrature of the pdf.
        let lobe = ProxyLobe {
            alpha: 0.2,
            specular_probability: 0.7,
        };
        let wo = DVec3::new(0.5, 0.1, 0.86).normalize();
        let axis = DVec3::new(-wo.x, -wo.y, wo.z);
        let in_cone = |w: DVec3| w.dot(axis) > 0.95;
        let n = 400_000;
        let hits = (0..n)
            .filter_map(|k| lobe.sample(wo, quasi_random(k)))
            .filter(|w| in_cone(*w))
            .count();
        let sampled = hits as f64 / n as f64;
        let (nt, np) = (600, 600);
        let mut quadrature = 0.0;
        for i in 0..nt {
            let t = (i as f64 + 0.5) / nt as f64 * PI / 2.0;
            for j in 0..np {
                let p = (j as f64 + 0.5) / np as f64 * 2.0 * PI;
                let w = DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos());
                if in_cone(w) {
                    quadrature +=
                        lobe.pdf(wo, w) * t.sin() * (PI / 2.0 / nt as f64) * (2.0 * PI / np as f64);
                }
            }
        }
        assert!(
            (sampled - quadrature).abs() < 0.01 * quadrature.max(0.05),
            "{sampled} vs {quadrature}"
        );
    }

    #[test]
    fn fit_recovers_the_roughness_of_a_ggx_material() {
        for alpha in [0.003, 0.02, 0.1, 0.3] {
            let brdf = Microfacet {
                alpha,
                fresnel: 0.9,
                diffuse: 0.0,
            };
            let lobe = ProxyLobe::fit(&brdf);
            // MERL's bins sample the very narrow peaks coarsely: within 35 percent is enough
            // for a proxy; broad ones within 15 percent.
            let tolerance = if alpha < 0.01 { 0.35 } else { 0.15 };
            assert!(
                (lobe.alpha / alpha - 1.0).abs() < tolerance,
                "{alpha}: {lobe:?}"
            );
            assert!(lobe.specular_probability > 0.95, "{lobe:?}");
        }
        let paint = ProxyLobe::fit(&Microfacet {
            alpha: 0.05,
            fresnel: 0.04,
            diffuse: 0.3,
        });
        assert!(paint.specular_probability < 0.5, "{paint:?}");
        let lambert = ProxyLobe::fit(&Microfacet {
            alpha: 0.5,
            fresnel: 0.0,
            diffuse: 0.5,
        });
        assert_eq!(lambert.specular_probability, SPECULAR_PROBABILITY_RANGE.0);
    }

    #[test]
    fn half_width_formula_inverts_ggx() {
        for alpha in [0.01, 0.1, 0.5] {
            let theta = alpha_half_angle(alpha);
            assert!((alpha_of_half_width(theta) - alpha).abs() < 1e-9);
        }
    }

    /// The angle at which D falls to half its peak, by bisection.
    fn alpha_half_angle(alpha: f64) -> f64 {
        let (mut lo, mut hi) = (0.0, PI / 2.0 - 1e-9);
        let d0 = ggx_d(alpha, DVec3::Z);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if ggx_d(alpha, DVec3::new(mid.sin(), 0.0, mid.cos())) > 0.5 * d0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }
}
