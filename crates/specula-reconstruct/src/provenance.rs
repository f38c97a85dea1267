//! The provenance sidecar: for every MERL cell, where its reconstructed value comes from,
//! which the MERL format itself cannot say.
//!
//! File: NumPy `.npy` (format 1.0), dtype `uint8`, shape `(90, 90, 180)` in C order, i.e. the
//! MERL cell order (theta_h, theta_d, phi_d); `numpy.load` reads it. Codes:
//!
//! - 0 measured: a sample lies in the cell's bin (directly or through the phi_d symmetry);
//! - 1 interpolated: the value comes from measured lattice nodes only;
//! - 2 extrapolated: the bin centre lies beyond the lattice on some axis, or a node that
//!   brackets it was extrapolated ([`crate::extrapolate`]: the nearest measured node
//!   continued in the method's domain; with `lobe` that is the residual over the fitted
//!   lobe, so the lobe's shape carries the cell, with `linear` and `log` a copy of the value);
//! - 3 prior: as 2, with the `prior` method's model (the lobe blended with the data-driven
//!   prior, [`crate::prior_reconstruct`]) carrying the cell.
//!
//! Beside `OUT.binary` it is written as `OUT.provenance.npy`.

use specula_core::merl::{self, Bin, CELLS, PHI_D_BINS, THETA_D_BINS, THETA_H_BINS};
use specula_core::{HalfDiff, Sample};
use std::path::{Path, PathBuf};

/// Where a cell's value comes from (the code stored in the file).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum CellOrigin {
    /// A sample lies in the cell's bin (directly or through the phi_d symmetry).
    Measured = 0,
    /// Interpolated from measured lattice nodes only.
    Interpolated = 1,
    /// Beyond the lattice, or bracketed by an extrapolated node.
    Extrapolated = 2,
    /// As `Extrapolated`, but taken from the data-driven prior and the lobe.
    Prior = 3,
}

impl CellOrigin {
    fn from_code(code: u8) -> Option<Self> {
        match code {
            0 => Some(CellOrigin::Measured),
            1 => Some(CellOrigin::Interpolated),
            2 => Some(CellOrigin::Extrapolated),
            3 => Some(CellOrigin::Prior),
            _ => None,
        }
    }

    /// Whether the value lies beyond what was measured (extrapolated or from the prior).
    pub fn is_extrapolated(self) -> bool {
        matches!(self, CellOrigin::Extrapolated | CellOrigin::Prior)
    }
}

/// The origin of every MERL cell, in cell order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Provenance {
    /// The origin of each cell, in MERL cell order.
    pub cells: Vec<CellOrigin>,
}

/// What is wrong with a provenance file.
#[derive(Debug, thiserror::Error)]
pub enum ProvenanceError {
    /// The file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The file's contents are not a provenance array.
    #[error("{path}: {problem}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// What is wrong with its bytes.
        problem: NpyProblem,
    },
}

/// What is wrong with the bytes of a provenance `.npy` file.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum NpyProblem {
    /// The bytes do not start with NumPy 1.0's magic.
    #[error("not a NumPy 1.0 .npy file")]
    NotNpy,
    /// The header is cut short or is not text.
    #[error("truncated or non-text .npy header")]
    Header,
    /// The header describes another array than the provenance's.
    #[error("header '{found}', expected '{HEADER}'")]
    Layout {
        /// The header found, trailing padding removed.
        found: String,
    },
    /// The data holds another number of cells than the MERL grid.
    #[error("{found} cells, expected {CELLS}")]
    Cells {
        /// The number of cells found.
        found: usize,
    },
    /// A cell holds a code that no [`CellOrigin`] has.
    #[error("unknown code {code} at cell {index}")]
    Code {
        /// The code found.
        code: u8,
        /// The cell's index in MERL order.
        index: usize,
    },
}

const MAGIC: &[u8] = b"\x93NUMPY\x01\x00";
const HEADER: &str = "{'descr': '|u1', 'fortran_order': False, 'shape': (90, 90, 180), }";

