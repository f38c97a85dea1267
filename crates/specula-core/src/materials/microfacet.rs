//! Microfacet normal distributions (GGX / Trowbridge-Reitz and Beckmann) with Smith masking,
//! exactly as Mitsuba 3's `MicrofacetDistribution` (`include/mitsuba/render/microfacet.h`),
//! which its `roughconductor` uses.
//!
//! - `D(m)`: the density of microfacet normals `m` per unit solid angle, in 1/sr, normalised
//!   so that `int D(m) cos(theta_m) dm = 1` (Walter et al. 2007, eq. 4). Anisotropic with
//!   roughness `alpha_u` along x and `alpha_v` along y; isotropic when they are equal.
//! - `G1(v, m)`: Smith's monodirectional masking. GGX has the closed form
//!   `2 / (1 + sqrt(1 + alpha^2 tan^2 theta_v))`; Beckmann uses the rational approximation of
//!   Walter et al. 2007 (eq. 27, within 0.35 % of the exact erf form), as Mitsuba and PBRT do.
//!   `alpha` is the roughness projected on the azimuth of `v`.
//! - `G(wi, wo, m) = G1(wi, m) G1(wo, m)`: the separable form Mitsuba evaluates (not the
//!   height-correlated one).
//!
//! The formulas themselves are in [`crate::scattering::ndf`] and [`crate::scattering::masking`].

use crate::brdf::both_above_surface;
use crate::geometry::HalfDiff;
use crate::scattering::{masking, ndf};
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// The shape of the microfacet normal distribution.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Distribution {
    /// GGX / Trowbridge-Reitz: long tails, the usual fit to measured metals.
    #[default]
    Ggx,
    /// Beckmann: a Gaussian slope distribution, shorter tails.
    Beckmann,
}

impl Distribution {
    /// The name used in material files (`ggx`, `beckmann`).
    pub fn label(self) -> &'static str {
        match self {
            Distribution::Ggx => "ggx",
            Distribution::Beckmann => "beckmann",
        }
    }
}

/// A microfacet distribution of a given shape and roughness.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Microfacet {
    /// The distribution's shape (GGX or Beckmann).
    pub distribution: Distribution,
    /// Roughness along the frame's x axis (dimensionless, RMS slope scale).
    pub alpha_u: f64,
    /// Roughness along the frame's y axis.
    pub alpha_v: f64,
}

impl Microfacet {
    /// An isotropic distribution with roughness `alpha`.
    pub fn isotropic(distribution: Distribution, alpha: f64) -> Self {
        Self::anisotropic(distribution, alpha, alpha)
    }

    /// An anisotropic distribution: `alpha_u` along x, `alpha_v` along y.
    pub fn anisotropic(distribution: Distribution, alpha_u: f64, alpha_v: f64) -> Self {
        Self {
            distribution,
            alpha_u,
            alpha_v,
        }
    }

