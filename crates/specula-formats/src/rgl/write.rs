//! Writing any BRDF as an isotropic RGB RGL file (Dupuy & Jakob 2018), the tensor file that
//! Mitsuba 3's and pbrt-v4's `measured` BSDFs render.
//!
//! The tables are built as the format's authors build them from a measurement (section 5):
//!
//! 1. `ndf`, `sigma`: the microfacet distribution from the BRDF's retro-reflection by power
//!    iteration, and its projected area ([`super::ndf`]); shape `[2, n]` (two identical
//!    azimuth rows, `n` elevations at `u = sqrt(2 theta / pi)`). A reader multiplies every
//!    interpolated sample by `D` interpolated on its own grid (step 3), so `D`'s nodes must be
//!    fine enough that `D` between them is the `D` the samples were divided by: with 512
//!    nodes (4 KB) a sharp conductor's peak (GGX alpha 0.01) reads back within 0.015 % at
//!    its median, with 128 within 0.22 % (docs/book/src/renderers.md).
//! 2. `vndf`: per incident elevation `theta_i`, the density of visible normals
//!    `D(m) <wi . m> / sigma(wi)` over the unit square `(u(theta_m), u(phi_m - phi_i))`, times
//!    the Jacobian `2 pi^2 u sin(theta_m)` of that square, mixed with a uniform density over
//!    the square ([`UNIFORM_WARP_SHARE`]); shape `[1, T, W, W]` with `W` = [`WARP_SIZE`],
//!    each slice summing to 1.
//!    A reader only uses this field to place the sample grid (and Mitsuba to sample), so any
//!    positive density is exact. The uniform share is most of it: the square's own
//!    coordinate `u(theta_m) = sqrt(2 theta_m / pi)` already packs evenly spaced nodes
//!    towards the normal (the first node off the normal at `theta_m = pi / (2 (N-1)^2)`), so
//!    the mirror peak keeps fine cells, and the BRDF's tail, far from the mirror direction,
//!    gets cells as fine, which the VNDF alone leaves to a few wide ones.
//! 3. `rgb`: the warped domain of each slice's VNDF is sampled on an `N x N` grid; at each node
//!    the forward warp gives a normal `m`, `wo` is `wi` mirrored about it, and the node stores
//!    `f_r(wo, wi) cos(theta_o) 4 sigma(wi) / D(m)` (the `jacobian` flag is 1, so the reader
//!    multiplies by `D / (4 sigma)` again); shape `[1, T, 3, N, N]`. The source is read with
//!    [`Brdf::eval_smooth`]: a table (MERL) gives its interpolant, not its nearest bin, whose
//!    steps bilinear interpolation between nodes could not follow. The interpolants of the
//!    f32 tables themselves give `D` and `sigma` here, so a reader reproduces a node exactly.
//! 4. `luminance`: the Rec. 709 luminance of each node times the VNDF over the mixed density
//!    at its normal (`[1, T, N, N]`), the density Mitsuba samples before the warp, so that
//!    sampling follows `f_r cos(theta_o)` as with the pure VNDF warp; raised to
//!    [`LUMINANCE_FLOOR`] of each slice's peak so that every direction stays reachable.
//! 5. `valid`: one bit per `rgb` node (`[T][row][column]`, most significant bit first, as the
//!    RGL files pack it): 0 where `wo` falls below the horizon (stored 0) or the source has not
//!    measured `f_r` (stored as the nearest measured node of the same slice, in grid steps, or
//!    when the slice has none, the same node of the nearest slice that has).
//! 6. `theta_i` (radians), `phi_i = [0]`, `description`, `jacobian = [1]`, `version = [1, 0]`.
//!
//! The file's incident direction `wi` is the camera's and `wo` the light's, as Mitsuba 3
//! renders the file (the module documentation of [`super`]): each node stores the source's
//! `f_r(wo, wi)` in Specula's order (light from `wo`, seen from `wi`), so that Specula's
//! reader gives the source back and Mitsuba renders the file as Specula renders the source.
//! The source is evaluated with `wi` in the plane `phi_i = 0`; an anisotropic source is thus
//! written as its isotropic slice there.

use super::ndf::RetroNdf;
use super::tensor::{encode, FieldData};
use super::warp::{Grid, VndfWarp};
use glam::{DVec2, DVec3};
use rayon::prelude::*;
use specula_core::brdf::luminance;
use specula_core::Brdf;
use std::f64::consts::PI;
use std::ops::RangeInclusive;
use std::path::{Path, PathBuf};

