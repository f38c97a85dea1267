//! The MERL `.binary` BRDF table (Matusik et al. 2003), the field's exchange format.
//!
//! Layout (docs/book/src/design.md): little-endian; a header of three `i32` (90, 90, 180: theta_h,
//! theta_d and phi_d bins), then three planes (R, G, B) of 1,458,000 `f64`, cell index
//! `phi_d_i + 180 * theta_d_i + 180 * 90 * theta_h_i`. The BRDF in 1/sr is the stored value
//! times a per-channel scale; a negative stored value means "not measured".
//!
//! Bins: `theta_h_i = floor(sqrt(theta_h_deg * 90))`, `theta_d_i = floor(theta_d_deg)`,
//! `phi_d_i = floor(phi_d_deg)` with phi_d folded into `[0, 180)` (reciprocity), each clamped
//! ([`Bin::of_degrees`], the one home of these rules).
//! Bin centres are taken in index space: `theta_h = (i + 0.5)^2 / 90` deg,
//! `theta_d = j + 0.5` deg, `phi_d = k + 0.5` deg.

use crate::brdf::{both_above_surface, Brdf, Rgb};
use crate::geometry::HalfDiff;
use glam::DVec3;
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// Number of theta_h bins.
pub const THETA_H_BINS: usize = 90;
/// Number of theta_d bins.
pub const THETA_D_BINS: usize = 90;
/// Number of phi_d bins (phi_d in `[0, 180)` degrees).
pub const PHI_D_BINS: usize = 180;
/// Number of cells of one channel.
pub const CELLS: usize = THETA_H_BINS * THETA_D_BINS * PHI_D_BINS;
/// Stored value times this gives f_r in 1/sr, per channel (R, G, B).
pub const CHANNEL_SCALE: [f64; 3] = [1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0];
/// Value written for a cell that was not measured.
pub const NOT_MEASURED: f64 = -1.0;

/// The largest stored value read (f_r up to 6.7e9 1/sr in the red channel, 5.8e9 in green,
/// 4e9 in blue): a thousand times the largest cell of a perfect mirror's table (electroplated
/// chrome tabulates to 6e6 1/sr in the smallest theta_h bin), and small enough that sums
/// over a whole table stay far from overflowing. A larger value is refused at load.
pub const MAX_STORED_VALUE: f64 = 1e13;

/// Bytes of the header: three `i32` dimensions.
pub const HEADER_BYTES: usize = 12;
/// Bytes of a whole file: the header and three planes of `f64`.
pub const FILE_BYTES: usize = HEADER_BYTES + 3 * CELLS * 8;

/// What is wrong with a MERL file; shown after the file's path.
#[derive(Debug, thiserror::Error)]
pub enum MerlError {
    /// The file cannot be read or written.
    #[error("{path}: cannot {action}: {}", crate::shown::io_cause(cause))]
    Io {
        /// The file.
        path: PathBuf,
        /// `read` or `write`.
        action: &'static str,
        /// Not `source`: the message already holds it, and error chains would print it twice.
        cause: std::io::Error,
    },
    /// The file's content is not a MERL table.
    #[error("{path}: {problem}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        problem: MerlProblem,
    },
}

impl MerlError {
    fn invalid(path: &Path, problem: MerlProblem) -> Self {
        MerlError::Invalid {
            path: path.to_path_buf(),
            problem,
        }
    }
}

/// What is wrong with the content of a MERL `.binary` file, for the caller to put after the
/// file's name.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MerlProblem {
    /// The path names a directory.
    #[error("is a directory, not a MERL .binary file")]
    Directory,
    /// Fewer bytes than the 12-byte header.
    #[error("too short for a MERL header ({total_len} bytes, need {HEADER_BYTES})")]
    TooShort {
        /// The file's length, bytes.
        total_len: u64,
    },
    /// The header's dimensions are not the MERL grid's 90 x 90 x 180.
    #[error(
        "not a MERL file: its header gives dimensions {} x {} x {} where a MERL table has 90 x 90 x 180 (theta_h, theta_d, phi_d)",
        dims[0],
        dims[1],
        dims[2]
    )]
    Dimensions {
        /// The dimensions the header holds (theta_h, theta_d, phi_d).
        dims: [i32; 3],
    },
    /// The payload is shorter than the grid's three planes.
    #[error("truncated payload: {total_len} bytes, expected {FILE_BYTES}")]
    Truncated {
        /// The file's length, bytes.
        total_len: u64,
    },
    /// The payload is longer than the grid's three planes.
    #[error("over-long payload: {total_len} bytes, expected {FILE_BYTES}")]
    OverLong {
        /// The file's length, bytes.
        total_len: u64,
    },
    /// A stored value is NaN or infinite.
    #[error(
        "non-finite value {value} in the {channel} channel at cell (theta_h {}, theta_d {}, phi_d {})",
        cell.theta_h_i,
        cell.theta_d_i,
        cell.phi_d_i
    )]
    NonFinite {
        /// The value as stored.
        value: f64,
        /// "red", "green" or "blue".
        channel: &'static str,
        /// The cell holding it.
        cell: Bin,
    },
    /// A stored value above [`MAX_STORED_VALUE`].
    #[error(
        "value {} in the {channel} channel at cell (theta_h {}, theta_d {}, phi_d {}) is above {MAX_STORED_VALUE:e}, the most a MERL table may hold",
        crate::shown::shown(*value),
        cell.theta_h_i,
        cell.theta_d_i,
        cell.phi_d_i
    )]
    TooLarge {
        /// The value as stored.
        value: f64,
        /// "red", "green" or "blue".
        channel: &'static str,
        /// The cell holding it.
        cell: Bin,
    },
    /// Every cell holds a negative value, the format's "not measured".
    #[error("no measured cell: every cell holds a negative value, the format's \"not measured\"")]
    NothingMeasured,
}

/// Cell coordinates `(theta_h_i, theta_d_i, phi_d_i)` of the MERL grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Bin {
    /// theta_h bin, `0..90`, square-root spaced (`theta_h = (i + 0.5)^2 / 90` deg).
    pub theta_h_i: usize,
    /// theta_d bin, `0..90`, 1 deg wide.
    pub theta_d_i: usize,
    /// phi_d bin, `0..180`, 1 deg wide (reciprocity folds phi_d into `[0, 180)`).
    pub phi_d_i: usize,
}

impl Bin {
    /// The flat cell index within one channel plane.
    pub fn index(self) -> usize {
        self.phi_d_i + PHI_D_BINS * self.theta_d_i + PHI_D_BINS * THETA_D_BINS * self.theta_h_i
    }

    /// The bin of a flat cell index.
    pub fn from_index(index: usize) -> Self {
        Self {
            theta_h_i: index / (PHI_D_BINS * THETA_D_BINS),
            theta_d_i: (index / PHI_D_BINS) % THETA_D_BINS,
            phi_d_i: index % PHI_D_BINS,
        }
    }