    /// The normal distribution `D(m)` in 1/sr for a unit microfacet normal `m`; zero for
    /// normals facing below the surface.
    pub fn d(&self, m: DVec3) -> f64 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let cos2 = m.z * m.z;
        self.d_of_scaled_tan2(ndf::scaled_tan2(m, self.alpha_u, self.alpha_v), cos2)
    }

    /// `D` from `tan^2 theta_m / alpha^2` (alpha projected on m's azimuth) and
    /// `cos^2 theta_m`.
    fn d_of_scaled_tan2(&self, scaled_tan2: f64, cos2: f64) -> f64 {
        let d = match self.distribution {
            Distribution::Beckmann => ndf::beckmann_d,
            Distribution::Ggx => ndf::ggx_d,
        };
        d(scaled_tan2, cos2, self.alpha_u, self.alpha_v)
    }

    /// Smith's masking `G1(v, m)` of direction `v` for microfacet normal `m`, in `[0, 1]`.
    pub fn g1(&self, v: DVec3, m: DVec3) -> f64 {
        // One cannot see the back of a microfacet from the front, and vice versa.
        if v.dot(m) * v.z <= 0.0 {
            return 0.0;
        }
        let xy_alpha2 = (self.alpha_u * v.x).powi(2) + (self.alpha_v * v.y).powi(2);
        self.g1_of_alpha2_tan2(xy_alpha2 / (v.z * v.z))
    }

    /// `G1` from `alpha^2 tan^2 theta_v` (alpha projected on v's azimuth).
    fn g1_of_alpha2_tan2(&self, alpha2_tan2: f64) -> f64 {
        match self.distribution {
            Distribution::Beckmann => masking::beckmann_g1(alpha2_tan2),
            Distribution::Ggx => masking::ggx_g1(alpha2_tan2),
        }
    }

    /// Separable Smith shadowing-masking `G1(wi, m) G1(wo, m)`.
    pub fn g(&self, wi: DVec3, wo: DVec3, m: DVec3) -> f64 {
        self.g1(wi, m) * self.g1(wo, m)
    }

    /// The microfacet factor of a reflection BRDF without Fresnel,
    /// `D(h) G(wi, wo, h) / (4 cos_i cos_o)` in 1/sr, for any roughness; zero when either
    /// direction is at or below the horizon.
    pub fn reflection(&self, wi: DVec3, wo: DVec3) -> f64 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let h = (wi + wo).normalize();
        self.d(h) * self.g(wi, wo, h) / (4.0 * wi.z * wo.z)
    }

    /// [`Microfacet::reflection`] for isotropic roughness (`alpha_u` is used), from the
    /// cosines alone.
    pub fn reflection_isotropic(&self, c: IsotropicCosines) -> f64 {
        self.d_isotropic(c.cos_h) * self.masking_over_cosines(c.cos_i, c.cos_o)
    }

    /// `D(h)` in 1/sr for isotropic roughness (`alpha_u`) from `cos theta_h`.
    pub fn d_isotropic(&self, cos_h: f64) -> f64 {
        match self.distribution {
            Distribution::Beckmann => self.d_isotropic_by(ndf::beckmann_d, cos_h),
            Distribution::Ggx => self.d_isotropic_by(ndf::ggx_d, cos_h),
        }
    }

    /// [`Microfacet::d_isotropic`] by the distribution's formula `d` (`ndf::ggx_d` or
    /// `ndf::beckmann_d`).
    fn d_isotropic_by(&self, d: impl Fn(f64, f64, f64, f64) -> f64, cos_h: f64) -> f64 {
        let cos2_h = cos_h * cos_h;
        let alpha2 = self.alpha_u * self.alpha_u;
        let scaled_tan2 = (1.0 - cos2_h).max(0.0) / (cos2_h * alpha2);
        d(scaled_tan2, cos2_h, self.alpha_u, self.alpha_v)
    }

    /// `G1(wi, h) G1(wo, h) / (4 cos_i cos_o)` for isotropic roughness (`alpha_u`): the part
    /// of [`Microfacet::reflection_isotropic`] that changes along a row of constant theta_h
    /// and theta_d.
    pub fn masking_over_cosines(&self, cos_i: f64, cos_o: f64) -> f64 {
        match self.distribution {
            Distribution::Beckmann => {
                self.masking_over_cosines_by(masking::beckmann_g1, cos_i, cos_o)
            }
            Distribution::Ggx => self.masking_over_cosines_by(masking::ggx_g1, cos_i, cos_o),
        }
    }

    /// [`Microfacet::masking_over_cosines`] by the distribution's `G1` of
    /// `alpha^2 tan^2 theta_v` (`masking::ggx_g1` or `masking::beckmann_g1`).
    fn masking_over_cosines_by(&self, g1: impl Fn(f64) -> f64, cos_i: f64, cos_o: f64) -> f64 {
        let alpha2 = self.alpha_u * self.alpha_u;
        let g1_of_cos = |cos_v: f64| {
            let cos2 = cos_v * cos_v;
            g1(alpha2 * (1.0 - cos2).max(0.0) / cos2)
        };
        g1_of_cos(cos_i) * g1_of_cos(cos_o) / (4.0 * cos_i * cos_o)
    }

    /// [`Microfacet::reflection_isotropic`] at each configuration of `columns`, into `out`
    /// (one value per configuration; where a direction is at or below the horizon, the value
    /// at the normal, which the caller discards). The distribution is chosen once for the
    /// block, and the loop over the columns runs in vector instructions: the same values,
    /// bit for bit, as configuration by configuration.
    pub fn reflection_isotropic_columns(&self, columns: &CosineColumns, out: &mut [f64]) {
        match self.distribution {
            Distribution::Beckmann => self.reflection_columns_by(
                |cos_h| self.d_isotropic_by(ndf::beckmann_d, cos_h),
                |cos_i, cos_o| self.masking_over_cosines_by(masking::beckmann_g1, cos_i, cos_o),
                columns,
                out,
            ),
            Distribution::Ggx => self.reflection_columns_by(
                |cos_h| self.d_isotropic_by(ndf::ggx_d, cos_h),
                |cos_i, cos_o| self.masking_over_cosines_by(masking::ggx_g1, cos_i, cos_o),
                columns,
                out,
            ),
        }
    }

    /// [`Microfacet::reflection_isotropic_columns`] with the distribution's `D` of
    /// `cos theta_h` and masking term of `cos_i`, `cos_o`.
    fn reflection_columns_by(
        &self,
        d: impl Fn(f64) -> f64,
        masking_over_cosines: impl Fn(f64, f64) -> f64,
        columns: &CosineColumns,
        out: &mut [f64],
    ) {
        let n = columns.len();
        assert_eq!(out.len(), n, "one output per configuration");
        let (cos_h, cos_i, cos_o) = (
            &columns.cos_h[..n],
            &columns.cos_i[..n],
            &columns.cos_o[..n],
        );
        for (k, out) in out.iter_mut().enumerate() {
            *out = d(cos_h[k]) * masking_over_cosines(cos_i[k], cos_o[k]);
        }
    }
}