impl Provenance {
    /// Cells are extrapolated where `extrapolated` says so, otherwise interpolated, and
    /// measured in the bins of a sample and of its mirror image (phi_d to 180 - phi_d), by
    /// [`Bin::of_degrees`] after [`edge_snapped_degrees`].
    pub fn new(samples: &[Sample], extrapolated: &[bool]) -> Self {
        let mut cells: Vec<CellOrigin> = extrapolated
            .iter()
            .map(|&e| {
                if e {
                    CellOrigin::Extrapolated
                } else {
                    CellOrigin::Interpolated
                }
            })
            .collect();
        for s in samples {
            let [theta_h_deg, theta_d_deg, phi_d_deg] = edge_snapped_degrees(s.hd);
            for phi in [phi_d_deg, 180.0 - phi_d_deg] {
                cells[Bin::of_degrees(theta_h_deg, theta_d_deg, phi).index()] =
                    CellOrigin::Measured;
            }
        }
        Self { cells }
    }

    /// Marks the extrapolated cells as filled from the prior ([`CellOrigin::Prior`]).
    pub fn mark_prior(&mut self) {
        for cell in &mut self.cells {
            if *cell == CellOrigin::Extrapolated {
                *cell = CellOrigin::Prior;
            }
        }
    }

    /// The counts of [`Provenance::counts`] in words, e.g. "1205 measured, 600900
    /// interpolated, 855895 extrapolated", with how many of the extrapolated cells come from
    /// the prior when any do.
    pub fn summary(&self) -> String {
        let (measured, interpolated, extrapolated) = self.counts();
        let from_prior = match self.prior_count() {
            0 => String::new(),
            n => format!(" ({n} of them from the prior)"),
        };
        format!("{measured} measured, {interpolated} interpolated, {extrapolated} extrapolated{from_prior}")
    }

    /// How many cells have each origin: (measured, interpolated, extrapolated), the last
    /// counting the cells from the prior too ([`CellOrigin::is_extrapolated`]).
    pub fn counts(&self) -> (usize, usize, usize) {
        let count = |o| self.cells.iter().filter(|c| **c == o).count();
        let extrapolated = self.cells.iter().filter(|c| c.is_extrapolated()).count();
        (
            count(CellOrigin::Measured),
            count(CellOrigin::Interpolated),
            extrapolated,
        )
    }

    /// The share of the cells extrapolated (not between samples), in `[0, 1]`: how much of
    /// the table is made up rather than measured.
    pub fn extrapolated_share(&self) -> f64 {
        let (measured, interpolated, extrapolated) = self.counts();
        extrapolated as f64 / (measured + interpolated + extrapolated).max(1) as f64
    }

    /// How many cells come from the prior.
    pub fn prior_count(&self) -> usize {
        self.cells
            .iter()
            .filter(|c| **c == CellOrigin::Prior)
            .count()
    }

    /// The bytes of the `.npy` file.
    pub fn to_npy(&self) -> Vec<u8> {
        // Header padded with spaces and a newline so that the data starts on 64 bytes.
        let unpadded = MAGIC.len() + 2 + HEADER.len() + 1;
        let padding = (64 - unpadded % 64) % 64;
        let header = format!("{HEADER}{}\n", " ".repeat(padding));
        let mut out = Vec::with_capacity(MAGIC.len() + 2 + header.len() + CELLS);
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&(header.len() as u16).to_le_bytes());
        out.extend_from_slice(header.as_bytes());
        out.extend(self.cells.iter().map(|c| *c as u8));
        out
    }

    /// Parses the bytes of a file written by [`Provenance::to_npy`].
    pub fn from_npy(bytes: &[u8]) -> Result<Self, NpyProblem> {
        if !bytes.starts_with(MAGIC) || bytes.len() < MAGIC.len() + 2 {
            return Err(NpyProblem::NotNpy);
        }
        let len = u16::from_le_bytes([bytes[MAGIC.len()], bytes[MAGIC.len() + 1]]) as usize;
        let start = MAGIC.len() + 2;
        let header = bytes
            .get(start..start + len)
            .and_then(|h| std::str::from_utf8(h).ok())
            .ok_or(NpyProblem::Header)?;
        if header.trim_end() != HEADER {
            return Err(NpyProblem::Layout {
                found: header.trim_end().to_string(),
            });
        }
        let data = &bytes[start + len..];
        if data.len() != THETA_H_BINS * THETA_D_BINS * PHI_D_BINS {
            return Err(NpyProblem::Cells { found: data.len() });
        }
        let cells = data
            .iter()
            .enumerate()
            .map(|(i, &code)| {
                CellOrigin::from_code(code).ok_or(NpyProblem::Code { code, index: i })
            })
            .collect::<Result<_, _>>()?;
        Ok(Self { cells })
    }

    /// Whether a sample fell in the cell at `index` (in MERL cell order).
    pub fn is_measured(&self, index: usize) -> bool {
        self.cells.get(index) == Some(&CellOrigin::Measured)
    }

    /// The provenance beside a MERL table ([`sidecar_path`]), if there is one.
    pub fn beside(merl_path: &Path) -> Result<Option<Self>, ProvenanceError> {
        let sidecar = sidecar_path(merl_path);
        if sidecar.is_file() {
            Self::read(&sidecar).map(Some)
        } else {
            Ok(None)
        }
    }

    /// Writes the provenance as a `.npy` file at `path`.
    pub fn write(&self, path: &Path) -> Result<(), ProvenanceError> {
        specula_core::atomic_file::write_bytes(path, &self.to_npy()).map_err(|source| {
            ProvenanceError::Io {
                path: path.to_path_buf(),
                source,
            }
        })
    }

    /// Reads a provenance `.npy` file.
    pub fn read(path: &Path) -> Result<Self, ProvenanceError> {
        let bytes = std::fs::read(path).map_err(|source| ProvenanceError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::from_npy(&bytes).map_err(|problem| ProvenanceError::Invalid {
            path: path.to_path_buf(),
            problem,
        })
    }
}

