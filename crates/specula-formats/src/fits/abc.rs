//! The ABC model of Löw, Kronander, Ynnerman & Unger, "BRDF models for accurate and efficient
//! rendering of glossy surfaces", ACM TOG 31(1), 2012, with the parameters fitted to the MERL
//! materials. With `i` towards the light, `o` towards the camera, `h = normalize(i + o)`:
//!
//! ```text
//! f_r = kD / pi + F(i . h; ior) D G / (pi i.z o.z)
//! D   = A / (1 + B (1 - cos theta_h))^C          (A and kD per channel)
//! G   = min(1, 2 h.z i.z / (i . h), 2 h.z o.z / (o . h))   (Cook-Torrance V-groove)
//! F   = the unpolarised Fresnel reflectance of a dielectric of real index ior
//! ```

use super::TableRow;
use crate::input::Malformed;
use glam::DVec3;
use specula_core::brdf::both_above_surface;
use specula_core::scattering::fresnel::dielectric as fresnel_dielectric;
use specula_core::{Brdf, Rgb};
use std::f64::consts::PI;

/// One material's ABC fit.
#[derive(Debug, Clone, PartialEq)]
pub struct Abc {
    /// The MERL material the fit is of, as in the `abc:NAME` argument.
    pub name: String,
    /// Diffuse coefficient `kD` per channel (f_r contributes `kD / pi`, 1/sr).
    pub k_d: Rgb,
    /// Scale `A` of the distribution `D` per channel.
    pub a: Rgb,
    /// Width `B` of the distribution, the coefficient of `1 - cos theta_h` (non-negative).
    pub b: f64,
    /// Falloff exponent `C` of the distribution `D = A / (1 + B (1 - cos theta_h))^C`.
    pub c: f64,
    /// Real index of refraction of the Fresnel term (positive).
    pub ior: f64,
}

impl Abc {
    pub(crate) fn from_row(row: &TableRow) -> Result<Self, Malformed> {
        let fit = Self {
            name: row.text("material")?.to_string(),
            k_d: row.rgb("kD")?,
            a: row.rgb("A")?,
            b: row.number("B")?,
            c: row.number("C")?,
            ior: row.number("ior")?,
        };
        if fit.ior <= 0.0 || fit.b < 0.0 {
            return Err(format!("{}: needs ior > 0 and B >= 0", fit.name).into());
        }
        Ok(fit)
    }
}

impl Brdf for Abc {
    fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
        if !both_above_surface(wi, wo) {
            return Some(Rgb::ZERO);
        }
        let (wi, wo) = (wi.normalize(), wo.normalize());
        let h = (wi + wo).normalize();
        let (i_h, o_h) = (wi.dot(h), wo.dot(h));
        let shadowing = 1f64
            .min(2.0 * h.z * wi.z / i_h)
            .min(2.0 * h.z * wo.z / o_h)
            .max(0.0);
        let fresnel = fresnel_dielectric(i_h, self.ior);
        let falloff = (1.0 + self.b * (1.0 - h.z)).powf(self.c);
        let specular = self.a / falloff * (fresnel * shadowing / (PI * wi.z * wo.z));
        Some((self.k_d / PI + specular).max(Rgb::ZERO))
    }

    fn name(&self) -> String {
        format!("abc:{}", self.name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_has_its_known_values() {
        // Normal incidence: ((n - 1) / (n + 1))^2; grazing: 1; Brewster: r_p = 0.
        let n: f64 = 1.5;
        assert!((fresnel_dielectric(1.0, n) - 0.04).abs() < 1e-12);
        assert!((fresnel_dielectric(0.0, n) - 1.0).abs() < 1e-12);
        let brewster = n.atan();
        let cos_b = brewster.cos();
        let sin_t = brewster.sin() / n;
        let r_s =
            (cos_b - n * (1.0 - sin_t * sin_t).sqrt()) / (cos_b + n * (1.0 - sin_t * sin_t).sqrt());
        assert!((fresnel_dielectric(cos_b, n) - 0.5 * r_s * r_s).abs() < 1e-12);
    }
}
