//! The shifted-gamma microfacet model of Bagher, Soler & Holzschuch, "Accurate fitting of
//! measured reflectances using a Shifted Gamma micro-facet distribution", EGSR 2012, with the
//! parameters they fitted to the MERL materials. Per channel, with `i` towards the light,
//! `o` towards the camera, `h = normalize(i + o)`, `cd = i . h`:
//!
//! ```text
//! f_r = ( rhoD + rhoS F D G / (i.z o.z) ) / pi
//! F   = f0 - cd f1 + (1 - cd)^5 (1 - f0)
//! D   = kap exp(-ax) / (pi ax^p cos^4 theta_h),   ax = alpha + tan^2 theta_h / alpha
//! G   = G1(i) G1(o),  G1(w) = clamp(1 + lambda (1 - exp(c max(0, acos w.z - theta0)^k)), 0, 1)
//! ```
//! A negative total (possible for some fitted Fresnel terms) is clamped to zero.

use super::TableRow;
use crate::input::Malformed;
use glam::DVec3;
use specula_core::brdf::both_above_surface;
use specula_core::scattering::fresnel;
use specula_core::{Brdf, Rgb};
use std::f64::consts::PI;

/// One material's SGD fit; every parameter per channel (x red, y green, z blue).
#[derive(Debug, Clone, PartialEq)]
pub struct Sgd {
    /// The MERL material the fit is of, as in the `sgd:NAME` argument.
    pub name: String,
    /// Diffuse albedo `rhoD` (f_r contributes `rhoD / pi`, 1/sr).
    pub rho_d: Rgb,
    /// Specular albedo `rhoS`, the weight of the microfacet term.
    pub rho_s: Rgb,
    /// Roughness `alpha` of the shifted-gamma distribution (positive).
    pub alpha: Rgb,
    /// Exponent `p` of `ax` in the shifted-gamma distribution `D`.
    pub p: Rgb,
    /// Constant `f0` of the fitted Fresnel term `F = f0 - cd f1 + (1 - cd)^5 (1 - f0)`.
    pub f0: Rgb,
    /// Linear coefficient `f1` of `cos theta_d` in the fitted Fresnel term.
    pub f1: Rgb,
    /// Normalisation `kap` of the shifted-gamma distribution `D`.
    pub kap: Rgb,
    /// Strength `lambda` of the shadowing term `G1`.
    pub lambda: Rgb,
    /// Rate `c` in the exponential of the shadowing term `G1`.
    pub c: Rgb,
    /// Exponent `k` of the elevation excess in the shadowing term `G1`.
    pub k: Rgb,
    /// Elevation `theta0` in rad above which the shadowing term `G1` falls below one.
    pub theta0: Rgb,
}

impl Sgd {
    pub(crate) fn from_row(row: &TableRow) -> Result<Self, Malformed> {
        let fit = Self {
            name: row.text("material")?.to_string(),
            rho_d: row.rgb("rhoD")?,
            rho_s: row.rgb("rhoS")?,
            alpha: row.rgb("alpha")?,
            p: row.rgb("p")?,
            f0: row.rgb("f0")?,
            f1: row.rgb("f1")?,
            kap: row.rgb("kap")?,
            lambda: row.rgb("lambda")?,
            c: row.rgb("c")?,
            k: row.rgb("k")?,
            theta0: row.rgb("theta0")?,
        };
        if fit.alpha.min_element() <= 0.0 {
            return Err(format!("{}: alpha must be positive", fit.name).into());
        }
        Ok(fit)
    }

    /// The shadowing term of one direction for channel `ch`.
    fn g1(&self, w: DVec3, ch: usize) -> f64 {
        let excess = (w.z.clamp(-1.0, 1.0).acos() - self.theta0[ch]).max(0.0);
        let g = 1.0 + self.lambda[ch] * (1.0 - (self.c[ch] * excess.powf(self.k[ch])).exp());
        g.clamp(0.0, 1.0)
    }
}

impl Brdf for Sgd {
    fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
        if !both_above_surface(wi, wo) {
            return Some(Rgb::ZERO);
        }
        let (wi, wo) = (wi.normalize(), wo.normalize());
        let h = (wi + wo).normalize();
        let cd = wi.dot(h).clamp(0.0, 1.0);
        let cos_h = h.z.clamp(1e-300, 1.0);
        let tan2_h = (1.0 - cos_h * cos_h).max(0.0) / (cos_h * cos_h);
        let mut f = [0.0; 3];
        for (ch, value) in f.iter_mut().enumerate() {
            let fresnel =
                self.f0[ch] - cd * self.f1[ch] + fresnel::schlick_weight(cd) * (1.0 - self.f0[ch]);
            let ax = self.alpha[ch] + tan2_h / self.alpha[ch];
            let d = self.kap[ch] * (-ax).exp() / (PI * ax.powf(self.p[ch]) * cos_h.powi(4));
            let g = self.g1(wi, ch) * self.g1(wo, ch);
            let specular = self.rho_s[ch] * fresnel * d * g / (wi.z * wo.z);
            *value = ((self.rho_d[ch] + specular) / PI).max(0.0);
        }
        Some(Rgb::from_array(f))
    }

    fn name(&self) -> String {
        format!("sgd:{}", self.name)
    }
}
