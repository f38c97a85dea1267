//! A BRDF into another file format (`specula convert`) and into an analytic material for
//! renderers (`specula fit`).

use crate::brdf::{brdf_arg, figures_dict};
use crate::errors::OrRaise;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use specula_formats::convert::{run_convert, ConvertRequest, CsvGrid};
use specula_formats::material_fit::FitChoice;
use specula_formats::rgl::RglResolution;
use specula_formats::{run_fit, FitExports, FitRequest};
use std::path::PathBuf;

/// Convert a BRDF into the format of `out`'s extension (`specula convert`): MERL `.binary`,
/// UTIA `.bin`, RGL `.bsdf` or samples `.csv`. `source` is a file, a preset name or a
/// model:name fit (a str or path); MERL cells and bin-centre samples are taken at
/// `phi_h_deg`; a continuous source written as CSV is sampled at `grid` (`"merl"` bin
/// centres or `"utia"` nodes); an RGL file is written with `rgl_elevations`,
/// `rgl_ndf_size` and `rgl_sample_size` (checked as the CLI checks them).
///
/// Returns `{"out", "format", "method", "measured", "not_measured"}`.
#[pyfunction]
#[pyo3(signature = (source, out, phi_h_deg = 45.0, grid = "merl",
    rgl_elevations = RglResolution::DEFAULT.elevations,
    rgl_ndf_size = RglResolution::DEFAULT.ndf_size,
    rgl_sample_size = RglResolution::DEFAULT.sample_size))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn convert<'py>(
    py: Python<'py>,
    source: PathBuf,
    out: PathBuf,
    phi_h_deg: f64,
    grid: &str,
    rgl_elevations: usize,
    rgl_ndf_size: usize,
    rgl_sample_size: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let request = ConvertRequest {
        input: source.to_string_lossy().into_owned(),
        output: out.clone(),
        phi_h_deg,
        csv_grid: grid.parse::<CsvGrid>().or_raise()?,
        rgl: RglResolution {
            elevations: rgl_elevations,
            ndf_size: rgl_ndf_size,
            sample_size: rgl_sample_size,
        },
    };
    request.validate().or_raise()?;
    let done = py.detach(|| run_convert(&request)).or_raise()?;
    let dict = PyDict::new(py);
    dict.set_item("out", out)?;
    dict.set_item("format", done.target.label())?;
    dict.set_item("method", done.method)?;
    dict.set_item("measured", done.measured)?;
    dict.set_item("not_measured", done.not_measured)?;
    Ok(dict)
}

/// Fit the analytic materials renderers have to a BRDF and export the best (`specula
/// fit`): `model` is `"conductor"`, `"coat"` or `"both"` (the one with the lower log_rmse
/// within `max_elevation_deg` is exported). `brdf` is a `Brdf`, a source or a table array,
/// tabulated at phi_h 45 deg first. The exports given are written: `out` (a material
/// `.toml`), `mitsuba` (a Mitsuba 3 scene), `pbrt` (a pbrt-v4 material), `gltf` (a glTF
/// document).
///
/// Returns `{"exported": the model exported, "reason": why, "notes": [what the exports need
/// said, as the CLI's notes], "fits": [{"model", "material" (the material
/// file's TOML), "within", "all"}, ...]}`, best first, the figures as `compare`'s.
#[pyfunction]
#[pyo3(signature = (brdf, model = "both", max_elevation_deg = 75.0, out = None, mitsuba = None,
    pbrt = None, gltf = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn fit<'py>(
    py: Python<'py>,
    brdf: &Bound<'py, PyAny>,
    model: &str,
    max_elevation_deg: f64,
    out: Option<PathBuf>,
    mitsuba: Option<PathBuf>,
    pbrt: Option<PathBuf>,
    gltf: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    let request = FitRequest {
        model: model.parse::<FitChoice>().or_raise()?,
        max_elevation_deg,
        exports: FitExports {
            out,
            mitsuba,
            pbrt,
            gltf,
        },
    };
    request.validate().or_raise()?;
    let name = brdf
        .extract::<PathBuf>()
        .map(|p| p.to_string_lossy().into_owned())
        .ok();
    let brdf = brdf_arg(brdf)?;
    let name = name.unwrap_or_else(|| brdf.name());
    let outcome = py
        .detach(|| run_fit(&request, brdf.as_ref(), &name))
        .or_raise()?;
    let fits = &outcome.fits;
    let dict = PyDict::new(py);
    dict.set_item("exported", outcome.exported().model.label())?;
    dict.set_item("reason", outcome.reason.to_string())?;
    dict.set_item("notes", &outcome.notes)?;
    let rows = fits
        .iter()
        .map(|fit| {
            let row = PyDict::new(py);
            row.set_item("model", fit.model.label())?;
            row.set_item("material", fit.material.to_toml_string())?;
            row.set_item("within", figures_dict(py, &fit.error_within)?)?;
            row.set_item("all", figures_dict(py, &fit.error_all)?)?;
            Ok(row)
        })
        .collect::<PyResult<Vec<_>>>()?;
    dict.set_item("fits", rows)?;
    Ok(dict)
}