/// Range of [`RglResolution::elevations`].
pub const ELEVATIONS_RANGE: RangeInclusive<usize> = 2..=90;
/// Range of [`RglResolution::ndf_size`].
pub const NDF_SIZE_RANGE: RangeInclusive<usize> = 8..=512;
/// Nodes per axis of each slice's warp density (`vndf`). The warp is mostly uniform
/// ([`UNIFORM_WARP_SHARE`]), so its own resolution hardly moves the samples: at the default
/// resolution 128 instead of 64 changes no test material's fraction of direction pairs
/// within 5 % by more than 0.1 point, and costs 2.4 MB more (docs/book/src/renderers.md).
pub const WARP_SIZE: usize = 64;
/// Range of [`RglResolution::sample_size`].
pub const SAMPLE_SIZE_RANGE: RangeInclusive<usize> = 4..=256;
/// The last incident elevation, degrees: just above the horizon, as the RGL files (89.99999).
pub const LAST_ELEVATION_DEG: f64 = 89.9;
/// Floor of the `luminance` sampling density, relative to each slice's peak.
pub const LUMINANCE_FLOOR: f64 = 1e-3;
/// Share of each slice's warp density spread evenly over the unit square; the rest follows
/// the VNDF. Chosen by the fraction of direction pairs within 5 % of the source
/// (docs/book/src/renderers.md): at 32 elevations, 128 `ndf` nodes and 96 x 96 samples 0.3
/// gave 95.6 % for the green paint and 73 % for the MERL tabulation of the RGL film
/// `cc_ibiza_sunset_rgb`, 0.9 gives 99.7 % and 86 %.
pub const UNIFORM_WARP_SHARE: f64 = 0.9;

/// The table sizes of a written file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RglResolution {
    /// `T`: incident elevations (slices), evenly spaced in `cos(theta_i)` from the normal to
    /// [`LAST_ELEVATION_DEG`].
    pub elevations: usize,
    /// `n`: nodes (elevations) of the `ndf` and `sigma` tables.
    pub ndf_size: usize,
    /// `N`: nodes per axis of each slice's `rgb` and `luminance` grid.
    pub sample_size: usize,
}

impl RglResolution {
    /// 48 elevations, 512 `ndf` nodes and 104 x 104 samples per elevation (six times the RGL
    /// database's 8 elevations, 3.25 times its 32 x 32 samples), with [`WARP_SIZE`] warp
    /// nodes: about 9.2 MB. The fine sample grid resolves sharp coats over a diffuse base and
    /// the tails of measured files; the elevations, 1.2 deg apart near 80 deg incidence,
    /// resolve the change of a sharp coat's highlight and of a film's colour with incidence,
    /// which a reader interpolates linearly between slices; the `ndf` nodes resolve a sharp
    /// conductor's peak (module documentation). Figures per resolution in
    /// docs/book/src/renderers.md.
    pub const DEFAULT: Self = Self {
        elevations: 48,
        ndf_size: 512,
        sample_size: 104,
    };
}

