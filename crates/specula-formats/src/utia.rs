//! The UTIA BRDF database binary (`.bin`): Filip & Vávra, "Template-Based Sampling of
//! Anisotropic BRDFs", Computer Graphics Forum (Pacific Graphics) 2014; http://btf.utia.cas.cz.
//!
//! Layout, checked against three public readers that agree (Filip's `TBDRF.cpp` as adapted
//! in ALTA's `data_utia` plugin, Sztrajman's `brdf_read.py`, Fichet's `utia.py`): no header;
//! `3 x 6 x 48 x 6 x 48` little-endian `f64`, outermost first: channel plane (R, G, B),
//! theta_i, phi_i, theta_v, phi_v. Elevations are `0, 15, ..., 75` degrees and azimuths
//! `0, 7.5, ..., 352.5` degrees, so
//! `index = plane * 82944 + ((ti * 48 + pi) * 6 + tv) * 48 + pv`.
//! Values are RGB BRDF values (linear; the database states sRGB primaries, D65) and are read
//! as f_r in 1/sr. The material may be anisotropic: all four angles are kept.
//!
//! Evaluation is quadrilinear in the four angles (azimuths wrap), as the reference reader.
//! Two documented differences: the reference extrapolates linearly beyond the last measured
//! elevation (75 deg), whereas Specula reports such directions as not measured (`None`); and
//! Specula writes cells it has no measurement for as -1, like MERL, and leaves negative nodes
//! out of the interpolation (renormalising the weights of the others), `None` if all are out.

use crate::input::{file_error, file_stem, io_error, open_input, read_input, Malformed, Result};
use glam::DVec3;
use rayon::prelude::*;
use specula_core::brdf::both_above_surface;
use specula_core::shown::shown;
use specula_core::{Brdf, Rgb, Spherical};
use std::path::Path;

/// Number of elevations (theta_i and theta_v).
pub const THETA_COUNT: usize = 6;
/// Number of azimuths (phi_i and phi_v).
pub const PHI_COUNT: usize = 48;
/// Spacing of the elevations, degrees.
pub const THETA_STEP_DEG: f64 = 15.0;
/// Spacing of the azimuths, degrees.
pub const PHI_STEP_DEG: f64 = 7.5;
/// The last measured elevation, degrees.
pub const THETA_MAX_DEG: f64 = THETA_STEP_DEG * (THETA_COUNT - 1) as f64;
/// Number of nodes of one channel plane.
pub const NODES: usize = THETA_COUNT * PHI_COUNT * THETA_COUNT * PHI_COUNT;
/// Size of a file in bytes.
pub const FILE_BYTES: usize = 3 * NODES * 8;
/// The largest value read, f_r in 1/sr: the bound of a MERL table
/// ([`specula_core::merl::MAX_STORED_VALUE`]) in the units of this format, far above any
/// real node (a mirror's peak on this 7.5 deg grid is tens of 1/sr) and small enough that
/// sums stay finite. A larger value is refused at load.
pub const MAX_VALUE_PER_SR: f64 = 1e10;
/// Value written for a node that was not measured.
pub const NOT_MEASURED: f64 = -1.0;

/// Indices of one node: `(theta_i, phi_i, theta_v, phi_v)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Node {
    /// Index of the incident elevation, `theta_i = 15 deg * theta_i`.
    pub theta_i: usize,
    /// Index of the incident azimuth, `phi_i = 7.5 deg * phi_i`.
    pub phi_i: usize,
    /// Index of the viewing elevation, `theta_v = 15 deg * theta_v`.
    pub theta_v: usize,
    /// Index of the viewing azimuth, `phi_v = 7.5 deg * phi_v`.
    pub phi_v: usize,
}

impl Node {
    /// The flat index within one channel plane.
    pub fn index(self) -> usize {
        ((self.theta_i * PHI_COUNT + self.phi_i) * THETA_COUNT + self.theta_v) * PHI_COUNT
            + self.phi_v
    }