    /// The nearest bin of half-difference angles, exactly as MERL's reference reader.
    ///
    /// The arithmetic is the reference reader's own (`angle / (pi/2) * 90`, not a conversion
    /// to degrees), so that angles of whole degrees such as 15 land in bin 15 and not 14; the
    /// boundary rules are [`Bin::of_degrees`]'s.
    pub fn of(hd: HalfDiff) -> Self {
        let [theta_h_deg, theta_d_deg, phi_d_deg] = reader_degrees(hd);
        Self::of_degrees(theta_h_deg, theta_d_deg, phi_d_deg)
    }

    /// The bin of `hd`'s mirror image across the plane of incidence (phi_d to 180 - phi_d,
    /// the configuration an isotropic material shares with it), with [`Bin::of`]'s
    /// arithmetic: a configuration on a bin boundary mirrors onto a boundary (45 deg onto
    /// 135, which starts bin 135).
    pub fn of_mirror(hd: HalfDiff) -> Self {
        let [theta_h_deg, theta_d_deg, phi_d_deg] = reader_degrees(hd);
        Self::of_degrees(theta_h_deg, theta_d_deg, 180.0 - phi_d_deg)
    }

    /// The bin of half-difference angles in degrees, by the rules of MERL's reference reader:
    /// - theta_h: square-root spaced, `floor(sqrt(theta_h / 90) * 90)` (the index coordinate
    ///   of [`theta_h_coordinate`]);
    /// - theta_d: `floor(theta_d)`;
    /// - phi_d: folded into `[0, 180)` first (reciprocity: phi_d and phi_d + 180 are the same
    ///   configuration, so -10 is 170 and a value that rounds to 180 is 0), then `floor`;
    ///
    /// each index clamped to its axis (below 0 or NaN gives bin 0, beyond the last bin the
    /// last bin). A value on a boundary belongs to the bin above it.
    pub fn of_degrees(theta_h_deg: f64, theta_d_deg: f64, phi_d_deg: f64) -> Self {
        let phi_d_folded_deg = phi_d_deg.rem_euclid(180.0).rem_euclid(180.0);
        Self {
            theta_h_i: clamp_bin(theta_h_coordinate(theta_h_deg), THETA_H_BINS),
            theta_d_i: clamp_bin(theta_d_deg, THETA_D_BINS),
            phi_d_i: clamp_bin(phi_d_folded_deg, PHI_D_BINS),
        }
    }

    /// The centre of this bin in index space, radians, at the given phi_h.
    pub fn centre(self, phi_h: f64) -> HalfDiff {
        let [theta_h_deg, theta_d_deg, phi_d_deg] = self.centre_deg();
        HalfDiff::from_degrees(theta_h_deg, phi_h.to_degrees(), theta_d_deg, phi_d_deg)
    }

    /// The centre of this bin, degrees: `[theta_h, theta_d, phi_d]` =
    /// `[(i + 0.5)^2 / 90, j + 0.5, k + 0.5]`.
    pub fn centre_deg(self) -> [f64; 3] {
        [
            theta_h_centre_deg(self.theta_h_i),
            self.theta_d_i as f64 + 0.5,
            self.phi_d_i as f64 + 0.5,
        ]
    }
}

/// A row of the MERL grid: the [`PHI_D_BINS`] cells of one (theta_h, theta_d) bin pair,
/// contiguous in a plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Row {
    /// theta_h bin, `0..90`.
    pub theta_h_i: usize,
    /// theta_d bin, `0..90`.
    pub theta_d_i: usize,
}

impl Row {
    /// The `index`-th row in file order.
    pub fn from_index(index: usize) -> Self {
        Self {
            theta_h_i: index / THETA_D_BINS,
            theta_d_i: index % THETA_D_BINS,
        }
    }

    /// The row's cell in phi_d bin `phi_d_i`.
    pub fn bin(self, phi_d_i: usize) -> Bin {
        Bin {
            theta_h_i: self.theta_h_i,
            theta_d_i: self.theta_d_i,
            phi_d_i,
        }
    }

    /// The flat index of the row's cell with phi_d bin 0.
    pub fn first_cell(self) -> usize {
        self.bin(0).index()
    }
}

/// Centres of the phi_d bins in radians, `k + 0.5` degrees.
pub fn phi_d_centres_rad() -> [f64; PHI_D_BINS] {
    std::array::from_fn(|k| (k as f64 + 0.5).to_radians())
}

/// The three stored values of f_r in 1/sr: divided by the channel scales, or all
/// [`NOT_MEASURED`] for `None`, a negative or a non-finite value.
fn stored_values(value: Option<Rgb>) -> [f64; 3] {
    match value.filter(|v| v.is_finite() && v.min_element() >= 0.0) {
        Some(v) => std::array::from_fn(|c| v[c] / CHANNEL_SCALE[c]),
        None => [NOT_MEASURED; 3],
    }
}

/// f_r in 1/sr of a cell's three stored values; `None` when any is negative (not measured).
fn value_of_stored(stored: [f64; 3]) -> Option<Rgb> {
    (stored.iter().all(|&s| s >= 0.0)).then(|| {
        Rgb::new(
            stored[0] * CHANNEL_SCALE[0],
            stored[1] * CHANNEL_SCALE[1],
            stored[2] * CHANNEL_SCALE[2],
        )
    })
}

/// What a table's cell set to `value` reads back ([`MerlBrdf::cell`]): f_r through the
/// stored values' scale, `None` for what a table stores as not measured. For values worked
/// out cell by cell that must equal a table's bit for bit.
pub fn stored_round_trip(value: Option<Rgb>) -> Option<Rgb> {
    value_of_stored(stored_values(value))
}

/// The half-difference angles in degrees as MERL's reference reader computes them from
/// radians (`angle / (pi/2) * 90`, phi_d folded into `[0, 180]` first): `[theta_h, theta_d,
/// phi_d]`.
fn reader_degrees(hd: HalfDiff) -> [f64; 3] {
    use std::f64::consts::{FRAC_PI_2, PI};
    [
        hd.theta_h / FRAC_PI_2 * THETA_H_BINS as f64,
        hd.theta_d / FRAC_PI_2 * THETA_D_BINS as f64,
        hd.phi_d.rem_euclid(PI) / PI * PHI_D_BINS as f64,
    ]
}

/// Nodes in MERL's square-root theta_h coordinate of [`MerlBrdf::directional_albedo`].
pub const ALBEDO_THETA_H_NODES: usize = 256;

/// Nodes in phi_h of [`MerlBrdf::directional_albedo`].
pub const ALBEDO_PHI_H_NODES: usize = 256;

/// Centre of theta_h bin `i` in degrees: `(i + 0.5)^2 / 90`.
pub fn theta_h_centre_deg(i: usize) -> f64 {
    theta_h_deg_at(i as f64 + 0.5)
}