impl Default for RglResolution {
    /// [`RglResolution::DEFAULT`].
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Why a BRDF cannot be written as an RGL file.
#[derive(Debug, thiserror::Error)]
pub enum RglWriteError {
    /// A requested table size is outside the range the format allows.
    #[error("{what} = {value} is out of range (allowed {min} to {max})")]
    Resolution {
        /// Which table size.
        what: &'static str,
        /// The size requested.
        value: usize,
        /// The smallest size allowed.
        min: usize,
        /// The largest size allowed.
        max: usize,
    },
    /// The retro-reflection is zero or not measured at some elevation, so no microfacet
    /// distribution can be derived from it.
    #[error("{brdf}: the retro-reflection is zero or not measured at every elevation, so no microfacet distribution can be derived from it")]
    NoRetroReflection {
        /// The BRDF's name.
        brdf: String,
    },
    /// No direction pair of the RGL sample grid is measured.
    #[error("{brdf}: no direction pair of the RGL sample grid is measured")]
    NothingMeasured {
        /// The BRDF's name.
        brdf: String,
    },
    /// The file could not be written.
    #[error("{}: cannot write: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
}

/// The tables of an isotropic RGB RGL file, built from a BRDF.
#[derive(Debug, Clone)]
pub struct RglTables {
    resolution: RglResolution,
    description: String,
    theta_i_rad: Vec<f32>,
    ndf: Vec<f32>,
    sigma: Vec<f32>,
    vndf: Vec<f32>,
    rgb: Vec<f32>,
    luminance: Vec<f32>,
    valid: Vec<bool>,
    /// `rgb` nodes whose direction pair the source has not measured.
    pub not_measured: usize,
    /// `rgb` nodes whose outgoing direction lies below the horizon.
    pub below_horizon: usize,
    /// Retro-reflection nodes the source has not measured.
    pub retro_not_measured: usize,
    /// Power iterations the microfacet distribution took.
    pub ndf_iterations: usize,
}

/// One elevation slice's samples, before hole filling: `None` where not measured.
struct Slice {
    rgb: Vec<Option<[f64; 3]>>,
    below_horizon: Vec<bool>,
    /// The VNDF over the warp's mixed density at each node's normal.
    vndf_share: Vec<f64>,
}

impl Slice {
    /// The values with each unmeasured node taken from the nearest measured node above the
    /// horizon (in grid steps); `None` when there is none.
    fn filled(&self, size: usize) -> Option<Vec<[f64; 3]>> {
        let measured: Vec<usize> = (0..self.rgb.len())
            .filter(|i| self.rgb[*i].is_some() && !self.below_horizon[*i])
            .collect();
        if measured.is_empty() {
            return None;
        }
        Some(
            (0..self.rgb.len())
                .map(|i| {
                    self.rgb[i].unwrap_or_else(|| {
                        self.rgb[nearest(&measured, i, size)].expect("a measured node")
                    })
                })
                .collect(),
        )
    }
}

impl RglTables {
    /// Builds every table of the file from `brdf` (module documentation).
    pub fn from_brdf(
        brdf: &dyn Brdf,
        resolution: RglResolution,
        description: &str,
    ) -> Result<Self, RglWriteError> {
        check_resolution(resolution)?;
        let RglResolution {
            elevations: t_count,
            ndf_size: n,
            sample_size: s_count,
        } = resolution;
        let retro = RetroNdf::from_brdf(brdf, n)
            .ok_or_else(|| RglWriteError::NoRetroReflection { brdf: brdf.name() })?;
        let ndf: Vec<f32> = retro.d.iter().map(|v| *v as f32).collect();
        let sigma: Vec<f32> = retro.sigma.iter().map(|v| *v as f32).collect();
        let ndf_grid = azimuth_constant_grid(&ndf);
        let sigma_grid = azimuth_constant_grid(&sigma);
        let theta_i_rad: Vec<f32> = (0..t_count)
            .map(|k| elevation_rad(k, t_count) as f32)
            .collect();

        let visible: Vec<Grid> = theta_i_rad
            .iter()
            .map(|t| vndf_grid(&ndf_grid, *t as f64, WARP_SIZE))
            .collect();
        let vndf_grids: Vec<Grid> = visible
            .iter()
            .map(|g| mixed_with_uniform(g, WARP_SIZE))
            .collect();
        let vndf: Vec<f32> = vndf_grids
            .iter()
            .flat_map(|g| g.values().iter().map(|v| *v as f32).collect::<Vec<_>>())
            .collect();
        // The warp as a reader builds it: from the f32 densities.
        let stored: Vec<Grid> = vndf
            .chunks_exact(WARP_SIZE * WARP_SIZE)
            .map(|c| Grid::new(WARP_SIZE, WARP_SIZE, c.iter().map(|v| *v as f64).collect()))
            .collect();
        let elevations: Vec<f64> = theta_i_rad.iter().map(|t| *t as f64).collect();
        let warp = VndfWarp::new(elevations.clone(), &stored)
            .expect("a VNDF slice of a positive D has positive mass");

        let slices: Vec<Slice> = (0..t_count)
            .into_par_iter()
            .map(|k| {
                sample_slice(
                    brdf,
                    &warp,
                    (&visible[k], &vndf_grids[k]),
                    (&ndf_grid, &sigma_grid),
                    k,
                    elevations[k],
                    s_count,
                )
            })
            .collect();

        let mut tables = Self {
            resolution,
            description: description.into(),
            theta_i_rad,
            ndf,
            sigma,
            vndf,
            rgb: Vec::with_capacity(t_count * 3 * s_count * s_count),
            luminance: Vec::with_capacity(t_count * s_count * s_count),
            valid: Vec::with_capacity(t_count * s_count * s_count),
            not_measured: 0,
            below_horizon: 0,
            retro_not_measured: retro.not_measured,
            ndf_iterations: retro.iterations,
        };
        let filled: Vec<Option<Vec<[f64; 3]>>> =
            slices.iter().map(|slice| slice.filled(s_count)).collect();
        let donors: Vec<usize> = (0..t_count).filter(|k| filled[*k].is_some()).collect();
        if donors.is_empty() {
            return Err(RglWriteError::NothingMeasured { brdf: brdf.name() });
        }
        for (k, slice) in slices.iter().enumerate() {
            let donor = *donors
                .iter()
                .min_by_key(|d| d.abs_diff(k))
                .expect("at least one donor");
            let values = filled[donor].as_ref().expect("a donor is filled");
            tables.push_slice(slice, values);
        }
        Ok(tables)
    }

