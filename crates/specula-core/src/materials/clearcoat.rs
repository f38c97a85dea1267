//! Clear-coated paint (the paper's green paint with a thick acrylic coat, section 4): a glossy
//! dielectric lacquer over a Lambertian pigmented base.
//!
//! `f = F(wi . h) D(h) G / (4 cos_i cos_o)`  (the coat's reflection lobe, grey)
//! `  + (1 - E(cos_i)) (1 - E(cos_o)) / (pi eta^2) * rho / (1 - rho r_int)`  (the base)
//!
//! The base term follows Weidlich & Wilkie 2007 and Mitsuba 3's `roughplastic` (non-linear
//! variant): light enters the coat with the fraction `1 - E(cos_i)` that the rough surface
//! does not reflect (`E` is the lobe's directional albedo, [`CoatAlbedo`]; for a smooth coat
//! `E = F`), is scattered by the Lambertian base of albedo `rho`, bounces between the base and
//! the coat's underside (internal diffuse reflectance `r_int`, the geometric series
//! `rho / (1 - rho r_int)`), and leaves with `1 - E(cos_o)`, its radiance divided by `eta^2`
//! by the change of solid angle across the interface. Symmetric in `wi`, `wo` (reciprocal).
//!
//! Energy: with `r_int = 1 - (1 - E_avg) / eta^2`, `E_avg = 2 int E(mu) mu dmu`, the base
//! term's directional albedo is `(1 - E(cos_i)) kappa`, `kappa = rho (1 - r_int) / (1 - rho
//! r_int) <= 1`, so lobe plus base would stay within 1 for any `rho <= 1` if `E` were exact.
//! The tabulated `E` is within ~2e-4, but up to ~3e-3 too low within a degree or two of
//! grazing for mirror-like coats (alpha < 0.01), where it peaks sharply. Capping the base
//! albedo at [`MAX_BASE_ALBEDO`] (`kappa <= 0.89`; real pigments stay below ~0.9, white TiO2
//! included) leaves a margin `(1 - E) (1 - kappa)` that absorbs it. The integration tests
//! check the directional albedo numerically up to 89 degrees for alpha from 0.003 to 1.

use super::coat_albedo::CoatAlbedo;
use super::microfacet::{Distribution, IsotropicCosines, IsotropicRow, Microfacet};
use crate::brdf::Rgb;
use crate::scattering::fresnel;
use std::f64::consts::PI;

/// The brightest base albedo per channel a material file accepts (see the energy note).
pub const MAX_BASE_ALBEDO: f64 = 0.95;

/// A rough dielectric coat of index `ior` over a Lambertian base of albedo `base_color`.
#[derive(Debug, Clone, PartialEq)]
pub struct ClearCoat {
    coat: Microfacet,
    /// Refractive index of the lacquer relative to air (acrylic ~1.49).
    pub ior: f64,
    /// Albedo of the Lambertian base per channel, in `[0, MAX_BASE_ALBEDO]`.
    pub base_color: Rgb,
    /// `E(mu)`, the fraction the coat's surface reflects.
    albedo: CoatAlbedo,
    /// `r_int`: reflectance of the coat's underside to diffuse light from the base.
    internal_reflectance: f64,
}

impl ClearCoat {
    /// A coat with roughness `alpha` of the given distribution.
    pub fn new(distribution: Distribution, alpha: f64, ior: f64, base_color: Rgb) -> Self {
        let coat = Microfacet::isotropic(distribution, alpha);
        let albedo = CoatAlbedo::new(&coat, ior);
        let internal_reflectance = 1.0 - (1.0 - albedo.average()) / (ior * ior);
        Self {
            coat,
            ior,
            base_color,
            albedo,
            internal_reflectance,
        }
    }

    /// The coat's microfacet distribution's shape.
    pub fn distribution(&self) -> Distribution {
        self.coat.distribution
    }