/// MERL's theta_h index coordinate of theta_h in degrees, `sqrt(theta_h / 90) * 90` =
/// `sqrt(90 theta_h)`, in `[0, 90]`: bin `i` covers coordinates `[i, i + 1)`. theta_h is
/// clamped to `[0, 90]` first, NaN counting as 0.
pub fn theta_h_coordinate(theta_h_deg: f64) -> f64 {
    let theta_h_deg = if theta_h_deg.is_nan() {
        0.0
    } else {
        theta_h_deg.clamp(0.0, 90.0)
    };
    (theta_h_deg * THETA_H_BINS as f64).sqrt()
}

/// theta_h in degrees at MERL's theta_h index coordinate, the inverse of
/// [`theta_h_coordinate`]: `coordinate^2 / 90`.
pub fn theta_h_deg_at(coordinate: f64) -> f64 {
    coordinate * coordinate / THETA_H_BINS as f64
}

/// `cos theta_i cos theta_o` of a configuration of half-difference angles (radians):
/// `cos^2 theta_h cos^2 theta_d - sin^2 theta_h sin^2 theta_d cos^2 phi_d`, the projection
/// factor every flux integral weights f_r by; at most 0 when a direction is below the
/// horizon.
fn cos_theta_i_cos_theta_o(theta_h: f64, theta_d: f64, phi_d: f64) -> f64 {
    let (sin_h, cos_h) = theta_h.sin_cos();
    let (sin_d, cos_d) = theta_d.sin_cos();
    let cos_p = phi_d.cos();
    (cos_h * cos_d).powi(2) - (sin_h * sin_d * cos_p).powi(2)
}

/// The two bins whose centres (at `i + 0.5`) bracket `coordinate` and their linear
/// weights; beyond the first or last centre, that bin alone.
fn clamped_neighbours(coordinate: f64, bins: usize) -> [(usize, f64); 2] {
    let x = if coordinate.is_nan() {
        0.0
    } else {
        (coordinate - 0.5).clamp(0.0, (bins - 1) as f64)
    };
    let lower = (x.floor() as usize).min(bins - 2);
    let t = x - lower as f64;
    [(lower, 1.0 - t), (lower + 1, t)]
}

/// The two bins whose centres bracket `coordinate` on a periodic axis of `bins` unit bins,
/// and their linear weights.
fn periodic_neighbours(coordinate: f64, bins: usize) -> [(usize, f64); 2] {
    let x = if coordinate.is_nan() {
        0.0
    } else {
        (coordinate - 0.5).rem_euclid(bins as f64)
    };
    let lower = (x.floor() as usize).min(bins - 1);
    let t = x - lower as f64;
    [(lower, 1.0 - t), ((lower + 1) % bins, t)]
}

fn clamp_bin(value: f64, bins: usize) -> usize {
    if value.is_nan() || value <= 0.0 {
        0
    } else {
        (value.floor() as usize).min(bins - 1)
    }
}

/// A MERL table held as the stored (unscaled) values of the file, so that reading and
/// writing is byte-exact. A cell is measured when none of its three stored values is
/// negative (the file's own convention), so the planes are the mask: a cell that is not
/// measured reads as `None`, never as a silent 0.
#[derive(Clone)]
pub struct MerlBrdf {
    name: String,
    /// Three planes (R, G, B) of `CELLS` stored values each, as in the file.
    stored: Vec<f64>,
}