    /// Adds a slice whose nodes hold `values` (its own, holes filled, or those of the nearest
    /// slice with measured nodes): counts, validity, RGB and luminance.
    fn push_slice(&mut self, slice: &Slice, values: &[[f64; 3]]) {
        let mut stored = Vec::with_capacity(values.len());
        for (i, value) in slice.rgb.iter().enumerate() {
            let below = slice.below_horizon[i];
            self.below_horizon += usize::from(below);
            self.not_measured += usize::from(value.is_none());
            self.valid.push(value.is_some() && !below);
            stored.push(if below { [0.0; 3] } else { values[i] });
        }
        for channel in 0..3 {
            self.rgb.extend(stored.iter().map(|v| v[channel] as f32));
        }
        let lum: Vec<f64> = stored
            .iter()
            .zip(&slice.vndf_share)
            .map(|(v, share)| luminance(DVec3::from_array(*v)).max(0.0) * share)
            .collect();
        let peak = lum.iter().cloned().fold(0.0, f64::max);
        let floor = if peak > 0.0 {
            LUMINANCE_FLOOR * peak
        } else {
            1.0
        };
        self.luminance
            .extend(lum.iter().map(|v| v.max(floor) as f32));
    }

    /// The table sizes.
    pub fn resolution(&self) -> RglResolution {
        self.resolution
    }

    /// The `rgb` nodes written (elevations x samples).
    pub fn nodes(&self) -> usize {
        self.valid.len()
    }

    /// The bytes of the tensor file.
    pub fn to_bytes(&self) -> Vec<u8> {
        let RglResolution {
            elevations: t,
            ndf_size: n,
            sample_size: s,
        } = self.resolution;
        let mut valid = vec![0u8; self.valid.len().div_ceil(8)];
        for (i, ok) in self.valid.iter().enumerate() {
            if *ok {
                valid[i / 8] |= 0x80 >> (i % 8);
            }
        }
        let twice = |v: &[f32]| [v, v].concat();
        encode(&[
            FieldData::u32("version", &[1, 0]),
            FieldData::u8("description", self.description.as_bytes()),
            FieldData::f32("phi_i", &[1], &[0.0]),
            FieldData::f32("theta_i", &[t], &self.theta_i_rad),
            FieldData::f32("sigma", &[2, n], &twice(&self.sigma)),
            FieldData::f32("ndf", &[2, n], &twice(&self.ndf)),
            FieldData::f32("vndf", &[1, t, WARP_SIZE, WARP_SIZE], &self.vndf),
            FieldData::f32("luminance", &[1, t, s, s], &self.luminance),
            FieldData::f32("rgb", &[1, t, 3, s, s], &self.rgb),
            FieldData::u8("valid", &valid),
            FieldData::u8("jacobian", &[1]),
        ])
    }

