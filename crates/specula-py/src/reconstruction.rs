//! Reconstruction from sample arrays (`specula reconstruct`) and the accuracy harness
//! (`specula evaluate`).

use crate::brdf::{brdf_arg, figures_dict};
use crate::errors::{invalid, OrRaise};
use crate::interrupt::{self, Stop};
use crate::plan::{device, GridArgs};
use crate::sampling::{rgb_array, rgb_rows};
use crate::table::to_array;
use numpy::ndarray::Array3;
use numpy::{AllowTypeChange, IntoPyArray, PyArray3, PyArray4, PyArrayLike1};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyMapping};
use specula_accuracy::merl_prior::basis_for;
use specula_accuracy::{run_evaluate, EvaluateRequest, Evaluated};
use specula_core::merl::{MerlBrdf, PHI_D_BINS, THETA_D_BINS, THETA_H_BINS};
use specula_core::progress::NoProgress;
use specula_core::{HalfDiff, Rgb, Sample};
use specula_reconstruct::provenance::{sidecar_path, Provenance};
use specula_reconstruct::{run_reconstruct, Method, ReconstructRequest};
use std::path::PathBuf;

/// The angle columns of a samples dict, in the order of `HalfDiff::from_degrees`.
const ANGLES: [&str; 4] = ["theta_h_deg", "phi_h_deg", "theta_d_deg", "phi_d_deg"];

/// Samples as the dict `{"theta_h_deg", "phi_h_deg", "theta_d_deg", "phi_d_deg": (N,),
/// "rgb": (N, 3)}` (degrees, 1/sr): the columns of a samples CSV.
pub(crate) fn samples_dict<'py>(
    py: Python<'py>,
    samples: &[Sample],
) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    let angle = |f: fn(&HalfDiff) -> f64| {
        samples
            .iter()
            .map(|s| f(&s.hd).to_degrees())
            .collect::<Vec<f64>>()
            .into_pyarray(py)
    };
    dict.set_item(ANGLES[0], angle(|hd| hd.theta_h))?;
    dict.set_item(ANGLES[1], angle(|hd| hd.phi_h))?;
    dict.set_item(ANGLES[2], angle(|hd| hd.theta_d))?;
    dict.set_item(ANGLES[3], angle(|hd| hd.phi_d))?;
    let rgb: Vec<_> = samples.iter().map(|s| s.value).collect();
    dict.set_item("rgb", rgb_array(py, &rgb))?;
    let noise: Option<Vec<Rgb>> = samples.iter().map(|s| s.noise_rel).collect();
    if let Some(noise) = noise.filter(|n| !n.is_empty()) {
        dict.set_item(NOISE, rgb_array(py, &noise))?;
    }
    Ok(dict)
}

/// The optional sample column of each value's relative noise per channel (its HDR merge's,
/// through the colour matrix), as a measurement session records it.
const NOISE: &str = "noise_rel";

/// Samples from a mapping with the keys of [`samples_dict`].
pub(crate) fn samples_of(samples: &Bound<'_, PyMapping>) -> PyResult<Vec<Sample>> {
    let mut angles = Vec::with_capacity(4);
    for key in ANGLES {
        let column: PyArrayLike1<'_, f64, AllowTypeChange> = samples.get_item(key)?.extract()?;
        angles.push(column.as_array().to_vec());
    }
    let n = angles[0].len();
    if angles.iter().any(|a| a.len() != n) {
        return Err(invalid(format!(
            "the sample columns {ANGLES:?} must have the same length"
        )));
    }
    let rgb = rgb_rows("rgb", &samples.get_item("rgb")?, n)?;
    let noise = match samples.contains(NOISE)? {
        true => Some(rgb_rows(NOISE, &samples.get_item(NOISE)?, n)?),
        false => None,
    };
    Ok((0..n)
        .map(|i| {
            let hd = HalfDiff::from_degrees(angles[0][i], angles[1][i], angles[2][i], angles[3][i]);
            let sample = Sample::new(hd, rgb[i]);
            match &noise {
                Some(noise) => sample.with_noise_rel(noise[i]),
                None => sample,
            }
        })
        .collect())
}