/// The cosines an isotropic microfacet BRDF depends on: of the half vector `h` to the
/// normal, of `wi` to `h` (`theta_d`), and of `wi` and `wo` to the normal. Only built for
/// directions strictly above the surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IsotropicCosines {
    /// Cosine of the half vector to the normal (`cos theta_h`).
    pub cos_h: f64,
    /// Cosine of `wi` to the half vector (`cos theta_d`).
    pub cos_d: f64,
    /// Cosine of `wi` to the normal.
    pub cos_i: f64,
    /// Cosine of `wo` to the normal.
    pub cos_o: f64,
}

impl IsotropicCosines {
    /// From unit directions; `None` when either is at or below the horizon.
    pub fn from_directions(wi: DVec3, wo: DVec3) -> Option<Self> {
        both_above_surface(wi, wo).then(|| Self::of_pair(wi, wo))
    }

    /// The cosines of a pair, NaN if its directions are opposite (no `h`); the caller checks
    /// that both directions are above the surface.
    fn of_pair(wi: DVec3, wo: DVec3) -> Self {
        let h = (wi + wo).normalize();
        Self {
            cos_h: h.z,
            cos_d: wi.dot(h),
            cos_i: wi.z,
            cos_o: wo.z,
        }
    }

    /// From half-difference angles without building the directions (the frame of docs/book/src/design.md);
    /// `None` when either direction is at or below the horizon. See [`IsotropicRow::at`].
    pub fn from_half_diff(hd: HalfDiff) -> Option<Self> {
        IsotropicRow::new(hd.theta_h, hd.theta_d).at(hd.phi_d.cos())
    }
}

