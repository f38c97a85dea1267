//! The probe and the k fit of paper 5.2 (`specula probe`, `specula fit-k`).

use crate::brdf::brdf_arg;
use crate::errors::{invalid, OrRaise};
use numpy::ndarray::Array2;
use numpy::{AllowTypeChange, IntoPyArray, PyArrayLike1, PyArrayLike2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyMapping};
use specula_core::request::THETA_H_SAMPLES;
use specula_core::sampling::Family;
use specula_core::{GridSpec, ProbeSpec, Rgb};
use specula_sampling::{fit_k as fit_k_hat, Probe};

/// `(N, 3)` rows of R, G, B as an array.
pub(crate) fn rgb_array<'py>(py: Python<'py>, rgb: &[Rgb]) -> Bound<'py, numpy::PyArray2<f64>> {
    Array2::from_shape_fn((rgb.len(), 3), |(i, c)| rgb[i][c]).into_pyarray(py)
}

/// `(N, 3)` rows of R, G, B from the array-like `column` (named `name` in the error) of that
/// shape; any other shape or dimension raises `SpeculaError`.
pub(crate) fn rgb_rows(name: &str, column: &Bound<'_, PyAny>, rows: usize) -> PyResult<Vec<Rgb>> {
    let wrong = |got: String| invalid(format!("{name} must have the shape ({rows}, 3), got {got}"));
    let rgb: PyArrayLike2<'_, f64, AllowTypeChange> = column
        .extract()
        .map_err(|_| wrong("an array of another dimension".into()))?;
    let rgb = rgb.as_array();
    if rgb.shape() != [rows, 3] {
        let [n, m] = [rgb.nrows(), rgb.ncols()];
        return Err(wrong(format!("({n}, {m})")));
    }
    Ok(rgb
        .rows()
        .into_iter()
        .map(|r| Rgb::new(r[0], r[1], r[2]))
        .collect())
}

/// A probe as the dict `{"theta_h_deg": (N,), "rgb": (N, 3)}`.
pub(crate) fn probe_dict<'py>(py: Python<'py>, probe: &Probe) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    dict.set_item("theta_h_deg", probe.theta_h_deg().to_vec().into_pyarray(py))?;
    dict.set_item("rgb", rgb_array(py, probe.rgb()))?;
    Ok(dict)
}

/// The family named by `name` (`exponential`, `power` or `base`).
pub(crate) fn family(name: &str) -> PyResult<Family> {
    name.parse().map_err(invalid)
}

/// Take the probe of paper 5.2 (`specula probe`): the dense theta_h column of `brdf` (a
/// `Brdf`, a source or a table array) at `theta_d_deg`, `phi_d_deg`, `phi_h_deg`, with
/// `samples` positions (each `None`: the paper's 40, 90, 45 deg and 90 positions) `theta_h = t^2 / 90` deg (MERL's square-root mapping); samples the
/// BRDF does not hold are left out. Returns `{"theta_h_deg": (N,), "rgb": (N, 3)}` (1/sr).
#[pyfunction]
#[pyo3(signature = (brdf, theta_d_deg = None, phi_d_deg = None, phi_h_deg = None, samples = None))]
pub(crate) fn probe<'py>(
    py: Python<'py>,
    brdf: &Bound<'py, PyAny>,
    theta_d_deg: Option<f64>,
    phi_d_deg: Option<f64>,
    phi_h_deg: Option<f64>,
    samples: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let brdf = brdf_arg(brdf)?;
    let paper = ProbeSpec::paper();
    let settings = ProbeSpec {
        theta_d_deg: theta_d_deg.unwrap_or(paper.theta_d_deg),
        phi_d_deg: phi_d_deg.unwrap_or(paper.phi_d_deg),
        phi_h_deg: phi_h_deg.unwrap_or(paper.phi_h_deg),
        samples: samples.unwrap_or(paper.samples),
    };
    settings.validate().or_raise()?;
    let probe = py
        .detach(|| Probe::take(brdf.as_ref(), &settings))
        .or_raise()?;
    probe_dict(py, &probe)
}

/// A probe from a mapping with `theta_h_deg` (N,) and `rgb` (N, 3), checked as the CLI
/// checks a probe file (increasing theta_h in [0, 90], finite non-negative values).
pub(crate) fn probe_of(probe: &Bound<'_, PyMapping>) -> PyResult<Probe> {
    let theta_h: PyArrayLike1<'_, f64, AllowTypeChange> =
        probe.get_item("theta_h_deg")?.extract()?;
    let theta_h = theta_h.as_array().to_vec();
    let rgb = rgb_rows("rgb", &probe.get_item("rgb")?, theta_h.len())?;
    Probe::new(theta_h, rgb).or_raise()
}

/// Fit k of a theta_h sampling function to a probe (paper 5.2, `specula fit-k`): `probe` is
/// a mapping with `theta_h_deg` and `rgb` (as `probe()` returns). The error of a candidate
/// k re-interpolates the probe through the function's `samples` positions (`None`: the
/// paper's 30 theta_h of the main grid, `GridSpec::paper`; docs/book/src/design.md); k-hat
/// minimises it. Returns `{"k", "error", "family", "samples", "evaluations",
/// "theta_h_deg"}` (the positions of k-hat, degrees, ready for `plan(theta_h_deg=...)`).
#[pyfunction]
#[pyo3(signature = (probe, family = "exponential", samples = None))]
pub(crate) fn fit_k<'py>(
    py: Python<'py>,
    probe: &Bound<'py, PyMapping>,
    family: &str,
    samples: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let family = self::family(family)?;
    let samples = THETA_H_SAMPLES
        .check(
            "samples",
            samples.unwrap_or(GridSpec::paper().theta_h_samples),
        )
        .or_raise()?;
    let probe = probe_of(probe)?;
    let fit = py
        .detach(|| fit_k_hat(&probe.column(), family, samples))
        .or_raise()?;
    let dict = PyDict::new(py);
    dict.set_item("k", fit.function.k)?;
    dict.set_item("error", fit.error)?;
    dict.set_item("family", family.name())?;
    dict.set_item("samples", samples)?;
    dict.set_item("evaluations", fit.evaluations)?;
    dict.set_item(
        "theta_h_deg",
        fit.function.positions_deg(samples).into_pyarray(py),
    )?;
    Ok(dict)
}
