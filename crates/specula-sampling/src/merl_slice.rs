//! Reading only the characteristic slice of a MERL `.binary` file, in one sequential pass
//! with a fixed-size buffer: a 33 MB file costs its read time and a few kilobytes of memory,
//! so a folder of a hundred can be analysed in parallel with bounded memory.
//!
//! The slice is the cells `(theta_h_i, theta_d_j, phi_d bin 90)` of each channel
//! (the MERL layout of docs/book/src/design.md); their theta_h positions are the bin centres `(i + 0.5)^2 / 90`
//! degrees. The file's header and length are checked, and every value the slice uses.

use crate::column::scalar_of;
use crate::error::SamplingError;
use crate::slice::{CharacteristicSlice, THETA_D_COLUMNS, THETA_H_NODES};
use specula_core::merl::{
    check_header, theta_h_centre_deg, CHANNEL_SCALE, HEADER_BYTES, PHI_D_BINS, THETA_D_BINS,
    THETA_H_BINS,
};
use specula_core::Rgb;
use std::io::{BufReader, Read};
use std::path::Path;

/// The phi_d bin of the characteristic slice: `[90, 91)` degrees. By the isotropic symmetry
/// `f(phi_d) = f(180 - phi_d)` it stands for phi_d = 90 as well as bin 89 does.
pub const SLICE_PHI_D_BIN: usize = 90;

/// One run of phi_d values for a (theta_h, theta_d) pair: the unit the reader walks by.
const ROW_BYTES: usize = PHI_D_BINS * 8;
const READ_BUFFER_BYTES: usize = 1 << 20;

