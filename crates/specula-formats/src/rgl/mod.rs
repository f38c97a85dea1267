//! Isotropic RGB files of the RGL material database (`.bsdf`): Dupuy & Jakob, "An Adaptive
//! Parameterization for Efficient Material Acquisition and Rendering", ACM TOG 37(6), 2018.
//!
//! The measured RGB values sit on a 2-D domain warped by the material's own visible normal
//! distribution (VNDF), one slice per incident elevation. Evaluating the file at its incident
//! direction `wi` and outgoing direction `wo`, as the reference loader (`powitacq_rgb`) and
//! Mitsuba 3's `measured` plugin do:
//!
//! 1. `h = normalize(wi + wo)`; elevations and azimuths of `wi` and `h`, and the unit
//!    coordinates `u(theta) = sqrt(2 theta / pi)`, `u(phi) = (phi + pi) / (2 pi)`; for an
//!    isotropic file the azimuth of `h` is taken relative to `wi`'s.
//! 2. The inverse of the VNDF warp at `theta_i` maps `u(h)` to the sample domain.
//! 3. The RGB table is interpolated there (bilinear, and linear in `theta_i`); negative
//!    (out-of-gamut) values are clamped to zero as `powitacq_rgb` does.
//! 4. When the file's `jacobian` flag is set, the value is multiplied by
//!    `D(u(h)) / (4 sigma(u(wi)))`, the NDF over the projected area.
//!
//! The result is the measured quantity f_r cos(theta_o) (Mitsuba's `eval` returns exactly
//! it); [`RglBsdf`] divides by `cos(theta_o)` to give f_r in 1/sr.
//!
//! Which slot is the camera: Mitsuba 3 passes the direction towards the camera (its `si.wi`)
//! as the file's incident direction and the direction towards the light as the outgoing one
//! (`tools/rgl_convention_check.py`: at the nodes of a real file Mitsuba reproduces the
//! tabulated value in that order, median 4e-7, and not in the other, median 9 %: the measured
//! files are not reciprocal). Specula follows it, so a file renders in Specula as in Mitsuba:
//! [`Brdf::eval`]`(wi, wo)`, with `wi` towards the light and `wo` towards the camera, looks
//! the file up at incident `wo` and outgoing `wi`, and the writer ([`write`]) stores a
//! source's `f_r(light, camera)` the same way. Colour: the files hold an
//! `rgb` field and no spectra, and Mitsuba's RGB variants read that field as three channels
//! with no spectral integration; so does this reader. Checked against Mitsuba 3.9.1 by
//! `tools/rgl_vectors.py` and `tests/rgl_mitsuba.rs`.
//!
//! At normal incidence the incident azimuth is undefined; it is taken as pi, as Mitsuba does
//! (see [`azimuth`]). Only isotropic files (`phi_i` with one entry) are supported.

mod ndf;
mod tensor;
mod warp;
pub mod write;

use crate::input::{Malformed, Result};
use glam::{DVec2, DVec3};
use specula_core::brdf::both_above_surface;
use specula_core::{Brdf, Rgb};
use std::f64::consts::PI;
use std::path::Path;
use tensor::TensorFile;
use warp::{Grid, GridStack, VndfWarp};

pub use tensor::MAGIC;
pub use write::{RglResolution, RglTables, RglWriteError};

/// A measured isotropic RGB material of the RGL database, evaluated as its reference loader.
#[derive(Debug, Clone)]
pub struct RglBsdf {
    name: String,
    description: String,
    jacobian: bool,
    ndf: Grid,
    sigma: Grid,
    vndf: VndfWarp,
    rgb: [GridStack; 3],
}

/// Shape of the 4-D and 5-D tables: `[phi_i, theta_i, ..., rows, columns]`.
struct TableShape {
    rows: usize,
    columns: usize,
}

impl RglBsdf {
    /// Reads a `.bsdf` file; the error names the file and the problem.
    pub fn read(path: &Path) -> Result<Self> {
        let bytes = crate::input::read_input(path)?;
        let name = crate::input::file_stem(path);
        Self::from_bytes(name, &bytes).map_err(|problem| crate::input::file_error(path, problem))
    }