impl MerlBrdf {
    /// A table with every cell "not measured".
    pub fn empty(name: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            stored: vec![NOT_MEASURED; 3 * CELLS],
        }
    }

    /// A table whose cell `i` holds `value(i)` (f_r in 1/sr, or `None` for not measured),
    /// evaluated in parallel straight into the stored planes.
    pub fn from_fn(name: impl Into<String>, value: impl Fn(usize) -> Option<Rgb> + Sync) -> Self {
        Self::from_rows(name, |row, out| {
            let first = row.first_cell();
            for (offset, out) in out.iter_mut().enumerate() {
                *out = value(first + offset);
            }
        })
    }

    /// A table filled row by row, in parallel: `fill_row(row, out)` writes f_r in 1/sr (or
    /// `None` for not measured) of the row's [`PHI_D_BINS`] cells, in phi_d order.
    pub fn from_rows(
        name: impl Into<String>,
        fill_row: impl Fn(Row, &mut [Option<Rgb>]) + Sync,
    ) -> Self {
        let mut table = Self::unfilled(name.into());
        let (red, rest) = table.stored.split_at_mut(CELLS);
        let (green, blue) = rest.split_at_mut(CELLS);
        red.par_chunks_mut(PHI_D_BINS)
            .zip(green.par_chunks_mut(PHI_D_BINS))
            .zip(blue.par_chunks_mut(PHI_D_BINS))
            .enumerate()
            .with_min_len(THETA_D_BINS)
            .for_each_init(
                || [None; PHI_D_BINS],
                |values, (row, ((red, green), blue))| {
                    fill_row(Row::from_index(row), values);
                    for (cell, value) in values.iter().enumerate() {
                        [red[cell], green[cell], blue[cell]] = stored_values(*value);
                    }
                },
            );
        table
    }

    /// Reads a `.binary` file, checking its header, its length and every value: each finite
    /// and at most [`MAX_STORED_VALUE`] (a negative value marks its cell "not measured",
    /// the format's convention), and at least one cell measured.
    ///
    /// The payload is read straight into the `f64` planes (no intermediate byte buffer) in
    /// parallel units, each checked while it is still in the cache, so reading costs about
    /// what `numpy.fromfile` does without any check (docs/book/src/performance.md).
    pub fn read(path: &Path) -> Result<Self, MerlError> {
        if path.is_dir() {
            return Err(MerlError::invalid(path, MerlProblem::Directory));
        }
        let io_error = |cause| MerlError::Io {
            path: path.to_path_buf(),
            action: "read",
            cause,
        };
        let mut file = std::fs::File::open(path).map_err(io_error)?;
        let length = file.metadata().map_err(io_error)?.len();
        let mut header = [0u8; HEADER_BYTES];
        let header_len = read_up_to(&mut file, &mut header).map_err(io_error)?;
        check_header(&header[..header_len], length)
            .map_err(|problem| MerlError::invalid(path, problem))?;
        let mut table = Self::unfilled(file_stem(path));
        let plausible = table.read_planes(&file).map_err(io_error)?;
        table
            .check_values(plausible)
            .map_err(|problem| MerlError::invalid(path, problem))?;
        Ok(table)
    }

    /// Parses the bytes of a `.binary` file; the error says what is wrong.
    pub fn from_bytes(name: impl Into<String>, bytes: &[u8]) -> Result<Self, MerlProblem> {
        check_header(&bytes[..bytes.len().min(HEADER_BYTES)], bytes.len() as u64)?;
        let mut table = Self::unfilled(name.into());
        table
            .stored
            .iter_mut()
            .zip(bytes[HEADER_BYTES..].chunks_exact(8))
            .for_each(|(v, c)| {
                *v = f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]])
            });
        table.check_values(all_plausible(&table.stored))?;
        Ok(table)
    }

    /// A table of zeros that is about to be overwritten: the planes come from the allocator
    /// zeroed and untouched, backed by huge pages where the system offers them.
    fn unfilled(name: String) -> Self {
        Self {
            name,
            stored: allocate_planes(),
        }
    }

    /// Fills the planes from the payload of `file` (header already checked) in parallel
    /// units of [`READ_UNIT_VALUES`], each checked right after its positioned read, while it
    /// is in the cache. Returns whether every value is finite.
    fn read_planes(&mut self, file: &std::fs::File) -> std::io::Result<bool> {
        self.stored
            .par_chunks_mut(READ_UNIT_VALUES)
            .enumerate()
            .map(|(unit, values)| {
                let offset = HEADER_BYTES + 8 * unit * READ_UNIT_VALUES;
                read_exact_at(file, bytemuck::cast_slice_mut(values), offset as u64)?;
                if cfg!(target_endian = "big") {
                    values
                        .iter_mut()
                        .for_each(|v| *v = f64::from_bits(v.to_bits().swap_bytes()));
                }
                Ok(all_plausible(values))
            })
            .try_reduce(|| true, |a, b| Ok(a && b))
    }

    /// The one check of a table read from a file: `plausible` (every value finite and at
    /// most [`MAX_STORED_VALUE`], as [`all_plausible`] found) or the first value that is not,
    /// and at least one measured cell.
    fn check_values(&self, plausible: bool) -> Result<(), MerlProblem> {
        if !plausible {
            let pos = self
                .stored
                .iter()
                .position(|v| !is_plausible(*v))
                .unwrap_or_default();
            let (value, channel, cell) = (
                self.stored[pos],
                ["red", "green", "blue"][pos / CELLS],
                Bin::from_index(pos % CELLS),
            );
            return Err(if value.is_finite() {
                MerlProblem::TooLarge {
                    value,
                    channel,
                    cell,
                }
            } else {
                MerlProblem::NonFinite {
                    value,
                    channel,
                    cell,
                }
            });
        }
        if !(0..CELLS).into_par_iter().any(|i| self.is_measured(i)) {
            return Err(MerlProblem::NothingMeasured);
        }
        Ok(())
    }

    /// The bytes of the `.binary` file; cells not measured are written as -1.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(FILE_BYTES);
        for d in [THETA_H_BINS, THETA_D_BINS, PHI_D_BINS] {
            out.extend_from_slice(&(d as i32).to_le_bytes());
        }
        let measured: Vec<bool> = (0..CELLS).map(|i| self.is_measured(i)).collect();
        for plane in self.stored.chunks_exact(CELLS) {
            for (v, measured) in plane.iter().zip(&measured) {
                let value = if *measured { *v } else { v.min(NOT_MEASURED) };
                out.extend_from_slice(&value.to_le_bytes());
            }
        }
        out
    }

    /// Writes the `.binary` file, atomically ([`crate::atomic_file`]).
    pub fn write(&self, path: &Path) -> Result<(), MerlError> {
        crate::atomic_file::write_bytes(path, &self.to_bytes()).map_err(|cause| MerlError::Io {
            path: path.to_path_buf(),
            action: "write",
            cause,
        })
    }

    /// The cell with the largest mean of R, G and B among the measured cells that
    /// `include` (given a cell index) keeps, and its value.
    pub fn peak(&self, include: impl Fn(usize) -> bool) -> Option<(usize, Rgb)> {
        let mut peak: Option<(usize, Rgb)> = None;
        for index in (0..CELLS).filter(|&i| include(i)) {
            if let Some(v) = self.cell(index) {
                if peak.is_none_or(|(_, p)| v.element_sum() > p.element_sum()) {
                    peak = Some((index, v));
                }
            }
        }
        peak
    }

    /// f_r in 1/sr of a cell, or `None` when it was not measured.
    pub fn cell(&self, index: usize) -> Option<Rgb> {
        value_of_stored(std::array::from_fn(|c| self.stored[index + c * CELLS]))
    }

    /// Sets a cell to f_r in 1/sr, or marks it not measured with `None`.
    /// Negative or non-finite values are stored as "not measured".
    pub fn set_cell(&mut self, index: usize, value: Option<Rgb>) {
        for (c, stored) in stored_values(value).into_iter().enumerate() {
            self.stored[index + c * CELLS] = stored;
        }
    }

    /// Whether cell `index` was measured: none of its three stored values is negative.
    pub fn is_measured(&self, index: usize) -> bool {
        (0..3).all(|c| self.stored[index + c * CELLS] >= 0.0)
    }

    /// Number of measured cells.
    pub fn measured_count(&self) -> usize {
        (0..CELLS)
            .into_par_iter()
            .filter(|&i| self.is_measured(i))
            .count()
    }

    /// The nearest-bin lookup at half-difference angles.
    pub fn lookup(&self, hd: HalfDiff) -> Option<Rgb> {
        self.cell(Bin::of(hd).index())
    }

    /// f_r at half-difference angles interpolated between cell centres, for integrals and
    /// readings between a table's samples (where [`MerlBrdf::lookup`]'s nearest bin is off by
    /// up to a sixth on a glossy lobe 7 deg from its peak, and more near grazing).
    ///
    /// What is interpolated is the projected BRDF `f cos theta_i cos theta_o` (smooth at
    /// grazing angles, where f itself grows as `1 / cos^2`), trilinearly in the grid's index
    /// coordinates (theta_h's square-root coordinate, theta_d and phi_d in degrees) and in
    /// its logarithm (so that a lobe's exponential or power-law fall is followed between
    /// centres, not cut by chords), then divided by the query's own projection. phi_d is
    /// periodic over 180 deg (reciprocity); theta_h and theta_d are held at the first and
    /// last centres beyond them. Where a neighbour is zero the values are averaged instead of
    /// their logarithms, and below the horizon f itself is interpolated. A table reads back
    /// its samples exactly at the centres.
    ///
    /// `None` when the nearest cell is not measured, like [`MerlBrdf::lookup`]; neighbours
    /// that are not measured are left out and the weights of the others renormalised.
    pub fn interpolate(&self, hd: HalfDiff) -> Option<Rgb> {
        self.cell(Bin::of(hd).index())?;
        let [theta_h_deg, theta_d_deg, phi_d_deg] = reader_degrees(hd);
        let theta_h = clamped_neighbours(theta_h_coordinate(theta_h_deg), THETA_H_BINS);
        let theta_d = clamped_neighbours(theta_d_deg, THETA_D_BINS);
        let phi_d = periodic_neighbours(phi_d_deg, PHI_D_BINS);
        let projection = cos_theta_i_cos_theta_o(hd.theta_h, hd.theta_d, hd.phi_d);
        // Above the horizon, the projected BRDF is interpolated (see the doc comment).
        let weighted = projection > 0.0;
        let mut sum = Rgb::ZERO;
        let mut log_sum = Rgb::ZERO;
        let mut weight = 0.0;
        for (theta_h_i, w_h) in theta_h {
            for (theta_d_i, w_d) in theta_d {
                for (phi_d_i, w_p) in phi_d {
                    let w = w_h * w_d * w_p;
                    let bin = Bin {
                        theta_h_i,
                        theta_d_i,
                        phi_d_i,
                    };
                    if let (true, Some(value)) = (w > 0.0, self.cell(bin.index())) {
                        let node = if weighted {
                            let [h, d, p] = bin.centre_deg().map(f64::to_radians);
                            cos_theta_i_cos_theta_o(h, d, p).max(0.0)
                        } else {
                            1.0
                        };
                        sum += w * node * value;
                        log_sum += w * (node * value).map(f64::ln);
                        weight += w;
                    }
                }
            }
        }
        let scale = if weighted { projection } else { 1.0 };
        let geometric = (log_sum / weight).exp();
        let mean = if geometric.is_finite() && geometric.min_element() > 0.0 {
            geometric
        } else {
            sum / weight
        };
        (weight > 0.0).then(|| mean / scale)
    }

    /// The directional albedo at incidence `theta_i_deg`, `rho(wi) = integral f(wi, wo)
    /// cos theta_o dwo` over the hemisphere (energy conservation asks `rho <= 1`), per channel.
    ///
    /// Integrated over the half vector, where a specular table keeps its structure: with
    /// `wo = 2 (wi . h) h - wi`, `dwo = 4 (wi . h) dwh` (the Jacobian of the reflection, as in
    /// Walter et al. 2007, eq. 14), on [`ALBEDO_THETA_H_NODES`] midpoints of MERL's
    /// square-root theta_h coordinate (fine at the peak) times [`ALBEDO_PHI_H_NODES`] in
    /// phi_h, the table between its bins by [`Self::interpolate`]. Cells not measured count
    /// as zero.
    pub fn directional_albedo(&self, theta_i_deg: f64) -> Rgb {
        let wi = DVec3::new(
            theta_i_deg.to_radians().sin(),
            0.0,
            theta_i_deg.to_radians().cos(),
        );
        let du = 1.0 / ALBEDO_THETA_H_NODES as f64;
        let dphi = std::f64::consts::TAU / ALBEDO_PHI_H_NODES as f64;
        (0..ALBEDO_THETA_H_NODES)
            .into_par_iter()
            .map(|i| {
                let u = (i as f64 + 0.5) * du;
                let theta_h = std::f64::consts::FRAC_PI_2 * u * u;
                let d_theta_h = std::f64::consts::PI * u * du;
                let mut sum = Rgb::ZERO;
                for j in 0..ALBEDO_PHI_H_NODES {
                    let phi_h = (j as f64 + 0.5) * dphi;
                    let h = DVec3::new(
                        theta_h.sin() * phi_h.cos(),
                        theta_h.sin() * phi_h.sin(),
                        theta_h.cos(),
                    );
                    let cos_d = wi.dot(h);
                    let wo = 2.0 * cos_d * h - wi;
                    if cos_d <= 0.0 || wo.z <= 0.0 {
                        continue;
                    }
                    let f = self
                        .interpolate(HalfDiff::from_directions(wi, wo))
                        .unwrap_or(Rgb::ZERO);
                    sum += f * (wo.z * 4.0 * cos_d * theta_h.sin() * d_theta_h * dphi);
                }
                sum
            })
            .collect::<Vec<Rgb>>()
            .into_iter()
            .fold(Rgb::ZERO, |a, b| a + b)
    }

    /// Renames the table (the name reports and written files show).
    pub fn set_name(&mut self, name: impl Into<String>) {
        self.name = name.into();
    }

    /// The table as f_r in 1/sr: three planes (R, G, B) of [`CELLS`] values each in cell
    /// order, NaN in every channel of a cell not measured. The stored planes are scaled in
    /// place (in parallel), so no second table is allocated.
    pub fn into_planes_per_sr(mut self) -> Vec<f64> {
        let (red, rest) = self.stored.split_at_mut(CELLS);
        let (green, blue) = rest.split_at_mut(CELLS);
        red.par_chunks_mut(PHI_D_BINS)
            .zip(green.par_chunks_mut(PHI_D_BINS))
            .zip(blue.par_chunks_mut(PHI_D_BINS))
            .with_min_len(THETA_D_BINS)
            .for_each(|((red, green), blue)| {
                for ((r, g), b) in red.iter_mut().zip(green).zip(blue) {
                    if *r >= 0.0 && *g >= 0.0 && *b >= 0.0 {
                        *r *= CHANNEL_SCALE[0];
                        *g *= CHANNEL_SCALE[1];
                        *b *= CHANNEL_SCALE[2];
                    } else {
                        [*r, *g, *b] = [f64::NAN; 3];
                    }
                }
            });
        self.stored
    }
}

