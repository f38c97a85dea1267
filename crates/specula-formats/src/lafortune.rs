//! Lafortune-model fits of measured materials by Ngan, Durand & Matusik, "Experimental
//! Analysis of BRDF Models", EGSR 2005 (100 MERL/MIT materials), as `lafortune:NAME`.
//!
//! One normalised lobe with per-channel diffuse and specular albedos, directions `i` (to the
//! light) and `o` (to the camera), z the normal:
//! `f_r = rho_d / pi + rho_s (n + 2) / (2 pi) * (max(0, C_xy (i.x o.x + i.y o.y) + C_z i.z o.z)
//! / max(|C_xy|, |C_z|))^n`.
//! Table, parameter mapping and checks: `shared/data/measured/merl_fits_ngan2005_lafortune/`.

use crate::input::argument_error;
use crate::input::{csv_error, file_error, measured_file, read_input, Malformed, Result};
use glam::DVec3;
use specula_core::bounded_read::{BoundedText, CSV_LIMITS};
use specula_core::brdf::both_above_surface;
use specula_core::{Brdf, Rgb};
use std::f64::consts::PI;
use std::path::Path;

/// The table's path inside the measured data directory.
pub const TABLE: &str = "merl_fits_ngan2005_lafortune/merl_lafortune_ngan2005.csv";

/// One fitted Lafortune lobe.
#[derive(Debug, Clone, PartialEq)]
pub struct Lafortune {
    /// The MERL material the fit is of.
    pub name: String,
    /// Diffuse albedo per channel.
    pub rho_d: Rgb,
    /// Specular albedo per channel.
    pub rho_s: Rgb,
    /// Weight of the tangential part of the dot product (negative: a mirror-like lobe).
    pub c_xy: f64,
    /// Weight of the normal part of the dot product.
    pub c_z: f64,
    /// Lobe exponent.
    pub n: f64,
}

#[derive(serde::Deserialize)]
struct Row {
    material: String,
    rho_d_r: f64,
    rho_d_g: f64,
    rho_d_b: f64,
    rho_s_r: f64,
    rho_s_g: f64,
    rho_s_b: f64,
    #[serde(rename = "C_xy")]
    c_xy: f64,
    #[serde(rename = "C_z")]
    c_z: f64,
    n: f64,
}

impl Lafortune {
    /// The fit of `material` from the table in the measured data directory.
    pub fn by_name(material: &str) -> Result<Self> {
        let path = measured_file(TABLE)?;
        let all = Self::read_table(&path)?;
        let count = all.len();
        all.into_iter().find(|f| f.name == material).ok_or_else(|| {
            argument_error(
                &format!("lafortune:{material}"),
                format!("no such material among the {count} of {}", path.display()),
            )
        })
    }

    /// Every fit of a table file (columns `index, material, rho_d_r..b, rho_s_r..b, C_xy, C_z, n`).
    pub fn read_table(path: &Path) -> Result<Vec<Self>> {
        let bytes = read_input(path)?;
        let mut reader = csv::Reader::from_reader(BoundedText::new(bytes.as_slice(), CSV_LIMITS));
        let mut fits = Vec::new();
        for (i, row) in reader.deserialize::<Row>().enumerate() {
            let row = row.map_err(|e| csv_error(path, format!("row {}", i + 2), e))?;
            let fit =
                Self::from_row(row).map_err(|p| file_error(path, format!("row {}: {p}", i + 2)))?;
            fits.push(fit);
        }
        Ok(fits)
    }

    fn from_row(r: Row) -> Result<Self, Malformed> {
        let fit = Self {
            name: r.material,
            rho_d: Rgb::new(r.rho_d_r, r.rho_d_g, r.rho_d_b),
            rho_s: Rgb::new(r.rho_s_r, r.rho_s_g, r.rho_s_b),
            c_xy: r.c_xy,
            c_z: r.c_z,
            n: r.n,
        };
        let scalars_finite = [fit.c_xy, fit.c_z, fit.n].iter().all(|v| v.is_finite());
        if !(fit.rho_d.is_finite() && fit.rho_s.is_finite() && scalars_finite) {
            return Err(format!("{}: a parameter is not finite", fit.name).into());
        }
        if (fit.c_xy == 0.0 && fit.c_z == 0.0) || fit.n < 0.0 {
            return Err(format!("{}: degenerate lobe (C_xy = C_z = 0 or n < 0)", fit.name).into());
        }
        Ok(fit)
    }

    /// The lobe's cosine term before the exponent, normalised by `max(|C_xy|, |C_z|)`.
    fn lobe_cosine(&self, wi: DVec3, wo: DVec3) -> f64 {
        let dot = self.c_xy * (wi.x * wo.x + wi.y * wo.y) + self.c_z * wi.z * wo.z;
        dot.max(0.0) / self.c_xy.abs().max(self.c_z.abs())
    }
}

impl Brdf for Lafortune {
    fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
        if !both_above_surface(wi, wo) {
            return Some(Rgb::ZERO);
        }
        let lobe = (self.n + 2.0) / (2.0 * PI)
            * self
                .lobe_cosine(wi.normalize(), wo.normalize())
                .powf(self.n);
        Some(self.rho_d / PI + self.rho_s * lobe)
    }

    fn name(&self) -> String {
        format!("lafortune:{}", self.name)
    }
}
