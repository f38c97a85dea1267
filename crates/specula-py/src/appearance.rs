//! `specula.appearance`: gloss, haze, DOI and multi-angle colour of BRDFs, the figures of
//! `specula appearance` (specula-appearance computes them; this converts).

use crate::brdf::brdf_arg;
use crate::errors::OrRaise;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use specula_appearance::figures::{column_values, csv_header};
use specula_appearance::uncertainty::column_names;
use specula_report::{run_appearance, AppearanceInput, AppearanceRequest, AppearanceRow};
use std::path::PathBuf;

/// The appearance figures of `brdf`, as `specula appearance --csv` gives them, in a dict
/// keyed by its column names: `gloss_20`, `gloss_60`, `gloss_85` (GU, ISO 2813 / ASTM
/// D523), `haze` and `doi` (ASTM E430 at 30 deg), `haze_20` (ISO 13803), `haze_d4039`
/// (ASTM D4039, `gloss_60 - gloss_20`), CIELAB under D65
/// `L_g`, `a_g`, `b_g` at the aspecular angles g = 15, 25, 45, 75, 110 deg, and
/// `flop_index`; plus `name` (the BRDF's) and `warnings` (the CLI's warning lines).
///
/// `brdf` is a `Brdf`, a source for `load` (str or path) or a `(90, 90, 180, 3)` array; a
/// list of them gives a list of dicts. With `against` (one BRDF of the same kinds) each
/// dict also holds the differences to it: `d_gloss_20` ... `d_haze_20`, `d_haze_d4039`, `d_flop_index`
/// (material minus reference) and CIEDE2000 `de00_g` per aspecular angle.
/// `resolution_deg` (in (0, 90]) is the measuring instrument's angular resolution: figures
/// that read the BRDF at a finer angle get a warning. A MERL `.binary` given by its path
/// with an `OUT.provenance.npy` sidecar has its extrapolated cells flagged, and one with an
/// `OUT.uncertainty.binary` sidecar gets `U_<figure>` keys (expanded, k = 2), as in the CLI.
/// A figure that cannot be given (a colour reading on an unmeasured cell) is None.
#[pyfunction]
#[pyo3(signature = (brdf, against = None, resolution_deg = None))]
pub(crate) fn appearance<'py>(
    py: Python<'py>,
    brdf: &Bound<'py, PyAny>,
    against: Option<&Bound<'py, PyAny>>,
    resolution_deg: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let many = brdf.cast::<PyList>().is_ok() || brdf.cast::<PyTuple>().is_ok();
    let items: Vec<Bound<'py, PyAny>> = if many {
        brdf.try_iter()?.collect::<PyResult<_>>()?
    } else {
        vec![brdf.clone()]
    };
    let request = AppearanceRequest {
        brdfs: items.iter().map(input).collect::<PyResult<_>>()?,
        against: against.map(input).transpose()?,
        resolution_deg,
        tolerances: None,
    };
    request.validate().or_raise()?;
    let table = py.detach(|| run_appearance(&request)).or_raise()?;
    let skip = usize::from(table.with_reference);
    let mut dicts = table.rows[skip..]
        .iter()
        .map(|row| figures_dict(py, row))
        .collect::<PyResult<Vec<_>>>()?;
    if many {
        Ok(PyList::new(py, dicts)?.into_any())
    } else {
        Ok(dicts.pop().expect("one BRDF").into_any())
    }
}

/// A Python BRDF argument as the request's input: the file it names, when it names one,
/// has its sidecars read as the CLI reads them.
fn input(value: &Bound<'_, PyAny>) -> PyResult<AppearanceInput> {
    let brdf = brdf_arg(value)?;
    let path = value.extract::<PathBuf>().ok();
    Ok(AppearanceInput {
        label: path
            .as_ref()
            .map_or_else(|| brdf.name(), |p| p.to_string_lossy().into_owned()),
        brdf,
        path,
    })
}

/// A row's figures as a dict keyed by the CSV's column names (None where unknown), with
/// `U_<figure>` where the row has its expanded uncertainty.
fn figures_dict<'py>(py: Python<'py>, row: &AppearanceRow) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    dict.set_item("name", &row.name)?;
    let columns: Vec<String> = csv_header(row.differences.is_some())
        .into_iter()
        .skip(1)
        .collect();
    for (column, value) in columns
        .iter()
        .zip(column_values(&row.figures, row.differences.as_ref()))
    {
        dict.set_item(column, value)?;
    }
    if let Some(expanded) = &row.expanded {
        let figure_columns = &csv_header(false)[1..];
        for (column, u) in column_names(figure_columns).into_iter().zip(expanded) {
            dict.set_item(column, *u)?;
        }
    }
    let warnings: Vec<String> = row.figures.warnings.iter().map(|w| w.to_string()).collect();
    dict.set_item("warnings", warnings)?;
    Ok(dict)
}