    /// The node of a flat index.
    pub fn from_index(index: usize) -> Self {
        Self {
            phi_v: index % PHI_COUNT,
            theta_v: (index / PHI_COUNT) % THETA_COUNT,
            phi_i: (index / (PHI_COUNT * THETA_COUNT)) % PHI_COUNT,
            theta_i: index / (PHI_COUNT * THETA_COUNT * PHI_COUNT),
        }
    }

    /// The node's angles, degrees: `[theta_i, phi_i, theta_v, phi_v]`.
    pub fn angles_deg(self) -> [f64; 4] {
        [
            self.theta_i as f64 * THETA_STEP_DEG,
            self.phi_i as f64 * PHI_STEP_DEG,
            self.theta_v as f64 * THETA_STEP_DEG,
            self.phi_v as f64 * PHI_STEP_DEG,
        ]
    }

    /// The light and camera directions of this node.
    pub fn directions(self) -> (DVec3, DVec3) {
        let [theta_i, phi_i, theta_v, phi_v] = self.angles_deg();
        (
            Spherical::from_degrees(theta_i, phi_i).to_vector(),
            Spherical::from_degrees(theta_v, phi_v).to_vector(),
        )
    }
}

/// A UTIA BRDF table: the file's values, plane by plane.
#[derive(Clone)]
pub struct UtiaBrdf {
    name: String,
    values: Vec<f64>,
}

impl std::fmt::Debug for UtiaBrdf {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("UtiaBrdf")
            .field("name", &self.name)
            .field("measured", &self.measured_count())
            .finish()
    }
}

impl UtiaBrdf {
    /// A table with every node "not measured".
    pub fn empty(name: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            values: vec![NOT_MEASURED; 3 * NODES],
        }
    }

    /// Reads a `.bin` file; the error names the file and the problem. A file longer than a
    /// table is refused by its size, before it is read.
    pub fn read(path: &Path) -> Result<Self> {
        let size = open_input(path)?
            .metadata()
            .map_err(|cause| io_error(path, "read", cause))?
            .len();
        if size > FILE_BYTES as u64 {
            return Err(file_error(path, length_problem(size, &[])));
        }
        let bytes = read_input(path)?;
        Self::from_bytes(file_stem(path), &bytes).map_err(|problem| file_error(path, problem))
    }

    /// Parses the bytes of a `.bin` file; the error says what is wrong. Every value must be
    /// finite and at most [`MAX_VALUE_PER_SR`] (a negative one marks its node not measured),
    /// and at least one node measured.
    pub fn from_bytes(name: impl Into<String>, bytes: &[u8]) -> Result<Self, Malformed> {
        if bytes.len() != FILE_BYTES {
            return Err(length_problem(bytes.len() as u64, bytes));
        }
        let values: Vec<f64> = bytes
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
            .collect();
        let plausible = |v: &f64| v.is_finite() && *v <= MAX_VALUE_PER_SR;
        if let Some(pos) = values.iter().position(|v| !plausible(v)) {
            let node = Node::from_index(pos % NODES);
            let [theta_i, phi_i, theta_v, phi_v] = node.angles_deg();
            let value = values[pos];
            let what = if value.is_finite() {
                format!(
                    "value {} above {MAX_VALUE_PER_SR:e} 1/sr, the most a UTIA table may hold,",
                    shown(value)
                )
            } else {
                format!("non-finite value {value}")
            };
            return Err(format!(
                "{what} in the {} channel at theta_i {theta_i} phi_i {phi_i} theta_v {theta_v} phi_v {phi_v} deg",
                ["red", "green", "blue"][pos / NODES],
            )
            .into());
        }
        let table = Self {
            name: name.into(),
            values,
        };
        if table.measured_count() == 0 {
            return Err(
                "no measured node: every node holds a negative value, \"not measured\"".into(),
            );
        }
        Ok(table)
    }
}