    /// Parses the bytes of a `.bsdf` file; the error says what is wrong.
    pub fn from_bytes(name: impl Into<String>, bytes: &[u8]) -> Result<Self, Malformed> {
        let tf = TensorFile::parse(bytes)?;
        let description = String::from_utf8_lossy(tf.u8_field("description")?).into_owned();
        let jacobian = match tf.u8_field("jacobian")? {
            [flag] => *flag != 0,
            other => {
                return Err(
                    format!("field 'jacobian' has {} entries, expected 1", other.len()).into(),
                )
            }
        };
        let (phi_i, _) = tf.f32_field("phi_i", 1)?;
        if phi_i.len() != 1 {
            return Err(format!(
                "anisotropic material (phi_i has {} entries); only isotropic RGL files are supported",
                phi_i.len()
            ).into());
        }
        let theta_i_rad = elevations(&tf)?;
        let n_theta = theta_i_rad.len();
        let ndf = plain_grid(&tf, "ndf", false)?;
        let sigma = plain_grid(&tf, "sigma", true)?;

        let (vndf_values, vndf_shape) = tf.f32_field("vndf", 4)?;
        let vndf_table = table_shape("vndf", &vndf_shape, &[1, n_theta])?;
        if vndf_values.iter().any(|v| *v < 0.0) {
            return Err("field 'vndf' holds negative densities".into());
        }
        let vndf_grids = split_grids(&vndf_values, &vndf_table, n_theta);
        let vndf = VndfWarp::new(theta_i_rad.clone(), &vndf_grids).map_err(|k| {
            format!("field 'vndf': the density of elevation slice {k} integrates to zero")
        })?;

        let (rgb_values, rgb_shape) = tf.f32_field("rgb", 5)?;
        let rgb_table = table_shape("rgb", &rgb_shape, &[1, n_theta, 3])?;
        // Layout [phi_i][theta_i][channel][row][column]: slice index theta * 3 + channel.
        let mut per_slice = split_grids(&rgb_values, &rgb_table, 3 * n_theta).into_iter();
        let mut channels: [Vec<Grid>; 3] = Default::default();
        for _ in 0..n_theta {
            for channel in channels.iter_mut() {
                channel.extend(per_slice.next());
            }
        }
        let rgb = channels.map(|grids| GridStack::new(theta_i_rad.clone(), grids));
        Ok(Self {
            name: name.into(),
            description,
            jacobian,
            ndf,
            sigma,
            vndf,
            rgb,
        })
    }

    /// The material description stored in the file.
    pub fn description(&self) -> &str {
        &self.description
    }

    /// The stored quantity f_r cos(theta_o) at the file's incident direction `wi` (towards the
    /// camera, Mitsuba's `si.wi`) and outgoing direction `wo` (towards the light): what
    /// Mitsuba's `eval(si, wo)` returns, RGB; zero when a direction is at or below the
    /// horizon.
    pub fn eval_projected(&self, wi: DVec3, wo: DVec3) -> Rgb {
        if !both_above_surface(wi, wo) {
            return Rgb::ZERO;
        }
        let wi = wi.normalize();
        let half = (wi + wo.normalize()).normalize();
        let theta_i = elevation(wi);
        let phi_i = azimuth(wi);
        let theta_h = elevation(half);
        let phi_h = azimuth(half);
        let u_wi = DVec2::new(theta_to_unit(theta_i), phi_to_unit(phi_i));
        let u_half_phi = phi_to_unit(phi_h - phi_i);
        let u_half = DVec2::new(theta_to_unit(theta_h), u_half_phi - u_half_phi.floor());

        let sample = self.vndf.invert(u_half, theta_i);
        let mut value = Rgb::from_array(
            self.rgb
                .each_ref()
                .map(|c| c.eval(sample, theta_i).max(0.0)),
        );
        if self.jacobian {
            value *= self.ndf.eval(u_half) / (4.0 * self.sigma.eval(u_wi));
        }
        value
    }
}

impl Brdf for RglBsdf {
    /// f_r in 1/sr for light from `wi` seen from `wo`: the file at incident `wo` (the camera)
    /// and outgoing `wi` (the light), as Mitsuba renders it (module documentation), divided
    /// by the cosine of the light.
    fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
        if !both_above_surface(wi, wo) {
            return Some(Rgb::ZERO);
        }
        Some(self.eval_projected(wo, wi) / wi.normalize().z)
    }

    fn name(&self) -> String {
        self.name.clone()
    }
}