/// The half-difference angles of `hd` in degrees, `[theta_h, theta_d, phi_d]`, each put on a
/// MERL bin edge when within float noise (1e-9 in the axis's index coordinate) of it: plans
/// put samples on whole degrees, which the round trip through radians may leave a hair below
/// the edge, and a sample and its reciprocal (phi_d + 180) must mark the same cells.
fn edge_snapped_degrees(hd: HalfDiff) -> [f64; 3] {
    const NOISE: f64 = 1e-9;
    let snap = |x: f64| {
        if (x - x.round()).abs() < NOISE {
            x.round()
        } else {
            x
        }
    };
    [
        merl::theta_h_deg_at(snap(merl::theta_h_coordinate(hd.theta_h.to_degrees()))),
        snap(hd.theta_d.to_degrees()),
        snap(hd.phi_d.to_degrees().rem_euclid(180.0)),
    ]
}

/// The sidecar path of a MERL output: `OUT.binary` -> `OUT.provenance.npy`.
pub fn sidecar_path(merl_path: &Path) -> PathBuf {
    merl_path.with_extension("provenance.npy")
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::{HalfDiff, Rgb};

    #[test]
    fn npy_round_trips_and_aligns_the_data() {
        let mut extrapolated = vec![false; CELLS];
        extrapolated[CELLS - 1] = true;
        let samples = [Sample::new(
            HalfDiff::from_degrees(1.0, 45.0, 40.0, 15.0),
            Rgb::ONE,
        )];
        let p = Provenance::new(&samples, &extrapolated);
        assert_eq!(p.counts(), (2, CELLS - 3, 1));
        assert_eq!(p.extrapolated_share(), 1.0 / CELLS as f64);
        let bytes = p.to_npy();
        assert_eq!((bytes.len() - CELLS) % 64, 0);
        assert_eq!(Provenance::from_npy(&bytes).unwrap(), p);
        // The sample (theta_h 1 deg -> bin 9, theta_d 40, phi_d 15) and its mirror 165.
        let at = |k| {
            p.cells[Bin {
                theta_h_i: 9,
                theta_d_i: 40,
                phi_d_i: k,
            }
            .index()]
        };
        assert_eq!(
            (at(15), at(165), at(16)),
            (
                CellOrigin::Measured,
                CellOrigin::Measured,
                CellOrigin::Interpolated
            )
        );
        let mut prior = Provenance::new(&samples, &extrapolated);
        prior.mark_prior();
        assert_eq!(
            (prior.counts(), prior.prior_count()),
            ((2, CELLS - 3, 1), 1)
        );
        assert_eq!(prior.cells[CELLS - 1], CellOrigin::Prior);
        assert_eq!(Provenance::from_npy(&prior.to_npy()).unwrap(), prior);
        let mut bad = bytes.clone();
        *bad.last_mut().unwrap() = 7;
        assert!(Provenance::from_npy(&bad)
            .unwrap_err()
            .to_string()
            .contains("unknown code 7"));
        assert!(Provenance::from_npy(&bytes[..1000])
            .unwrap_err()
            .to_string()
            .contains("cells"));
        assert!(Provenance::from_npy(&bytes[..100])
            .unwrap_err()
            .to_string()
            .contains("truncated"));
        assert_eq!(
            sidecar_path(Path::new("out/silver.binary")),
            Path::new("out/silver.provenance.npy")
        );
    }
}