/// What is wrong with a file of `len` bytes (not [`FILE_BYTES`]) starting with `start`.
fn length_problem(len: u64, start: &[u8]) -> Malformed {
    let kind = if len < FILE_BYTES as u64 {
        "truncated"
    } else {
        "over-long"
    };
    let looks_like = if start.starts_with(crate::rgl::MAGIC) {
        " (it starts like an RGL .bsdf tensor file)"
    } else if start.len() >= 12 && start[..12] == merl_header() {
        " (it starts with a MERL .binary header)"
    } else {
        ""
    };
    format!("{kind}: {len} bytes, a UTIA BRDF file has {FILE_BYTES} (3 x 6 x 48 x 6 x 48 f64){looks_like}")
        .into()
}

impl UtiaBrdf {
    /// The bytes of the `.bin` file.
    pub fn to_bytes(&self) -> Vec<u8> {
        self.values.iter().flat_map(|v| v.to_le_bytes()).collect()
    }

    /// Writes the `.bin` file.
    pub fn write(&self, path: &Path) -> Result<()> {
        specula_core::atomic_file::write_bytes(path, &self.to_bytes())
            .map_err(|cause| io_error(path, "write", cause))
    }

    /// f_r of a node, or `None` when it was not measured (a negative channel).
    pub fn node(&self, index: usize) -> Option<Rgb> {
        let v = Rgb::new(
            self.values[index],
            self.values[index + NODES],
            self.values[index + 2 * NODES],
        );
        (v.min_element() >= 0.0).then_some(v)
    }

    /// Sets a node to f_r in 1/sr, or marks it not measured with `None` (also for negative
    /// or non-finite values).
    pub fn set_node(&mut self, index: usize, value: Option<Rgb>) {
        let value = value.filter(|v| v.is_finite() && v.min_element() >= 0.0);
        for c in 0..3 {
            self.values[index + c * NODES] = value.map_or(NOT_MEASURED, |v| v[c]);
        }
    }

    /// Number of measured nodes.
    pub fn measured_count(&self) -> usize {
        (0..NODES).filter(|i| self.node(*i).is_some()).count()
    }

    /// Evaluates `brdf` at every node, in parallel; nodes it reports as not measured stay so.
    pub fn tabulate(brdf: &dyn Brdf) -> Self {
        let values: Vec<Option<Rgb>> = (0..NODES)
            .into_par_iter()
            .map(|i| {
                let (wi, wo) = Node::from_index(i).directions();
                brdf.eval(wi, wo)
            })
            .collect();
        let mut table = Self::empty(brdf.name());
        for (i, v) in values.into_iter().enumerate() {
            table.set_node(i, v);
        }
        table
    }

    /// Quadrilinear interpolation at angles in degrees (elevations in `[0, 75]`).
    pub fn lookup_deg(&self, theta_i: f64, phi_i: f64, theta_v: f64, phi_v: f64) -> Option<Rgb> {
        let axes = [
            theta_axis(theta_i),
            phi_axis(phi_i),
            theta_axis(theta_v),
            phi_axis(phi_v),
        ];
        let mut sum = Rgb::ZERO;
        let mut weight_sum = 0.0;
        for corner in 0..16 {
            let pick = |axis: usize| axes[axis][(corner >> axis) & 1];
            let (ti, pi, tv, pv) = (pick(0), pick(1), pick(2), pick(3));
            let weight = ti.1 * pi.1 * tv.1 * pv.1;
            if weight == 0.0 {
                continue;
            }
            let node = Node {
                theta_i: ti.0,
                phi_i: pi.0,
                theta_v: tv.0,
                phi_v: pv.0,
            };
            if let Some(v) = self.node(node.index()) {
                sum += v * weight;
                weight_sum += weight;
            }
        }
        (weight_sum > 0.0).then(|| sum / weight_sum)
    }