/// Elevation of a unit vector from the normal, computed as Mitsuba does for accuracy near
/// the pole: `2 asin(|d - z| / 2)`.
fn elevation(d: DVec3) -> f64 {
    2.0 * (0.5 * (d - DVec3::Z).length()).clamp(-1.0, 1.0).asin()
}

/// Azimuth of a vector in `[-pi, pi]`. On the pole, where it is undefined, it is pi, the
/// value Mitsuba 3.9.1 (Dr.Jit's `atan2(0, 0)`) uses, so that normal incidence is evaluated
/// in the same azimuthal frame as Mitsuba (`powitacq` uses 0 there; the data differ by up to
/// about 10% between the two frames).
fn azimuth(v: DVec3) -> f64 {
    if v.x == 0.0 && v.y == 0.0 {
        PI
    } else {
        v.y.atan2(v.x)
    }
}

/// Elevation to the unit coordinate of the tables: `sqrt(2 theta / pi)`.
fn theta_to_unit(theta_rad: f64) -> f64 {
    (theta_rad * 2.0 / PI).max(0.0).sqrt()
}

/// Azimuth in `[-pi, pi]` (or beyond, before wrapping) to the unit coordinate `(phi + pi) / 2 pi`.
fn phi_to_unit(phi_rad: f64) -> f64 {
    (phi_rad + PI) / (2.0 * PI)
}

/// The incident elevations of the slices: at least two, strictly increasing.
fn elevations(tf: &TensorFile) -> Result<Vec<f64>, Malformed> {
    let (theta, _) = tf.f32_field("theta_i", 1)?;
    if theta.len() < 2 {
        return Err(format!(
            "field 'theta_i' has {} entries, need at least 2",
            theta.len()
        )
        .into());
    }
    if theta.windows(2).any(|w| w[1] <= w[0]) {
        return Err("field 'theta_i' is not strictly increasing".into());
    }
    Ok(theta.iter().map(|t| *t as f64).collect())
}

/// A rank-2 field as a grid (rows = first axis); `positive` requires every value > 0,
/// otherwise values must be >= 0.
fn plain_grid(tf: &TensorFile, name: &str, positive: bool) -> Result<Grid, Malformed> {
    let (values, shape) = tf.f32_field(name, 2)?;
    if shape[0] < 2 || shape[1] < 2 {
        return Err(format!("field '{name}' has shape {shape:?}, need at least 2 x 2").into());
    }
    let bad = if positive {
        values.iter().any(|v| *v <= 0.0)
    } else {
        values.iter().any(|v| *v < 0.0)
    };
    if bad {
        let need = if positive { "positive" } else { "non-negative" };
        return Err(format!("field '{name}' holds values that are not {need}").into());
    }
    Ok(Grid::new(
        shape[1],
        shape[0],
        values.iter().map(|v| *v as f64).collect(),
    ))
}

/// Checks that `shape` starts with `leading` and ends with two axes of at least 2.
fn table_shape(name: &str, shape: &[usize], leading: &[usize]) -> Result<TableShape, Malformed> {
    let ok = shape.len() == leading.len() + 2
        && shape[..leading.len()] == *leading
        && shape[leading.len()] >= 2
        && shape[leading.len() + 1] >= 2;
    if !ok {
        return Err(format!(
            "field '{name}' has shape {shape:?}, expected {leading:?} followed by two axes of at least 2"
        ).into());
    }
    Ok(TableShape {
        rows: shape[leading.len()],
        columns: shape[leading.len() + 1],
    })
}

/// Cuts a table into `count` consecutive `rows x columns` grids.
fn split_grids(values: &[f32], shape: &TableShape, count: usize) -> Vec<Grid> {
    values
        .chunks_exact(shape.rows * shape.columns)
        .take(count)
        .map(|c| {
            Grid::new(
                shape.columns,
                shape.rows,
                c.iter().map(|v| *v as f64).collect(),
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_coordinates_cover_the_tables() {
        assert_eq!(theta_to_unit(0.0), 0.0);
        assert!((theta_to_unit(PI / 2.0) - 1.0).abs() < 1e-15);
        assert!((phi_to_unit(-PI)).abs() < 1e-15 && (phi_to_unit(PI) - 1.0).abs() < 1e-15);
        let d = DVec3::new(0.3, -0.2, 0.5).normalize();
        assert!((elevation(d) - d.z.acos()).abs() < 1e-14);
    }
}
