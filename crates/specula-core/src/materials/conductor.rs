//! The rough conductor: a metal surface of microfacets (Cook & Torrance 1982, Walter et al.
//! 2007), the model of polished silver, chrome and steel in Specula, identical to Mitsuba 3's
//! `roughconductor` for isotropic roughness:
//!
//! `f(wi, wo) = F(wi . h) D(h) G1(wi, h) G1(wo, h) / (4 cos_i cos_o)` in 1/sr,
//!
//! with `h = normalize(wi + wo)`, `F` the exact conductor Fresnel reflectance per RGB channel
//! and `D`, `G1` from [`Microfacet`].

use super::microfacet::{CosineColumns, Distribution, IsotropicCosines, IsotropicRow, Microfacet};
use crate::brdf::Rgb;
use crate::scattering::fresnel;

/// A rough conductor with isotropic roughness and a complex index `eta + i k` per channel.
#[derive(Debug, Clone, PartialEq)]
pub struct RoughConductor {
    microfacet: Microfacet,
    /// Real part of the relative index per channel (R, G, B).
    pub eta: Rgb,
    /// Extinction coefficient per channel (R, G, B).
    pub k: Rgb,
}

impl RoughConductor {
    /// A conductor with roughness `alpha` of the given distribution.
    pub fn new(distribution: Distribution, alpha: f64, eta: Rgb, k: Rgb) -> Self {
        Self {
            microfacet: Microfacet::isotropic(distribution, alpha),
            eta,
            k,
        }
    }

    /// The microfacet distribution's shape.
    pub fn distribution(&self) -> Distribution {
        self.microfacet.distribution
    }

    /// The roughness (isotropic: along both axes).
    pub fn alpha(&self) -> f64 {
        self.microfacet.alpha_u
    }

    /// Fresnel reflectance per channel at `cos_d = wi . h`.
    pub fn fresnel(&self, cos_d: f64) -> Rgb {
        fresnel::conductor_rgb(cos_d, self.eta, self.k)
    }

    /// f_r in 1/sr from the cosines of an isotropic configuration.
    pub fn eval_cosines(&self, c: IsotropicCosines) -> Rgb {
        self.fresnel(c.cos_d) * self.microfacet.reflection_isotropic(c)
    }

    /// [`RoughConductor::eval_cosines`] at each pair of `columns`, zero where a direction is
    /// at or below the horizon, into `out` (one value per pair): the microfacet factor over
    /// the block ([`Microfacet::reflection_isotropic_columns`]), then the Fresnel reflectance
    /// one channel at a time over the block's `cos_d`. Both loops run in vector instructions;
    /// the values are the same, bit for bit, as pair by pair.
    pub fn eval_columns(&self, columns: &CosineColumns, out: &mut [Rgb]) {
        const CAPACITY: usize = CosineColumns::CAPACITY;
        let n = columns.len();
        assert_eq!(out.len(), n, "one output per pair");
        let mut factor = [0.0; CAPACITY];
        self.microfacet
            .reflection_isotropic_columns(columns, &mut factor[..n]);
        let mut channels = [[0.0; CAPACITY]; 3];
        for (channel, column) in channels.iter_mut().enumerate() {
            let (eta, k) = (self.eta[channel], self.k[channel]);
            let (cos_d, factor) = (&columns.cos_d[..n], &factor[..n]);
            for (j, value) in column[..n].iter_mut().enumerate() {
                let f = fresnel::conductor(cos_d[j], eta, k) * factor[j];
                *value = if columns.above[j] { f } else { 0.0 };
            }
        }
        for (j, out) in out.iter_mut().enumerate() {
            *out = Rgb::new(channels[0][j], channels[1][j], channels[2][j]);
        }
    }

    /// f_r in 1/sr as a function of `cos(phi_d)` along a row of constant theta_h and theta_d:
    /// `F D` depends on the row alone, so only the masking term is left per phi_d.
    pub fn along_row(&self, row: IsotropicRow) -> impl Fn(f64) -> Rgb + '_ {
        let fresnel_d = self.fresnel(row.cos_d) * self.microfacet.d_isotropic(row.cos_h);
        move |cos_phi_d| {
            row.at(cos_phi_d).map_or(Rgb::ZERO, |c| {
                fresnel_d * self.microfacet.masking_over_cosines(c.cos_i, c.cos_o)
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn mirror_peak_has_the_closed_form() {
        // Normal incidence, mirror direction: D = 1/(pi alpha^2), G = 1, F = F(1).
        let alpha = 0.1;
        let eta = Rgb::new(3.535, 2.901, 2.145);
        let k = Rgb::new(4.348, 4.231, 3.862);
        let c = RoughConductor::new(Distribution::Beckmann, alpha, eta, k);
        let cosines = IsotropicCosines::from_directions(DVec3::Z, DVec3::Z).unwrap();
        let f = c.eval_cosines(cosines);
        let f0 = ((eta - 1.0) * (eta - 1.0) + k * k) / ((eta + 1.0) * (eta + 1.0) + k * k);
        let expected = f0 / (4.0 * std::f64::consts::PI * alpha * alpha);
        assert!((f - expected).abs().max_element() < 1e-9 * expected.max_element());
    }
}