/// Checks the 12-byte header (or as much as there is) and the total length of a file; the
/// error says what is wrong, for the caller to put after the file's name.
pub fn check_header(header: &[u8], total_len: u64) -> Result<(), MerlProblem> {
    if header.len() < HEADER_BYTES {
        return Err(MerlProblem::TooShort { total_len });
    }
    let dim = |i: usize| {
        i32::from_le_bytes([
            header[4 * i],
            header[4 * i + 1],
            header[4 * i + 2],
            header[4 * i + 3],
        ])
    };
    let dims = [dim(0), dim(1), dim(2)];
    if dims != [THETA_H_BINS as i32, THETA_D_BINS as i32, PHI_D_BINS as i32] {
        return Err(MerlProblem::Dimensions { dims });
    }
    match total_len.cmp(&(FILE_BYTES as u64)) {
        std::cmp::Ordering::Less => Err(MerlProblem::Truncated { total_len }),
        std::cmp::Ordering::Greater => Err(MerlProblem::OverLong { total_len }),
        std::cmp::Ordering::Equal => Ok(()),
    }
}

/// A zeroed buffer for the three planes, backed by transparent huge pages where the system
/// offers them: filling 35 MB of fresh 4 KiB pages costs more page faults than the read
/// itself (numpy asks for huge pages for large arrays the same way). The allocator hands out
/// zeroed pages it has not touched, so the advice takes effect before the first fault.
fn allocate_planes() -> Vec<f64> {
    let mut planes = vec![0.0; 3 * CELLS];
    advise_huge_pages(&mut planes);
    planes
}

/// Values per unit of parallel reading and checking (64 KiB), so that a unit is still in
/// the cache when it is checked.
const READ_UNIT_VALUES: usize = 8192;

/// Whether a stored value is finite and at most [`MAX_STORED_VALUE`].
fn is_plausible(value: f64) -> bool {
    value.is_finite() && value <= MAX_STORED_VALUE
}