/// Cell origins as a uint8 `(90, 90, 180)` array: 0 measured, 1 interpolated, 2 extrapolated, 3 from the prior.
fn provenance_array<'py>(py: Python<'py>, provenance: &Provenance) -> Bound<'py, PyArray3<u8>> {
    let codes: Vec<u8> = provenance.cells.iter().map(|&c| c as u8).collect();
    Array3::from_shape_vec((THETA_H_BINS, THETA_D_BINS, PHI_D_BINS), codes)
        .expect("one origin per cell")
        .into_pyarray(py)
}

/// The provenance of a reconstructed MERL file: its `OUT.provenance.npy` sidecar (written by
/// `specula reconstruct` and `specula measure`) as a uint8 `(90, 90, 180)` array (0 measured,
/// 1 interpolated, 2 extrapolated, 3 from the prior), or None when the file has no sidecar.
#[pyfunction]
pub(crate) fn read_provenance(
    py: Python<'_>,
    merl_path: PathBuf,
) -> PyResult<Option<Bound<'_, PyArray3<u8>>>> {
    let sidecar = sidecar_path(&merl_path);
    if !sidecar.exists() {
        return Ok(None);
    }
    let provenance = Provenance::read(&sidecar).or_raise()?;
    Ok(Some(provenance_array(py, &provenance)))
}

/// The standard uncertainty (k = 1) of a reconstructed MERL file: its
/// `OUT.uncertainty.binary` sidecar (written by `specula reconstruct` and `specula measure`)
/// as a `(90, 90, 180, 3)` float64 array in 1/sr, NaN where a cell has none, or None when the
/// file has no sidecar.
#[pyfunction]
pub(crate) fn read_uncertainty(
    py: Python<'_>,
    merl_path: PathBuf,
) -> PyResult<Option<Bound<'_, PyArray4<f64>>>> {
    let sidecar = specula_reconstruct::uncertainty::sidecar_path(&merl_path);
    if !sidecar.exists() {
        return Ok(None);
    }
    let table = py.detach(|| MerlBrdf::read(&sidecar)).or_raise()?;
    Ok(Some(to_array(py, table)))
}

/// The reconstruction method named `name` (`lobe`, `log` or `linear`).
fn method(name: &str) -> PyResult<Method> {
    name.parse().map_err(invalid)
}

/// Reconstruct a full MERL table from sparse samples (paper 5.3, `specula reconstruct`):
/// `samples` is a mapping of arrays `theta_h_deg`, `phi_h_deg`, `theta_d_deg`, `phi_d_deg`
/// (N,) and `rgb` (N, 3) in 1/sr, and optionally `noise_rel` (N, 3), each value's relative
/// standard deviation per channel from the camera's noise, which the `lobe` method smooths the residual
/// within (as `evaluate(...)["samples"]` and `read_session` return). `method`: `"lobe"` (ours), `"prior"` (lobe blended with the MERL-100 prior as far
/// as the samples trust it), `"log"` or `"linear"` (the paper's baseline). Samples
/// that measure both halves of phi_d (0-90 and 90-180 deg, two positions each at least) are
/// reconstructed half by half, as `specula reconstruct` does. `out`: a MERL `.binary` to
/// write the table to, with its provenance beside it (`OUT.provenance.npy`), as
/// `specula reconstruct --out`.
///
/// Returns `{"table": (90, 90, 180, 3), "provenance": uint8 (90, 90, 180) (0 measured, 1
/// interpolated, 2 extrapolated, 3 from the prior), "lattice_shape", "measured_nodes", "filled_nodes",
/// "lobe"}` (`lobe`: the fitted lobe's `alpha`, `gamma`, `diffuse`, or None).
#[pyfunction]
#[pyo3(signature = (samples, method = "lobe", out = None))]
pub(crate) fn reconstruct<'py>(
    py: Python<'py>,
    samples: &Bound<'py, PyMapping>,
    method: &str,
    out: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    let request = ReconstructRequest {
        method: self::method(method)?,
        deblur: false,
        out,
    };
    request.validate().or_raise()?;
    let samples = samples_of(samples)?;
    let prior = basis_for(request.method).or_raise()?;
    let r = py
        .detach(|| {
            let none = None::<&dyn specula_core::capture::CaptureResponse>;
            run_reconstruct(&request, &samples, none, prior.as_deref())
        })
        .or_raise()?;
    let dict = PyDict::new(py);
    dict.set_item("provenance", provenance_array(py, &r.provenance))?;
    dict.set_item("lattice_shape", r.lattice_shape.to_vec())?;
    dict.set_item("measured_nodes", r.measured_nodes)?;
    dict.set_item("filled_nodes", r.filled_nodes)?;
    match r.lobe {
        Some(lobe) => {
            let fitted = PyDict::new(py);
            fitted.set_item("alpha", lobe.shape.alpha)?;
            fitted.set_item("gamma", lobe.shape.gamma)?;
            fitted.set_item("diffuse", lobe.diffuse.to_array().to_vec())?;
            dict.set_item("lobe", fitted)?;
        }
        None => dict.set_item("lobe", py.None())?,
    }
    dict.set_item("table", to_array(py, r.brdf))?;
    Ok(dict)
}