/// Reads the characteristic slice of a MERL `.binary` file (see the module documentation).
/// Errors name the file and the problem.
pub fn read_merl_slice(path: &Path) -> Result<CharacteristicSlice, SamplingError> {
    let file = std::fs::File::open(path).map_err(SamplingError::io(path, "open"))?;
    let length = file
        .metadata()
        .map_err(SamplingError::io(path, "read"))?
        .len();
    let mut reader = BufReader::with_capacity(READ_BUFFER_BYTES, file);

    let mut header = [0u8; HEADER_BYTES];
    let header_len = (length as usize).min(HEADER_BYTES);
    reader
        .read_exact(&mut header[..header_len])
        .map_err(SamplingError::io(path, "read"))?;
    check_header(&header[..header_len], length).map_err(|problem| SamplingError::Merl {
        path: path.to_path_buf(),
        problem,
    })?;

    // stored[c][j * THETA_H_NODES + i]: channel c's stored value at (theta_h i, theta_d j).
    let mut stored = vec![vec![0.0f64; THETA_H_NODES * THETA_D_COLUMNS]; 3];
    let mut row = [0u8; ROW_BYTES];
    for (c, plane) in stored.iter_mut().enumerate() {
        for i in 0..THETA_H_BINS {
            for j in 0..THETA_D_BINS {
                reader
                    .read_exact(&mut row)
                    .map_err(SamplingError::io(path, "read"))?;
                let at = 8 * SLICE_PHI_D_BIN;
                let value = f64::from_le_bytes(row[at..at + 8].try_into().expect("8 bytes"));
                if !value.is_finite() {
                    return Err(SamplingError::NonFinite {
                        path: path.to_path_buf(),
                        channel: ["red", "green", "blue"][c],
                        theta_h_i: i,
                        theta_d_i: j,
                        phi_d_i: SLICE_PHI_D_BIN,
                    });
                }
                plane[j * THETA_H_NODES + i] = value;
            }
        }
    }

    let values = (0..THETA_H_NODES * THETA_D_COLUMNS)
        .map(|cell| {
            let v = [stored[0][cell], stored[1][cell], stored[2][cell]];
            (v.iter().all(|s| *s >= 0.0)).then(|| {
                scalar_of(Rgb::new(
                    v[0] * CHANNEL_SCALE[0],
                    v[1] * CHANNEL_SCALE[1],
                    v[2] * CHANNEL_SCALE[2],
                ))
            })
        })
        .collect();
    let theta_h_deg = (0..THETA_H_NODES).map(theta_h_centre_deg).collect();
    let material = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string());
    Ok(CharacteristicSlice::from_grid(
        material,
        theta_h_deg,
        values,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::merl::{Bin, MerlBrdf};

    /// A table whose slice cells hold a known function of the bin, and whose other cells
    /// hold something else, so that reading the wrong cell shows.
    fn table() -> MerlBrdf {
        let mut t = MerlBrdf::empty("t");
        for theta_h_i in 0..THETA_H_BINS {
            for theta_d_i in 0..THETA_D_BINS {
                for phi_d_i in [SLICE_PHI_D_BIN - 1, SLICE_PHI_D_BIN, SLICE_PHI_D_BIN + 1] {
                    let bin = Bin {
                        theta_h_i,
                        theta_d_i,
                        phi_d_i,
                    };
                    let v = if phi_d_i == SLICE_PHI_D_BIN {
                        (theta_h_i + 1000 * theta_d_i) as f64
                    } else {
                        -5.0
                    };
                    t.set_cell(bin.index(), Some(Rgb::new(v, 2.0 * v, 3.0 * v).abs()));
                }
            }
        }
        // One hole in the slice.
        t.set_cell(
            Bin {
                theta_h_i: 3,
                theta_d_i: 7,
                phi_d_i: SLICE_PHI_D_BIN,
            }
            .index(),
            None,
        );
        t
    }

    #[test]
    fn reads_the_slice_cells_and_their_centres() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("known.binary");
        let t = table();
        t.write(&path).unwrap();
        let slice = read_merl_slice(&path).unwrap();
        assert_eq!(slice.name(), "known");
        assert!((slice.theta_h_deg()[0] - 0.25 / 90.0).abs() < 1e-15);
        for (i, j) in [(0, 0), (89, 89), (10, 40), (45, 3)] {
            let cell = t.cell(
                Bin {
                    theta_h_i: i,
                    theta_d_i: j,
                    phi_d_i: SLICE_PHI_D_BIN,
                }
                .index(),
            );
            let expected = scalar_of(cell.unwrap());
            let got = slice.value(j, i).unwrap();
            assert!(
                (got - expected).abs() <= 1e-12 * expected.max(1.0),
                "({i}, {j}): {got} vs {expected}"
            );
            assert!((got - 2.0 * (i + 1000 * j) as f64).abs() < 1e-6);
        }
        assert_eq!(slice.value(7, 3), None);
        assert_eq!(slice.column(7).unwrap().len(), THETA_H_NODES - 1);
    }

    #[test]
    fn broken_files_are_refused_with_their_name() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("broken.binary");
        let mut bytes = table().to_bytes();
        bytes.truncate(bytes.len() - 8);
        std::fs::write(&path, &bytes).unwrap();
        let err = format!("{:#}", read_merl_slice(&path).unwrap_err());
        assert!(
            err.contains("broken.binary") && err.contains("bytes"),
            "{err}"
        );

        std::fs::write(
            &path,
            [90i32, 90, 90]
                .iter()
                .flat_map(|d| d.to_le_bytes())
                .collect::<Vec<_>>(),
        )
        .unwrap();
        let err = format!("{:#}", read_merl_slice(&path).unwrap_err());
        assert!(err.contains("dimensions"), "{err}");

        let mut bytes = table().to_bytes();
        let at = HEADER_BYTES
            + 8 * Bin {
                theta_h_i: 2,
                theta_d_i: 2,
                phi_d_i: SLICE_PHI_D_BIN,
            }
            .index();
        bytes[at..at + 8].copy_from_slice(&f64::NAN.to_le_bytes());
        std::fs::write(&path, &bytes).unwrap();
        let err = format!("{:#}", read_merl_slice(&path).unwrap_err());
        assert!(
            err.contains("non-finite") && err.contains("theta_h 2"),
            "{err}"
        );

        let err = format!(
            "{:#}",
            read_merl_slice(&dir.path().join("none.binary")).unwrap_err()
        );
        assert!(err.contains("none.binary"), "{err}");
    }
}