    /// The coat's roughness (isotropic).
    pub fn alpha(&self) -> f64 {
        self.coat.alpha_u
    }

    /// The coat's Fresnel reflectance at `cos_d = wi . h` (grey).
    pub fn fresnel(&self, cos_d: f64) -> f64 {
        fresnel::dielectric(cos_d, self.ior)
    }

    /// f_r in 1/sr from the cosines of an isotropic configuration.
    pub fn eval_cosines(&self, c: IsotropicCosines) -> Rgb {
        let specular = self.fresnel(c.cos_d) * self.coat.reflection_isotropic(c);
        Rgb::splat(specular) + self.multiple_bounces() * self.through_coat(c)
    }

    /// f_r in 1/sr as a function of `cos(phi_d)` along a row of constant theta_h and theta_d:
    /// the coat's `F D` and the base's bounce factor are computed once for the row.
    pub fn along_row(&self, row: IsotropicRow) -> impl Fn(f64) -> Rgb + '_ {
        let fresnel_d = self.fresnel(row.cos_d) * self.coat.d_isotropic(row.cos_h);
        let multiple_bounces = self.multiple_bounces();
        move |cos_phi_d| {
            row.at(cos_phi_d).map_or(Rgb::ZERO, |c| {
                let specular = fresnel_d * self.coat.masking_over_cosines(c.cos_i, c.cos_o);
                Rgb::splat(specular) + multiple_bounces * self.through_coat(c)
            })
        }
    }

    /// `(1 - E(cos_i)) (1 - E(cos_o)) / (pi eta^2)`: the light that crosses the coat twice.
    fn through_coat(&self, c: IsotropicCosines) -> f64 {
        (1.0 - self.albedo.at(c.cos_i)) * (1.0 - self.albedo.at(c.cos_o))
            / (PI * self.ior * self.ior)
    }

    /// `rho / (1 - rho r_int)`: the base's albedo with the bounces under the coat.
    fn multiple_bounces(&self) -> Rgb {
        let rho = self.base_color;
        rho / (Rgb::ONE - rho * self.internal_reflectance)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn black_base_leaves_only_the_coat() {
        let coat = ClearCoat::new(Distribution::Ggx, 0.05, 1.5, Rgb::ZERO);
        let c = IsotropicCosines::from_directions(DVec3::Z, DVec3::Z).unwrap();
        let expected = 0.04 / (4.0 * PI * 0.05 * 0.05);
        let f = coat.eval_cosines(c);
        assert!((f - Rgb::splat(expected)).abs().max_element() < 1e-9 * expected);
    }

    #[test]
    fn base_term_is_lambertian_times_the_coat_transmission() {
        // Far from the specular peak only the base remains. A nearly smooth coat reflects
        // E = F, so the base is (1 - F(cos_i)) (1 - F(cos_o)) / (pi 1.5^2) rho / (1 - rho r_int)
        // with r_int from the smooth interface's diffuse reflectance (Weidlich & Wilkie 2007).
        let rho = Rgb::new(0.1, 0.5, 0.2);
        // Beckmann: its lobe vanishes (exp(-3333)) 30 deg away from the peak, unlike GGX tails.
        let coat = ClearCoat::new(Distribution::Beckmann, 0.01, 1.5, rho);
        let wi = DVec3::Z;
        let wo = crate::geometry::Spherical::from_degrees(60.0, 0.0).to_vector();
        let f = coat.eval_cosines(IsotropicCosines::from_directions(wi, wo).unwrap());
        let f_dr_int = 1.0 - (1.0 - fresnel::dielectric_diffuse_reflectance(1.5)) / 2.25;
        let t = (1.0 - 0.04) * (1.0 - fresnel::dielectric(0.5, 1.5)) / (PI * 2.25);
        let expected = rho * t / (Rgb::ONE - rho * f_dr_int);
        assert!((f - expected).abs().max_element() < 1e-3 * expected.max_element());
    }
}