    /// Writes the tensor file to `path`.
    pub fn write(&self, path: &Path) -> Result<(), RglWriteError> {
        std::fs::write(path, self.to_bytes()).map_err(|source| RglWriteError::Io {
            path: path.to_path_buf(),
            source,
        })
    }
}

fn check_resolution(r: RglResolution) -> Result<(), RglWriteError> {
    for (what, value, range) in [
        ("elevations", r.elevations, ELEVATIONS_RANGE),
        ("ndf size", r.ndf_size, NDF_SIZE_RANGE),
        ("sample size", r.sample_size, SAMPLE_SIZE_RANGE),
    ] {
        if !range.contains(&value) {
            return Err(RglWriteError::Resolution {
                what,
                value,
                min: *range.start(),
                max: *range.end(),
            });
        }
    }
    Ok(())
}

/// Incident elevation `k` of `count`, radians: evenly spaced in `cos(theta_i)` from 1 to
/// `cos(LAST_ELEVATION_DEG)` (the RGL files' elevations are close to that spacing), denser
/// towards grazing where Fresnel and masking change fastest.
fn elevation_rad(k: usize, count: usize) -> f64 {
    let last = LAST_ELEVATION_DEG.to_radians().cos();
    let t = k as f64 / (count - 1) as f64;
    (1.0 + (last - 1.0) * t).acos()
}

/// A `[2, n]` table (two identical azimuth rows) as a grid over `(u(theta), u(phi))`.
fn azimuth_constant_grid(values: &[f32]) -> Grid {
    let row: Vec<f64> = values.iter().map(|v| *v as f64).collect();
    Grid::new(values.len(), 2, [row.clone(), row].concat())
}

/// The unit-square coordinate `u` to an elevation, radians (`theta = u^2 pi / 2`).
fn unit_to_theta(u: f64) -> f64 {
    u * u * PI / 2.0
}

/// The unit-square coordinate `u` to an azimuth relative to `wi`'s, radians.
fn unit_to_phi(u: f64) -> f64 {
    (2.0 * u - 1.0) * PI
}

/// The normal of unit-square coordinates `(u(theta_m), u(phi_m - phi_i))`, with `phi_i = 0`.
fn normal_at(u: DVec2) -> DVec3 {
    let (theta, phi) = (unit_to_theta(u.x), unit_to_phi(u.y));
    DVec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

/// The incident direction at elevation `theta_rad` in the plane `phi_i = 0`.
fn incident(theta_rad: f64) -> DVec3 {
    DVec3::new(theta_rad.sin(), 0.0, theta_rad.cos())
}

/// The VNDF density of one elevation over the `n x n` unit square, including the Jacobian
/// `2 pi^2 u sin(theta_m)` of the square, summing to 1.
fn vndf_grid(ndf: &Grid, theta_i_rad: f64, n: usize) -> Grid {
    let wi = incident(theta_i_rad);
    let step = 1.0 / (n - 1) as f64;
    let mut values: Vec<f64> = (0..n * n)
        .map(|i| {
            let u = DVec2::new((i % n) as f64 * step, (i / n) as f64 * step);
            let m = normal_at(u);
            let jacobian = 2.0 * PI * PI * u.x * unit_to_theta(u.x).sin();
            ndf.eval(u) * wi.dot(m).max(0.0) * jacobian
        })
        .collect();
    let total: f64 = values.iter().sum();
    for v in &mut values {
        *v /= total;
    }
    Grid::new(n, n, values)
}

/// The warp density of an `n x n` VNDF slice: `1 - UNIFORM_WARP_SHARE` of it and the rest
/// uniform, summing to 1.
fn mixed_with_uniform(vndf: &Grid, n: usize) -> Grid {
    let uniform = 1.0 / (n * n) as f64;
    let mixed = vndf
        .values()
        .iter()
        .map(|v| (1.0 - UNIFORM_WARP_SHARE) * v + UNIFORM_WARP_SHARE * uniform)
        .collect();
    Grid::new(n, n, mixed)
}

/// Evaluates the source at every sample node of slice `k`; `(vndf, mixed)` are the slice's
/// VNDF and the warp's density, `(ndf, sigma)` the microfacet distribution and its projected
/// area.
fn sample_slice(
    brdf: &dyn Brdf,
    warp: &VndfWarp,
    (vndf, mixed): (&Grid, &Grid),
    (ndf, sigma): (&Grid, &Grid),
    k: usize,
    theta_i_rad: f64,
    size: usize,
) -> Slice {
    let wi = incident(theta_i_rad);
    let u_wi = DVec2::new((theta_i_rad * 2.0 / PI).sqrt(), 0.5);
    let four_sigma = 4.0 * sigma.eval(u_wi);
    let step = 1.0 / (size - 1) as f64;
    let mut rgb = Vec::with_capacity(size * size);
    let mut below_horizon = Vec::with_capacity(size * size);
    let mut vndf_share = Vec::with_capacity(size * size);
    for i in 0..size * size {
        let s = DVec2::new((i % size) as f64 * step, (i / size) as f64 * step);
        let u_m = warp.sample_slice(k, s);
        vndf_share.push(vndf.eval(u_m) / mixed.eval(u_m));
        let m = normal_at(u_m);
        let wo = 2.0 * wi.dot(m) * m - wi;
        let below = wo.z <= 0.0;
        below_horizon.push(below);
        rgb.push(if below {
            Some([0.0; 3])
        } else {
            brdf.eval_smooth(wo, wi)
                .map(|f| (f * wo.z * four_sigma / ndf.eval(u_m)).to_array())
        });
    }
    Slice {
        rgb,
        below_horizon,
        vndf_share,
    }
}

/// The index of the measured node nearest to node `i` on a `size x size` grid.
fn nearest(measured: &[usize], i: usize, size: usize) -> usize {
    let (x, y) = ((i % size) as i64, (i / size) as i64);
    *measured
        .iter()
        .min_by_key(|j| {
            let (dx, dy) = ((**j % size) as i64 - x, (**j / size) as i64 - y);
            dx * dx + dy * dy
        })
        .expect("at least one measured node")
}