/// The cosines ([`IsotropicCosines`]) of up to [`CosineColumns::CAPACITY`] direction
/// pairs, a column per cosine, so that a model evaluates a block of pairs in vector
/// instructions (the batched [`crate::Brdf::eval_pairs`]). A pair with a direction at or
/// below the horizon holds the cosines of the normal (all 1), which keep every formula
/// finite, and is flagged in [`CosineColumns::above`]: its value is zero. One block is
/// refilled for each run of pairs ([`CosineColumns::set_directions`]).
#[derive(Debug, Clone)]
pub struct CosineColumns {
    len: usize,
    /// The components of the block's `wi` and `wo` (x, y, z of each), a column each.
    components: [[f64; Self::CAPACITY]; 6],
    /// Whether both directions of each pair are strictly above the surface.
    pub above: [bool; Self::CAPACITY],
    /// `cos theta_h` of each pair.
    pub cos_h: [f64; Self::CAPACITY],
    /// `cos theta_d` (`wi . h`) of each pair.
    pub cos_d: [f64; Self::CAPACITY],
    /// The cosine of `wi` to the normal of each pair.
    pub cos_i: [f64; Self::CAPACITY],
    /// The cosine of `wo` to the normal of each pair.
    pub cos_o: [f64; Self::CAPACITY],
}

impl Default for CosineColumns {
    fn default() -> Self {
        Self {
            len: 0,
            components: [[0.0; Self::CAPACITY]; 6],
            above: [false; Self::CAPACITY],
            cos_h: [1.0; Self::CAPACITY],
            cos_d: [1.0; Self::CAPACITY],
            cos_i: [1.0; Self::CAPACITY],
            cos_o: [1.0; Self::CAPACITY],
        }
    }
}

impl CosineColumns {
    /// Pairs a block holds: enough for the vector loops, few enough to stay in the L1 cache.
    pub const CAPACITY: usize = 64;

    /// Fills the block with the pairs `(wi[k], wo[k])`, unit directions, at most
    /// [`CosineColumns::CAPACITY`] of them: the cosines of
    /// [`IsotropicCosines::from_directions`], bit for bit. The directions are first split
    /// into columns of components, so that the cosines are computed in vector
    /// instructions. Panics if the slices differ in length or are longer than a block.
    pub fn set_directions(&mut self, wi: &[DVec3], wo: &[DVec3]) {
        assert!(
            wi.len() == wo.len() && wi.len() <= Self::CAPACITY,
            "CosineColumns: {} wi and {} wo for a block of {}",
            wi.len(),
            wo.len(),
            Self::CAPACITY
        );
        let n = wi.len();
        self.len = n;
        let [wi_x, wi_y, wi_z, wo_x, wo_y, wo_z] = &mut self.components;
        for (k, (wi, wo)) in wi.iter().zip(wo).enumerate() {
            (wi_x[k], wi_y[k], wi_z[k]) = (wi.x, wi.y, wi.z);
            (wo_x[k], wo_y[k], wo_z[k]) = (wo.x, wo.y, wo.z);
        }
        let [wi_x, wi_y, wi_z, wo_x, wo_y, wo_z] = &self.components;
        for k in 0..n {
            let wi = DVec3::new(wi_x[k], wi_y[k], wi_z[k]);
            let wo = DVec3::new(wo_x[k], wo_y[k], wo_z[k]);
            let above = both_above_surface(wi, wo);
            let c = IsotropicCosines::of_pair(wi, wo);
            self.above[k] = above;
            self.cos_h[k] = if above { c.cos_h } else { 1.0 };
            self.cos_d[k] = if above { c.cos_d } else { 1.0 };
            self.cos_i[k] = if above { c.cos_i } else { 1.0 };
            self.cos_o[k] = if above { c.cos_o } else { 1.0 };
        }
    }

    /// The number of pairs.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether there is no pair.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
}

