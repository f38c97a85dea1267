//! MERL tables as numpy arrays: `(90, 90, 180, 3)` float64, f_r in 1/sr, NaN where a cell is
//! not measured (docs/book/src/formats.md, "MERL files and error figures").

use crate::errors::{invalid, OrRaise};
use numpy::ndarray::{Array4, ArrayView4};
use numpy::{IntoPyArray, PyArray4, PyReadonlyArray4};
use pyo3::prelude::*;
use specula_core::merl::{Bin, PHI_D_BINS, THETA_D_BINS, THETA_H_BINS};
use specula_core::{MerlBrdf, Rgb};
use std::path::PathBuf;

/// The shape of a MERL table as an array: theta_h, theta_d, phi_d bins, then R, G, B.
pub(crate) const SHAPE: [usize; 4] = [THETA_H_BINS, THETA_D_BINS, PHI_D_BINS, 3];

/// The table as a `(90, 90, 180, 3)` array without a copy: the scaled planes become the
/// array's memory, the channel axis strided by a plane (`numpy` sees a transposed view).
pub(crate) fn to_array(py: Python<'_>, table: MerlBrdf) -> Bound<'_, PyArray4<f64>> {
    let planes = py.detach(|| table.into_planes_per_sr());
    let [nh, nd, np, channels] = SHAPE;
    Array4::from_shape_vec((channels, nh, nd, np), planes)
        .expect("into_planes_per_sr returns 3 planes of CELLS values")
        .permuted_axes([1, 2, 3, 0])
        .into_pyarray(py)
}

/// A table from a `(90, 90, 180, 3)` array of any strides: NaN (or a negative value) in any
/// channel marks the cell not measured.
pub(crate) fn from_array(view: ArrayView4<'_, f64>, name: &str) -> PyResult<MerlBrdf> {
    if view.shape() != SHAPE {
        return Err(invalid(format!(
            "a MERL table must have the shape (90, 90, 180, 3), got {:?}",
            view.shape()
        )));
    }
    Ok(MerlBrdf::from_fn(name, |index| {
        let bin = Bin::from_index(index);
        let at = |c| view[[bin.theta_h_i, bin.theta_d_i, bin.phi_d_i, c]];
        let value = Rgb::new(at(0), at(1), at(2));
        value.is_finite().then_some(value)
    }))
}

/// The array of a table that numpy hands in (float64, any layout).
pub(crate) fn table_of<'py>(array: &PyReadonlyArray4<'py, f64>, name: &str) -> PyResult<MerlBrdf> {
    let view = array.as_array();
    array.py().detach(|| from_array(view, name))
}

/// Read a MERL `.binary` file into a `(90, 90, 180, 3)` float64 array of f_r in 1/sr.
///
/// The header, the length and every value are checked (a bad file raises `SpeculaError`
/// naming it); cells not measured (a negative stored value) are NaN in all three channels.
/// The array's memory is the file's three planes, scaled: index it
/// `[theta_h_i, theta_d_i, phi_d_i, channel]` (docs/book/src/formats.md, "MERL files and error figures").
#[pyfunction]
pub(crate) fn read_merl(py: Python<'_>, path: PathBuf) -> PyResult<Bound<'_, PyArray4<f64>>> {
    let table = py.detach(|| MerlBrdf::read(&path)).or_raise()?;
    Ok(to_array(py, table))
}

/// Write a `(90, 90, 180, 3)` array of f_r in 1/sr as a MERL `.binary` file.
///
/// Cells with a NaN or a negative value in any channel are written as not measured (-1);
/// the others are stored divided by MERL's channel scales, so that `read_merl` gives them
/// back exactly as far as float64 division and multiplication allow.
#[pyfunction]
pub(crate) fn write_merl(path: PathBuf, array: PyReadonlyArray4<'_, f64>) -> PyResult<()> {
    let name = path
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let table = table_of(&array, &name)?;
    array.py().detach(|| table.write(&path)).or_raise()
}