/// Whether every value [`is_plausible`] (one pass without branches, so that checking costs
/// next to nothing beside reading).
fn all_plausible(values: &[f64]) -> bool {
    values.iter().fold(true, |ok, v| ok & is_plausible(*v))
}

/// Fills `buffer` from `file` at byte `offset`, without moving a shared cursor.
#[cfg(unix)]
fn read_exact_at(file: &std::fs::File, buffer: &mut [u8], offset: u64) -> std::io::Result<()> {
    std::os::unix::fs::FileExt::read_exact_at(file, buffer, offset)
}

/// Fills `buffer` from `file` at byte `offset`, without moving a shared cursor.
#[cfg(windows)]
fn read_exact_at(file: &std::fs::File, buffer: &mut [u8], offset: u64) -> std::io::Result<()> {
    let mut filled = 0;
    while filled < buffer.len() {
        match std::os::windows::fs::FileExt::seek_read(
            file,
            &mut buffer[filled..],
            offset + filled as u64,
        )? {
            0 => return Err(std::io::ErrorKind::UnexpectedEof.into()),
            n => filled += n,
        }
    }
    Ok(())
}

#[cfg(target_os = "linux")]
fn advise_huge_pages(buffer: &mut Vec<f64>) {
    const HUGE_PAGE: usize = 2 << 20;
    let start = buffer.as_mut_ptr() as usize;
    let end = start + buffer.capacity() * std::mem::size_of::<f64>();
    let aligned_start = start.next_multiple_of(HUGE_PAGE);
    let aligned_end = end - end % HUGE_PAGE;
    if aligned_end > aligned_start {
        // SAFETY: the range lies inside the buffer's own allocation, is page-aligned, and
        // MADV_HUGEPAGE only changes how the kernel backs it, never its contents. A failure
        // (no transparent huge pages) leaves ordinary pages, so the result is ignored.
        unsafe {
            libc::madvise(
                aligned_start as *mut libc::c_void,
                aligned_end - aligned_start,
                libc::MADV_HUGEPAGE,
            );
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn advise_huge_pages(_buffer: &mut Vec<f64>) {}

/// Reads as many bytes as are there, up to the buffer's length.
fn read_up_to(reader: &mut impl std::io::Read, buffer: &mut [u8]) -> std::io::Result<usize> {
    let mut filled = 0;
    while filled < buffer.len() {
        match reader.read(&mut buffer[filled..])? {
            0 => break,
            n => filled += n,
        }
    }
    Ok(filled)
}

fn file_stem(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}

impl std::fmt::Debug for MerlBrdf {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MerlBrdf")
            .field("name", &self.name)
            .field("measured", &self.measured_count())
            .finish()
    }
}

impl Brdf for MerlBrdf {
    fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
        if !both_above_surface(wi, wo) {
            return Some(Rgb::ZERO);
        }
        self.lookup(HalfDiff::from_directions(wi, wo))
    }

    fn eval_half_diff(&self, hd: HalfDiff) -> Option<Rgb> {
        self.lookup(hd)
    }

    fn eval_smooth(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
        if !both_above_surface(wi, wo) {
            return Some(Rgb::ZERO);
        }
        self.interpolate(HalfDiff::from_directions(wi, wo))
    }

    fn name(&self) -> String {
        self.name.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_table() -> MerlBrdf {
        let mut t = MerlBrdf::empty("t");
        for i in (0..CELLS).step_by(7) {
            t.set_cell(i, Some(Rgb::new(i as f64, 2.0 * i as f64, 0.5) * 1e-3));
        }
        t
    }

    /// The logarithm of the projected BRDF of [`interpolation_table`], affine in the grid's
    /// index coordinates (theta_h's square-root coordinate, theta_d and phi_d in degrees).
    fn log_projected(theta_h_coordinate: f64, theta_d_deg: f64, phi_d_deg: f64) -> f64 {
        -3.0 + 0.05 * theta_h_coordinate + 0.02 * theta_d_deg + 0.01 * phi_d_deg
    }

    /// `cos theta_i cos theta_o` at angles in degrees.
    fn projection_deg(theta_h_deg: f64, theta_d_deg: f64, phi_d_deg: f64) -> f64 {
        cos_theta_i_cos_theta_o(
            theta_h_deg.to_radians(),
            theta_d_deg.to_radians(),
            phi_d_deg.to_radians(),
        )
    }

    /// A table whose projected BRDF `f cos theta_i cos theta_o` is `exp` of
    /// [`log_projected`] at the cell centres (not measured below the horizon).
    fn interpolation_table() -> MerlBrdf {
        MerlBrdf::from_fn("log-affine", |index| {
            let bin = Bin::from_index(index);
            let [theta_h_deg, theta_d_deg, phi_d_deg] = bin.centre_deg();
            let projection = projection_deg(theta_h_deg, theta_d_deg, phi_d_deg);
            let log = log_projected(bin.theta_h_i as f64 + 0.5, theta_d_deg, phi_d_deg);
            (projection > 0.0).then(|| Rgb::splat(log.exp() / projection))
        })
    }

    #[test]
    fn interpolation_is_log_linear_in_the_projected_brdf_between_centres() {
        let table = interpolation_table();
        let at = |theta_h_deg: f64, theta_d_deg: f64, phi_d_deg: f64| {
            let hd = HalfDiff::from_degrees(theta_h_deg, 20.0, theta_d_deg, phi_d_deg);
            table.interpolate(hd).unwrap().x
        };
        let close = |got: f64, expected: f64| (got - expected).abs() < 1e-9 * expected;
        // Between centres (phi_d away from the seam): exp of the affine function over the
        // query's own projection, where the nearest bin is off by up to half a step.
        for (theta_h_deg, theta_d_deg, phi_d_deg) in [
            (7.5, 37.5, 90.0),
            (0.3, 12.2, 45.7),
            (33.3, 40.9, 170.1),
            (1.0, 0.6, 1.2),
            (2.0, 84.7, 30.2),
        ] {
            let log = log_projected(theta_h_coordinate(theta_h_deg), theta_d_deg, phi_d_deg);
            let expected = log.exp() / projection_deg(theta_h_deg, theta_d_deg, phi_d_deg);
            let got = at(theta_h_deg, theta_d_deg, phi_d_deg);
            assert!(
                close(got, expected),
                "({theta_h_deg}, {theta_d_deg}, {phi_d_deg}): {got}, expected {expected}"
            );
            let hd = HalfDiff::from_degrees(theta_h_deg, 20.0, theta_d_deg, phi_d_deg);
            let nearest = table.lookup(hd).unwrap().x;
            assert!((nearest - expected).abs() > 1e-4 * expected);
        }
        // Beyond the first and last centres, theta_h and theta_d hold their edge values.
        let edge = |theta_h_deg: f64, theta_d_deg: f64, coordinates: [f64; 3]| {
            let [h, d, p] = coordinates;
            log_projected(h, d, p).exp() / projection_deg(theta_h_deg, theta_d_deg, p)
        };
        assert!(close(at(0.0, 0.2, 90.5), edge(0.0, 0.2, [0.5, 0.5, 90.5])));
        assert!(close(at(1.0, 89.9, 90.5), {
            let h = theta_h_coordinate(1.0);
            edge(1.0, 89.9, [h, 89.5, 90.5])
        }));
        // phi_d is periodic over 180 deg: 0.2 deg lies between the centres 179.5 and 0.5.
        let theta_h_deg = theta_h_centre_deg(9);
        let seam = 0.3 * log_projected(9.5, 40.5, 179.5) + 0.7 * log_projected(9.5, 40.5, 0.5);
        let expected = seam.exp() / projection_deg(theta_h_deg, 40.5, 0.2);
        assert!(close(at(theta_h_deg, 40.5, 0.2), expected));
    }

    #[test]
    fn interpolation_leaves_out_unmeasured_neighbours_and_follows_the_nearest_cell() {
        let mut table = interpolation_table();
        let hd = HalfDiff::from_degrees(theta_h_centre_deg(20), 0.0, 40.2, 90.5);
        // Nearest cell (theta_d 40) measured, its neighbour across theta_d (39, weight 0.3)
        // not: the nearest cell's projected value alone, over the query's projection.
        let [nearest, neighbour] = [40, 39].map(|theta_d_i| Bin {
            theta_h_i: 20,
            theta_d_i,
            phi_d_i: 90,
        });
        table.set_cell(neighbour.index(), None);
        let [h, d, p] = nearest.centre_deg();
        let expected = table.cell(nearest.index()).unwrap().x * projection_deg(h, d, p)
            / projection_deg(theta_h_centre_deg(20), 40.2, 90.5);
        let got = table.interpolate(hd).unwrap().x;
        assert!((got - expected).abs() < 1e-9 * expected, "{got} {expected}");
        table.set_cell(nearest.index(), None);
        assert_eq!(table.interpolate(hd), None);
    }

    #[test]
    fn planes_per_sr_are_the_cells_with_nan_holes() {
        let mut t = sample_table();
        // One negative channel is enough to make a cell not measured.
        t.stored[14 + CELLS] = -0.5;
        let planes = t.clone().into_planes_per_sr();
        assert_eq!(planes.len(), 3 * CELLS);
        for i in [0, 1, 7, 14, 21, CELLS - 1] {
            match t.cell(i) {
                Some(v) => (0..3).for_each(|c| assert_eq!(planes[i + c * CELLS], v[c])),
                None => (0..3).for_each(|c| assert!(planes[i + c * CELLS].is_nan())),
            }
        }
        assert!(t.cell(14).is_none() && t.cell(21).is_some());
    }

    #[test]
    fn bins_of_degrees_follow_merls_boundary_rules() {
        let bin = |h: f64, d: f64, p: f64| {
            let b = Bin::of_degrees(h, d, p);
            (b.theta_h_i, b.theta_d_i, b.phi_d_i)
        };
        // theta_h is square-root spaced: bin i starts at i^2 / 90 deg (10 deg starts bin 30).
        assert_eq!(bin(10.0, 0.0, 0.0).0, 30);
        assert_eq!(bin(10.0 - 1e-9, 0.0, 0.0).0, 29);
        assert_eq!(bin(1.0, 0.0, 0.0).0, 9);
        // Clamping: below 0 and NaN to bin 0, 90 and beyond to the last bin.
        assert_eq!(bin(-3.0, -1.0, f64::NAN), (0, 0, 0));
        assert_eq!(bin(90.0, 90.0, 0.0), (89, 89, 0));
        assert_eq!(bin(120.0, 200.0, 0.0), (89, 89, 0));
        // phi_d folds into [0, 180): 180 is 0, 190 is 10, -10 is 170, a hair below 0 is 0.
        assert_eq!(bin(0.0, 0.0, 180.0).2, 0);
        assert_eq!(bin(0.0, 0.0, 190.0).2, 10);
        assert_eq!(bin(0.0, 0.0, -10.0).2, 170);
        assert_eq!(bin(0.0, 0.0, 179.999).2, 179);
        assert_eq!(bin(0.0, 0.0, -1e-15).2, 0);
        // Whole degrees in degrees land in their own bin.
        for deg in 0..90 {
            let x = deg as f64;
            assert_eq!(
                bin(theta_h_centre_deg(deg), x, 2.0 * x),
                (deg, deg, 2 * deg)
            );
        }
        // Through radians the reference reader's arithmetic decides: 15 deg is bin 15, but
        // 39 deg in radians is a hair below 39 and the reader bins it in 38.
        let through_radians = |d: f64| Bin::of(HalfDiff::from_degrees(1.0, 0.0, d, d));
        assert_eq!(through_radians(15.0), Bin::of_degrees(1.0, 15.0, 15.0));
        assert_eq!(through_radians(39.0), Bin::of_degrees(1.0, 38.5, 38.5));
        // The mirror of a boundary is a boundary; of a bin's inside, the mirror bin 179 - k.
        let mirror = |d: f64| Bin::of_mirror(HalfDiff::from_degrees(1.0, 0.0, 40.0, d)).phi_d_i;
        assert_eq!((mirror(45.0), mirror(45.5), mirror(0.0)), (135, 134, 0));
    }

    #[test]
    fn bins_of_degrees_and_of_radians_agree_beside_every_bin_edge() {
        // Each edge of each axis, approached from both sides by 1e-7 deg (far beyond the
        // float noise of the trip through radians, far inside the narrowest bin).
        const BESIDE_DEG: f64 = 1e-7;
        let agree = |h: f64, d: f64, p: f64| {
            assert_eq!(
                Bin::of(HalfDiff::from_degrees(h, 0.0, d, p)),
                Bin::of_degrees(h, d, p),
                "theta_h {h}, theta_d {d}, phi_d {p}"
            );
        };
        for side in [-BESIDE_DEG, BESIDE_DEG] {
            for i in 1..THETA_H_BINS {
                agree(theta_h_deg_at(i as f64) + side, 20.5, 70.5);
            }
            for j in 1..THETA_D_BINS {
                agree(30.0, j as f64 + side, 70.5);
            }
            for k in 1..PHI_D_BINS {
                agree(30.0, 20.5, k as f64 + side);
            }
        }
    }

    #[test]
    fn theta_h_coordinate_inverts_and_clamps() {
        assert_eq!(theta_h_coordinate(1.0), 90f64.sqrt());
        assert_eq!(theta_h_coordinate(-1.0), 0.0);
        assert_eq!(theta_h_coordinate(f64::NAN), 0.0);
        assert_eq!(theta_h_coordinate(100.0), 90.0);
        for c in [0.0, 0.5, 9.0, 44.5, 90.0] {
            assert!((theta_h_coordinate(theta_h_deg_at(c)) - c).abs() < 1e-12);
        }
        assert_eq!(theta_h_centre_deg(2), 2.5 * 2.5 / 90.0);
    }

    #[test]
    fn bin_centres_in_degrees() {
        let bin = Bin {
            theta_h_i: 2,
            theta_d_i: 40,
            phi_d_i: 89,
        };
        assert_eq!(bin.centre_deg(), [2.5 * 2.5 / 90.0, 40.5, 89.5]);
        let hd = bin.centre(0.0);
        assert!((hd.theta_d.to_degrees() - 40.5).abs() < 1e-12);
        assert_eq!(Bin::of(hd), bin);
    }

    #[test]
    fn bytes_round_trip_exactly() {
        let t = sample_table();
        let bytes = t.to_bytes();
        assert_eq!(bytes.len(), FILE_BYTES);
        let back = MerlBrdf::from_bytes("t", &bytes).unwrap();
        assert_eq!(back.to_bytes(), bytes);
        assert_eq!(back.measured_count(), t.measured_count());
        assert_eq!(back.cell(1), None);
        assert_eq!(back.cell(7), t.cell(7));
    }

    #[test]
    fn header_and_layout_follow_the_format() {
        let mut t = MerlBrdf::empty("t");
        let bin = Bin {
            theta_h_i: 3,
            theta_d_i: 5,
            phi_d_i: 7,
        };
        t.set_cell(bin.index(), Some(Rgb::new(1.0, 1.15, 1.66) / 1500.0));
        let bytes = t.to_bytes();
        assert_eq!(&bytes[0..4], &90i32.to_le_bytes());
        assert_eq!(&bytes[8..12], &180i32.to_le_bytes());
        let idx = 7 + 180 * 5 + 180 * 90 * 3;
        for c in 0..3 {
            let at = HEADER_BYTES + 8 * (c * CELLS + idx);
            let v = f64::from_le_bytes(bytes[at..at + 8].try_into().unwrap());
            assert!((v - 1.0).abs() < 1e-12, "channel {c}: {v}");
        }
    }

    #[test]
    fn bins_follow_the_reference_reader() {
        let b = Bin::of(HalfDiff::from_degrees(1.0, 0.0, 40.3, 90.0));
        assert_eq!(b.theta_h_i, 9); // sqrt(90) = 9.49
        assert_eq!(b.theta_d_i, 40);
        assert_eq!(b.phi_d_i, 90);
        let folded = Bin::of(HalfDiff::from_degrees(89.99, 0.0, 89.99, 270.5));
        assert_eq!(
            (folded.theta_h_i, folded.theta_d_i, folded.phi_d_i),
            (89, 89, 90)
        );
        for i in 0..THETA_H_BINS {
            let c = Bin {
                theta_h_i: i,
                theta_d_i: 12,
                phi_d_i: 170,
            };
            assert_eq!(Bin::of(c.centre(0.3)), c);
        }
        for whole_deg in [3.0, 15.0, 30.0, 60.0, 87.0] {
            let b = Bin::of(HalfDiff::from_degrees(10.0, 0.0, whole_deg, whole_deg));
            assert_eq!(
                (b.theta_d_i, b.phi_d_i),
                (whole_deg as usize, whole_deg as usize)
            );
        }
        for index in [0, 1, 180, CELLS - 1, 123_456] {
            assert_eq!(Bin::from_index(index).index(), index);
        }
    }

    #[test]
    fn bad_input_is_described() {
        assert!(MerlBrdf::from_bytes("x", &[0; 5])
            .unwrap_err()
            .to_string()
            .contains("too short"));
        let mut bytes = sample_table().to_bytes();
        let err = MerlBrdf::from_bytes("x", &bytes[..1000])
            .unwrap_err()
            .to_string();
        assert!(err.contains("truncated"), "{err}");
        bytes.push(0);
        assert!(MerlBrdf::from_bytes("x", &bytes)
            .unwrap_err()
            .to_string()
            .contains("over-long"));
        bytes.pop();
        bytes[0..4].copy_from_slice(&(-5i32).to_le_bytes());
        assert!(MerlBrdf::from_bytes("x", &bytes)
            .unwrap_err()
            .to_string()
            .contains("dimensions -5"));
        bytes[0..4].copy_from_slice(&90i32.to_le_bytes());
        let at = HEADER_BYTES + 8 * (CELLS + 44);
        bytes[at..at + 8].copy_from_slice(&f64::NAN.to_le_bytes());
        let err = MerlBrdf::from_bytes("x", &bytes).unwrap_err().to_string();
        assert!(err.contains("non-finite") && err.contains("green"), "{err}");
    }

    #[test]
    fn absurd_values_and_text_files_are_refused_at_load() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.binary");
        let mut bytes = sample_table().to_bytes();
        let at = HEADER_BYTES + 8 * (2 * CELLS + 181);
        bytes[at..at + 8].copy_from_slice(&1e308f64.to_le_bytes());
        std::fs::write(&path, &bytes).unwrap();
        let err = MerlBrdf::read(&path).unwrap_err().to_string();
        assert_eq!(
            err,
            format!(
                "{}: value 1e308 in the blue channel at cell (theta_h 0, theta_d 1, phi_d 1) is above 1e13, the most a MERL table may hold",
                path.display()
            )
        );
        let negative: Vec<u8> = bytes[..HEADER_BYTES]
            .iter()
            .copied()
            .chain((0..3 * CELLS).flat_map(|_| (-2.5f64).to_le_bytes()))
            .collect();
        std::fs::write(&path, &negative).unwrap();
        let err = MerlBrdf::read(&path).unwrap_err().to_string();
        assert!(err.ends_with("no measured cell: every cell holds a negative value, the format's \"not measured\""), "{err}");
        std::fs::write(&path, "a text file, not a table\n".repeat(100)).unwrap();
        let err = MerlBrdf::read(&path).unwrap_err().to_string();
        assert!(err.contains(": not a MERL file: "), "{err}");
        let err = MerlBrdf::read(&dir.path().join("none.binary"))
            .unwrap_err()
            .to_string();
        assert!(
            err.ends_with("none.binary: cannot read: no such file"),
            "{err}"
        );
    }

    #[test]
    fn a_lambertian_table_has_its_reflectance_as_albedo() {
        // f = rho / pi integrates to rho at every incidence (closed form); 0.6 and 0.3 in two
        // channels, at normal, oblique and grazing incidence.
        let rho = Rgb::new(0.6, 0.3, 0.3);
        let table = MerlBrdf::from_fn("lambert", |_| Some(rho * std::f64::consts::FRAC_1_PI));
        for theta_i in [0.0, 30.0, 60.0, 80.0] {
            let albedo = table.directional_albedo(theta_i);
            for c in 0..3 {
                assert!(
                    (albedo[c] / rho[c] - 1.0).abs() < 5e-3,
                    "{theta_i}: {albedo:?}"
                );
            }
        }
    }
}
