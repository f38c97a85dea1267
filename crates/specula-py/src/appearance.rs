//! `specula.appearance`: gloss, haze, DOI and multi-angle colour of BRDFs, the figures of
//! `specula appearance` (specula-appearance computes them; this converts).

use crate::brdf::brdf_arg;
use crate::errors::OrRaise;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use specula_appearance::figures::{column_values, csv_header};
use specula_appearance::{Appearance, Options};
use specula_core::Brdf;
use specula_report::appearance::extrapolated_cells;
use std::path::PathBuf;
use std::sync::Arc;

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
/// with an `OUT.provenance.npy` sidecar has its extrapolated cells flagged, as in the CLI.
/// A figure that cannot be given (a colour reading on an unmeasured cell) is None.
#[pyfunction]
#[pyo3(signature = (brdf, against = None, resolution_deg = None))]
pub(crate) fn appearance<'py>(
    py: Python<'py>,
    brdf: &Bound<'py, PyAny>,
    against: Option<&Bound<'py, PyAny>>,
    resolution_deg: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    Options {
        extrapolated: None,
        resolution_deg,
    }
    .validate()
    .or_raise()?;
    let reference = against
        .map(|against| figures_of(py, against, resolution_deg))
        .transpose()?;
    let many = brdf.cast::<PyList>().is_ok() || brdf.cast::<PyTuple>().is_ok();
    let items: Vec<Bound<'py, PyAny>> = if many {
        brdf.try_iter()?.collect::<PyResult<_>>()?
    } else {
        vec![brdf.clone()]
    };
    let mut dicts = Vec::with_capacity(items.len());
    for item in &items {
        let (name, figures) = figures_of(py, item, resolution_deg)?;
        dicts.push(figures_dict(
            py,
            &name,
            &figures,
            reference.as_ref().map(|r| &r.1),
        )?);
    }
    if many {
        Ok(PyList::new(py, dicts)?.into_any())
    } else {
        Ok(dicts.pop().expect("one BRDF").into_any())
    }
}

/// The BRDF's name and figures, with the extrapolated cells of a `.binary` source's
/// provenance sidecar.
fn figures_of(
    py: Python<'_>,
    value: &Bound<'_, PyAny>,
    resolution_deg: Option<f64>,
) -> PyResult<(String, Appearance)> {
    let brdf: Arc<dyn Brdf> = brdf_arg(value)?;
    let extrapolated = match value.extract::<PathBuf>() {
        Ok(path) => extrapolated_cells(&path.to_string_lossy()).or_raise()?,
        Err(_) => None,
    };
    let options = Options {
        extrapolated,
        resolution_deg,
    };
    let figures = py.detach(|| specula_appearance::appearance(brdf.as_ref(), &options));
    Ok((brdf.name(), figures))
}

/// The figures as a dict keyed by the CSV's column names (None where unknown).
fn figures_dict<'py>(
    py: Python<'py>,
    name: &str,
    figures: &Appearance,
    reference: Option<&Appearance>,
) -> PyResult<Bound<'py, PyDict>> {
    let differences = reference.map(|r| figures.against(r));
    let dict = PyDict::new(py);
    dict.set_item("name", name)?;
    let columns = csv_header(differences.is_some()).into_iter().skip(1);
    for (column, value) in columns.zip(column_values(figures, differences.as_ref())) {
        dict.set_item(column, value)?;
    }
    let warnings: Vec<String> = figures.warnings.iter().map(|w| w.to_string()).collect();
    dict.set_item("warnings", warnings)?;
    Ok(dict)
}