/// The configurations of constant theta_h and theta_d (a row of the MERL grid), where only
/// `cos_i` and `cos_o` change with phi_d.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IsotropicRow {
    /// `cos theta_h`.
    pub cos_h: f64,
    /// `sin theta_h`.
    pub sin_h: f64,
    /// `cos theta_d`.
    pub cos_d: f64,
    /// `sin theta_d`.
    pub sin_d: f64,
}

impl IsotropicRow {
    /// The row of `theta_h` and `theta_d`, radians.
    pub fn new(theta_h: f64, theta_d: f64) -> Self {
        let (sin_h, cos_h) = theta_h.sin_cos();
        let (sin_d, cos_d) = theta_d.sin_cos();
        Self {
            cos_h,
            sin_h,
            cos_d,
            sin_d,
        }
    }

    /// The cosines at the azimuth whose cosine is `cos_phi_d` (the frame of docs/book/src/design.md):
    /// `cos_i = cos theta_h cos theta_d - sin theta_h sin theta_d cos phi_d` and, `wo`
    /// being `wi` mirrored about `h`, `cos_o = 2 cos theta_h cos theta_d - cos_i`.
    /// `None` when either direction is at or below the horizon.
    pub fn at(&self, cos_phi_d: f64) -> Option<IsotropicCosines> {
        let cos_i = self.cos_h * self.cos_d - self.sin_h * self.sin_d * cos_phi_d;
        let cos_o = 2.0 * self.cos_h * self.cos_d - cos_i;
        (cos_i > 0.0 && cos_o > 0.0).then_some(IsotropicCosines {
            cos_h: self.cos_h,
            cos_d: self.cos_d,
            cos_i,
            cos_o,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Spherical;
    use std::f64::consts::PI;

    /// `int f(m) dm` over the upper hemisphere by the midpoint rule in
    /// `(u = 1 - cos theta, phi)`, with nodes crowded near the pole where narrow lobes live.
    fn hemisphere_integral(f: impl Fn(DVec3) -> f64, n_theta: usize, n_phi: usize) -> f64 {
        let mut sum = 0.0;
        // cos theta = 1 - t^2, t in (0, 1): dm = sin theta dtheta dphi = 2 t dt dphi.
        for i in 0..n_theta {
            let t = (i as f64 + 0.5) / n_theta as f64;
            let cos_t = 1.0 - t * t;
            let theta = cos_t.clamp(-1.0, 1.0).acos();
            for j in 0..n_phi {
                let phi = (j as f64 + 0.5) / n_phi as f64 * 2.0 * PI;
                sum += f(Spherical::new(theta, phi).to_vector()) * 2.0 * t;
            }
        }
        sum / n_theta as f64 * (2.0 * PI / n_phi as f64)
    }

    #[test]
    fn distributions_are_normalised() {
        for distribution in [Distribution::Ggx, Distribution::Beckmann] {
            for (au, av) in [(0.1, 0.1), (0.3, 0.3), (0.05, 0.4)] {
                let mf = Microfacet::anisotropic(distribution, au, av);
                let total = hemisphere_integral(|m| mf.d(m) * m.z, 800, 256);
                // GGX's tails reach the horizon, where the midpoint rule undersamples a little.
                assert!(
                    (total - 1.0).abs() < 2e-3,
                    "{distribution:?} {au} {av}: {total}"
                );
            }
        }
    }

    /// The defining property of Smith masking: the projected area of the visible microfacets
    /// equals the projected area of the macro-surface, `int G1(v, m) max(0, v.m) D(m) dm =
    /// cos theta_v` (Heitz 2014, "Understanding the masking-shadowing function").
    #[test]
    fn masking_conserves_projected_area() {
        for (distribution, tolerance) in [(Distribution::Ggx, 2e-3), (Distribution::Beckmann, 6e-3)]
        {
            for (au, av) in [(0.2, 0.2), (0.1, 0.4)] {
                let mf = Microfacet::anisotropic(distribution, au, av);
                for theta_v_deg in [0.0, 30.0, 60.0, 80.0] {
                    let v = Spherical::from_degrees(theta_v_deg, 35.0).to_vector();
                    let projected = hemisphere_integral(
                        |m| mf.g1(v, m) * v.dot(m).max(0.0) * mf.d(m),
                        800,
                        256,
                    );
                    let relative = (projected - v.z) / v.z;
                    assert!(
                        relative.abs() < tolerance,
                        "{distribution:?} ({au},{av}) at {theta_v_deg}: {projected} vs {}",
                        v.z
                    );
                }
            }
        }
    }

    /// The exact Beckmann Smith term `G1 = 2 / (1 + erf(a) + exp(-a^2) / (a sqrt(pi)))`,
    /// with erf by Simpson's rule, against the rational approximation.
    #[test]
    fn beckmann_masking_approximation_is_within_its_published_error() {
        fn erf(x: f64) -> f64 {
            let n = 2000;
            let h = x / n as f64;
            let f = |t: f64| (-t * t).exp();
            let mut s = f(0.0) + f(x);
            for i in 1..n {
                s += f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
            }
            s * h / 3.0 * 2.0 / PI.sqrt()
        }
        let alpha = 0.3;
        let mf = Microfacet::isotropic(Distribution::Beckmann, alpha);
        for theta_deg in [20.0, 50.0, 70.0, 80.0, 85.0, 89.0] {
            let v = Spherical::from_degrees(theta_deg, 0.0).to_vector();
            let a = v.z / (alpha * (1.0 - v.z * v.z).sqrt());
            let exact = 2.0 / (1.0 + erf(a) + (-a * a).exp() / (a * PI.sqrt()));
            let approx = mf.g1(v, DVec3::Z);
            assert!(
                (approx - exact).abs() / exact < 0.0035,
                "{theta_deg}: {approx} vs {exact}"
            );
        }
    }

    #[test]
    fn masking_is_one_at_normal_incidence_and_zero_behind_the_facet() {
        let mf = Microfacet::isotropic(Distribution::Ggx, 0.2);
        assert_eq!(mf.g1(DVec3::Z, DVec3::Z), 1.0);
        let v = Spherical::from_degrees(60.0, 0.0).to_vector();
        let m = Spherical::from_degrees(80.0, 180.0).to_vector();
        assert_eq!(mf.g1(v, m), 0.0);
    }

    #[test]
    fn isotropic_shortcut_matches_the_vector_form() {
        use std::f64::consts::TAU;
        for distribution in [Distribution::Ggx, Distribution::Beckmann] {
            for alpha in [0.005, 0.05, 0.4] {
                let mf = Microfacet::isotropic(distribution, alpha);
                for i in 0..300 {
                    let x = i as f64;
                    let hd = HalfDiff::new(
                        (x * 0.037).rem_euclid(1.5),
                        (x * 1.3).rem_euclid(TAU),
                        (x * 0.71).rem_euclid(1.5),
                        (x * 2.9).rem_euclid(TAU),
                    );
                    let (wi, wo) = hd.to_directions();
                    let by_vectors = mf.reflection(wi, wo);
                    let from_angles = IsotropicCosines::from_half_diff(hd);
                    let from_directions = IsotropicCosines::from_directions(wi, wo);
                    assert_eq!(from_angles.is_some(), from_directions.is_some(), "{hd:?}");
                    let (Some(a), Some(b)) = (from_angles, from_directions) else {
                        assert_eq!(by_vectors, 0.0);
                        continue;
                    };
                    for c in [a, b] {
                        let shortcut = mf.reflection_isotropic(c);
                        assert!(
                            (shortcut - by_vectors).abs() <= 1e-8 * by_vectors.max(1e-12),
                            "{distribution:?} {alpha} {hd:?}: {shortcut} vs {by_vectors}"
                        );
                    }
                }
            }
        }
    }
}