/// The accuracy harness (`specula evaluate --truth`): plan the measurement of a known BRDF
/// (`truth`: a `Brdf`, a source or a table array) as the paper does (5.3) — theta_h at the
/// `theta_h_samples` positions of the `family` function with `k` (default: k-hat fitted to
/// the material's probe), or with `placement="probe"` the least-error placement on the
/// probe; theta_d and phi_d in steps at `phi_h_deg`, the grid arguments as `plan`'s (default
/// the recommended grid) — keep the samples `device` reaches, take them without noise,
/// reconstruct with `method` (by halves of phi_d when the samples measure both) and compare
/// with the truth tabulated at the bin centres. With `through_instrument=True` the samples
/// are taken through the device's response (the light's disk blurs them) and the method
/// reconstructs through it, as `specula evaluate --through-instrument`.
///
/// Returns `{"name", "k" (None for the probe placement), "measured", "within", "all",
/// "samples"}`: the figures as `compare`'s, over the cells within `max_elevation_deg` and
/// over all, and the simulated samples (a dict for `reconstruct`). Ctrl-C returns at once.
#[pyfunction]
#[pyo3(signature = (truth, method = "lobe", k = None, placement = "function",
    family = "exponential", grid_preset = None, theta_h_samples = None, theta_d_step_deg = None,
    phi_d_step_deg = None, phi_d_span = None, phi_h_deg = None, max_elevation_deg = 75.0,
    device = None, through_instrument = false))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn evaluate<'py>(
    py: Python<'py>,
    truth: &Bound<'py, PyAny>,
    method: &str,
    k: Option<f64>,
    placement: &str,
    family: &str,
    grid_preset: Option<&str>,
    theta_h_samples: Option<usize>,
    theta_d_step_deg: Option<&Bound<'py, PyAny>>,
    phi_d_step_deg: Option<f64>,
    phi_d_span: Option<&str>,
    phi_h_deg: Option<f64>,
    max_elevation_deg: f64,
    device: Option<PathBuf>,
    through_instrument: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let request = EvaluateRequest {
        method: self::method(method)?,
        k,
        placement: placement.parse().or_raise()?,
        family: crate::sampling::family(family)?,
        grid: GridArgs {
            grid_preset,
            theta_h_samples,
            theta_d_step_deg,
            phi_d_step_deg,
            phi_d_span,
            phi_h_deg,
        }
        .request()?,
        max_elevation_deg,
        through_instrument,
    };
    request.validate().or_raise()?;
    let truths = [("given".to_string(), brdf_arg(truth)?)];
    let device = self::device(device)?;
    // Abandoned on Ctrl-C: the call returns at once, and the evaluation left on its thread
    // stops before its reconstruction.
    let mut evaluation = interrupt::run(py, Stop::Abandon, move |stop| {
        run_evaluate(&request, &truths, &device, &stop, &NoProgress)
    })?
    .or_raise()?;
    let (_, evaluated) = evaluation
        .rows
        .pop()
        .ok_or_else(|| invalid("the truth was not evaluated"))?;
    let Evaluated {
        name,
        k,
        samples,
        accuracy,
    } = evaluated;
    let dict = PyDict::new(py);
    dict.set_item("name", name)?;
    dict.set_item("k", k)?;
    dict.set_item("measured", samples.len())?;
    dict.set_item("within", figures_dict(py, &accuracy.within)?)?;
    dict.set_item("all", figures_dict(py, &accuracy.all)?)?;
    dict.set_item("samples", samples_dict(py, &samples)?)?;
    Ok(dict)
}