    /// Renames the BRDF (the name reports and messages show).
    pub fn set_name(&mut self, name: impl Into<String>) {
        self.name = name.into();
    }
}

/// The two elevation nodes around `theta_deg` (in `[0, 75]`) and their weights.
fn theta_axis(theta_deg: f64) -> [(usize, f64); 2] {
    let t = (theta_deg / THETA_STEP_DEG).clamp(0.0, (THETA_COUNT - 1) as f64);
    let low = (t.floor() as usize).min(THETA_COUNT - 2);
    let w = t - low as f64;
    [(low, 1.0 - w), (low + 1, w)]
}

/// The two azimuth nodes around `phi_deg` (wrapping at 360) and their weights.
fn phi_axis(phi_deg: f64) -> [(usize, f64); 2] {
    let p = phi_deg.rem_euclid(360.0) / PHI_STEP_DEG;
    let low = (p.floor() as usize).min(PHI_COUNT - 1);
    let w = (p - low as f64).clamp(0.0, 1.0);
    [(low, 1.0 - w), ((low + 1) % PHI_COUNT, w)]
}

/// The 12-byte header of a MERL `.binary` file, to recognise one given as UTIA.
fn merl_header() -> [u8; 12] {
    let mut h = [0u8; 12];
    for (i, d) in [90i32, 90, 180].iter().enumerate() {
        h[4 * i..4 * i + 4].copy_from_slice(&d.to_le_bytes());
    }
    h
}

impl Brdf for UtiaBrdf {
    /// Quadrilinear interpolation; `None` beyond the last measured elevation (75 deg).
    fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
        if !both_above_surface(wi, wo) {
            return Some(Rgb::ZERO);
        }
        let (i, o) = (Spherical::from_vector(wi), Spherical::from_vector(wo));
        let (theta_i, theta_v) = (i.theta_rad.to_degrees(), o.theta_rad.to_degrees());
        if theta_i > THETA_MAX_DEG + 1e-9 || theta_v > THETA_MAX_DEG + 1e-9 {
            return None;
        }
        self.lookup_deg(
            theta_i,
            i.phi_rad.to_degrees(),
            theta_v,
            o.phi_rad.to_degrees(),
        )
    }

    fn name(&self) -> String {
        self.name.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_index_follows_the_reference_layout() {
        // Reference: idx = nc * (npi * iti + ipi) + npv * itv + ipv, nc = npv * ntv.
        let node = Node {
            theta_i: 2,
            phi_i: 17,
            theta_v: 5,
            phi_v: 40,
        };
        assert_eq!(node.index(), 48 * 6 * (48 * 2 + 17) + 48 * 5 + 40);
        for index in [0, 1, 47, 48, 12_345, NODES - 1] {
            assert_eq!(Node::from_index(index).index(), index);
        }
        assert_eq!(node.angles_deg(), [30.0, 127.5, 75.0, 300.0]);
        let (wi, wo) = node.directions();
        let (si, so) = (Spherical::from_vector(wi), Spherical::from_vector(wo));
        assert!((si.theta_rad.to_degrees() - 30.0).abs() < 1e-9);
        assert!((si.phi_rad.to_degrees() - 127.5).abs() < 1e-9);
        assert!((so.theta_rad.to_degrees() - 75.0).abs() < 1e-9);
        assert!((so.phi_rad.to_degrees() - 300.0).abs() < 1e-9);
    }

    #[test]
    fn axes_interpolate_and_wrap() {
        assert_eq!(theta_axis(0.0), [(0, 1.0), (1, 0.0)]);
        assert_eq!(theta_axis(75.0), [(4, 0.0), (5, 1.0)]);
        assert_eq!(theta_axis(22.5), [(1, 0.5), (2, 0.5)]);
        assert_eq!(phi_axis(356.25), [(47, 0.5), (0, 0.5)]);
        assert_eq!(phi_axis(-3.75), [(47, 0.5), (0, 0.5)]);
    }
}
