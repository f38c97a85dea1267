//! `specula.Brdf`: any BRDF Specula reads, evaluated at numpy arrays; `load` and `compare`.

use crate::errors::{invalid, OrRaise};
use crate::table::{table_of, to_array};
use glam::DVec3;
use numpy::ndarray::{ArrayD, ArrayView2, ArrayViewD, Axis, CowArray, Ix2, IxDyn};
use numpy::{AllowTypeChange, IntoPyArray, PyArray4, PyArrayDyn, PyArrayLikeDyn, PyReadonlyArray4};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;
use specula_core::compare::ErrorFigures;
use specula_core::request::ELEVATION_DEG;
use specula_core::tabulate::tabulate;
use specula_core::{Brdf, HalfDiff, MerlBrdf};
use std::path::PathBuf;
use std::sync::Arc;

/// Largest distance of a direction's length from 1 that `eval` accepts.
const UNIT_TOLERANCE: f64 = 1e-6;

/// A BRDF: an analytic material, a measured table, a model fit or a reconstruction.
///
/// Made by `specula.load(source)`. Values are f_r in 1/sr per RGB channel; a measured
/// table answers NaN where its cell is not measured, and every BRDF answers 0 at or below
/// the horizon.
#[pyclass(name = "Brdf", module = "specula", frozen)]
pub(crate) struct PyBrdf {
    pub(crate) inner: Arc<dyn Brdf>,
}

#[pymethods]
impl PyBrdf {
    /// The BRDF's short name (a preset, a file's stem, a fit's material).
    #[getter]
    fn name(&self) -> String {
        self.inner.name()
    }

    fn __repr__(&self) -> String {
        format!("specula.Brdf({:?})", self.inner.name())
    }

    /// f_r (1/sr) at direction pairs: `wi` (towards the light) and `wo` (towards the camera)
    /// are `(N, 3)` arrays of unit vectors in the sample frame (z along the normal), or one
    /// direction each as `(3,)`; returns an `(N, 3)` array of R, G, B, or `(3,)` for one
    /// pair. Runs in parallel without the GIL; C-contiguous float64 inputs are read in
    /// place. A row whose length is not within 1e-6 of 1 (NaN included) raises
    /// `SpeculaError` naming the first.
    fn eval<'py>(
        &self,
        py: Python<'py>,
        wi: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
        wo: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let (wi, wo) = (wi.as_array(), wo.as_array());
        let one_pair = wi.ndim() == 1 && wo.ndim() == 1;
        let shapes = || {
            invalid(format!(
                "wi and wo must be (3,) directions or (N, 3) arrays of the same N, got {:?} and {:?}",
                wi.shape(),
                wo.shape()
            ))
        };
        let (Some(wi), Some(wo)) = (direction_rows(&wi), direction_rows(&wo)) else {
            return Err(shapes());
        };
        if wi.nrows() != wo.nrows() {
            return Err(shapes());
        }
        let (wi, wo) = (wi.as_standard_layout(), wo.as_standard_layout());
        let (wi, wo) = (directions(&wi), directions(&wo));
        let brdf = self.inner.as_ref();
        let values = py.detach(|| eval_pairs(brdf, wi, wo))?;
        let shape = if one_pair {
            vec![3]
        } else {
            vec![values.len() / 3, 3]
        };
        Ok(ArrayD::from_shape_vec(IxDyn(&shape), values)
            .expect("3 values per pair")
            .into_pyarray(py))
    }

    /// f_r (1/sr) at half-difference angles in degrees (Rusinkiewicz 1998; docs/book/src/design.md):
    /// the four arguments broadcast against each other as numpy's do; returns an array of
    /// their common shape plus a last axis of R, G, B.
    #[pyo3(signature = (theta_h_deg, theta_d_deg, phi_d_deg, phi_h_deg = None))]
    fn eval_half_diff<'py>(
        &self,
        py: Python<'py>,
        theta_h_deg: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
        theta_d_deg: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
        phi_d_deg: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
        phi_h_deg: Option<PyArrayLikeDyn<'py, f64, AllowTypeChange>>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let zero = ArrayD::<f64>::zeros(IxDyn(&[]));
        let views = [
            theta_h_deg.as_array(),
            theta_d_deg.as_array(),
            phi_d_deg.as_array(),
            match &phi_h_deg {
                Some(phi_h) => phi_h.as_array(),
                None => zero.view(),
            },
        ];
        let shape = broadcast_shape(&views)?;
        let columns: Vec<Vec<f64>> = views
            .iter()
            .map(|v| {
                v.broadcast(IxDyn(&shape))
                    .expect("broadcast_shape checked it")
                    .iter()
                    .copied()
                    .collect()
            })
            .collect();
        let brdf = self.inner.as_ref();
        let values = py.detach(|| {
            let mut out = vec![0.0; 3 * columns[0].len()];
            out.par_chunks_mut(3)
                .enumerate()
                .with_min_len(4096)
                .for_each(|(i, out)| {
                    let hd = HalfDiff::from_degrees(
                        columns[0][i],
                        columns[3][i],
                        columns[1][i],
                        columns[2][i],
                    );
                    out.copy_from_slice(&rgb_or_nan(brdf.eval_half_diff(hd)));
                });
            out
        });
        let mut out_shape = shape;
        out_shape.push(3);
        Ok(ArrayD::from_shape_vec(IxDyn(&out_shape), values)
            .expect("3 values per configuration")
            .into_pyarray(py))
    }

    /// The BRDF tabulated at the MERL bin centres (`specula tabulate`): a `(90, 90, 180, 3)`
    /// array, NaN where it does not answer. `phi_h_deg` matters only for anisotropic
    /// materials.
    #[pyo3(signature = (phi_h_deg = 0.0))]
    fn tabulate<'py>(&self, py: Python<'py>, phi_h_deg: f64) -> Bound<'py, PyArray4<f64>> {
        let brdf = self.inner.as_ref();
        let table = py.detach(|| tabulate(brdf, phi_h_deg.to_radians()));
        to_array(py, table)
    }
}

/// Direction pairs a rayon task takes: enough to amortise the scheduling.
const PAIRS_PER_TASK: usize = 2048;

/// Direction pairs a task checks and then evaluates in one [`Brdf::eval_pairs`] call: few
/// enough that their rows, values and results stay in the L1 cache between the two.
const PAIRS_PER_CALL: usize = 256;

/// The rows of a standard-layout `(N, 3)` array as vectors, in place.
fn directions<'a>(rows: &'a CowArray<'_, f64, Ix2>) -> &'a [DVec3] {
    bytemuck::cast_slice(rows.as_slice().expect("standard layout"))
}

/// Directions as rows: a `(3,)` array as one row, an `(N, 3)` array as it is; `None` for
/// any other shape.
fn direction_rows<'a>(array: &'a ArrayViewD<'a, f64>) -> Option<ArrayView2<'a, f64>> {
    let rows = match array.ndim() {
        1 => array
            .view()
            .insert_axis(Axis(0))
            .into_dimensionality::<Ix2>()
            .ok()?,
        2 => array.view().into_dimensionality::<Ix2>().ok()?,
        _ => return None,
    };
    (rows.ncols() == 3).then_some(rows)
}

/// f_r at the direction pairs `(wi[k], wo[k])`, R, G, B a row, NaN where the BRDF does not
/// answer: tasks of pairs in parallel, each checking runs of pairs (unit length) and
/// evaluating them with [`Brdf::eval_pairs`] while in cache, its values written once into
/// the result (which is not zeroed first). A direction that is not a unit vector fails the
/// call, naming the first such row of `wi`, else of `wo`.
fn eval_pairs(brdf: &dyn Brdf, wi: &[DVec3], wo: &[DVec3]) -> PyResult<Vec<f64>> {
    let len = 3 * wi.len();
    let mut out = Vec::with_capacity(len);
    let not_unit = out.spare_capacity_mut()[..len]
        .par_chunks_mut(3 * PAIRS_PER_TASK)
        .zip(
            wi.par_chunks(PAIRS_PER_TASK)
                .zip(wo.par_chunks(PAIRS_PER_TASK)),
        )
        .enumerate()
        .map_init(Vec::new, |values, (task, (out, (wi, wo)))| {
            let runs = wi.chunks(PAIRS_PER_CALL).zip(wo.chunks(PAIRS_PER_CALL));
            for (run, ((wi_run, wo_run), out)) in
                runs.zip(out.chunks_mut(3 * PAIRS_PER_CALL)).enumerate()
            {
                if first_not_unit(wi_run).is_some() || first_not_unit(wo_run).is_some() {
                    // The task's first rows that are not unit vectors, from this run on.
                    let first = run * PAIRS_PER_CALL;
                    let offset = task * PAIRS_PER_TASK + first;
                    return [&wi[first..], &wo[first..]]
                        .map(|rows| first_not_unit(rows).map(|row| offset + row));
                }
                values.clear();
                values.resize(wi_run.len(), None);
                brdf.eval_pairs(wi_run, wo_run, values);
                for (out, value) in out.chunks_exact_mut(3).zip(values.iter()) {
                    for (out, value) in out.iter_mut().zip(rgb_or_nan(*value)) {
                        out.write(value);
                    }
                }
            }
            [None, None]
        })
        .reduce(
            || [None, None],
            |a, b| [0, 1].map(|i| a[i].into_iter().chain(b[i]).min()),
        );
    for ((row, rows), name) in not_unit.into_iter().zip([wi, wo]).zip(["wi", "wo"]) {
        if let Some(row) = row {
            return Err(invalid(format!(
                "{name}[{row}] = {:?} is not a unit vector",
                rows[row].to_array()
            )));
        }
    }
    // SAFETY: every run of pairs passed its check (else the call failed above), so each
    // wrote all of its 3 values per pair, and the runs cover the first `len` values.
    unsafe { out.set_len(len) };
    Ok(out)
}

fn rgb_or_nan(value: Option<specula_core::Rgb>) -> [f64; 3] {
    value.map_or([f64::NAN; 3], |v| v.to_array())
}

/// The first of `rows` whose length is not within [`UNIT_TOLERANCE`] of 1 (NaN included).
/// The rows are scanned in one branch-free pass, then searched only when one fails.
fn first_not_unit(rows: &[DVec3]) -> Option<usize> {
    let (low, high) = (
        (1.0 - UNIT_TOLERANCE).powi(2),
        (1.0 + UNIT_TOLERANCE).powi(2),
    );
    let not_unit = |v: &DVec3| !(low..=high).contains(&v.length_squared());
    if rows.iter().fold(false, |any, v| any | not_unit(v)) {
        rows.iter().position(not_unit)
    } else {
        None
    }
}

/// The common shape of arrays under numpy's broadcasting rules.
fn broadcast_shape(views: &[ArrayViewD<'_, f64>]) -> PyResult<Vec<usize>> {
    let rank = views.iter().map(|v| v.ndim()).max().unwrap_or(0);
    let mut shape = vec![1; rank];
    for view in views {
        let offset = rank - view.ndim();
        for (axis, &len) in view.shape().iter().enumerate() {
            let common = &mut shape[offset + axis];
            if *common == 1 {
                *common = len;
            } else if len != 1 && len != *common {
                return Err(invalid(format!(
                    "the angle arrays do not broadcast together: shapes {:?}",
                    views.iter().map(|v| v.shape().to_vec()).collect::<Vec<_>>()
                )));
            }
        }
    }
    Ok(shape)
}

/// Load any BRDF the CLI takes (`specula-formats`' resolver): a preset or database name
/// (`silver-925`, `gold-polished`), a material `.toml`, a MERL `.binary`, an RGL `.bsdf`,
/// a UTIA `.bin`, a samples `.csv`, or a fit `model:name` (`sgd:`, `abc:`, `lafortune:`,
/// `nbrdf:`...). Raises `SpeculaError` with the CLI's message when it cannot.
#[pyfunction]
pub(crate) fn load(py: Python<'_>, source: PathBuf) -> PyResult<PyBrdf> {
    let spec = source.to_string_lossy().into_owned();
    let inner = py.detach(|| specula_formats::load_brdf(&spec)).or_raise()?;
    Ok(PyBrdf { inner })
}

/// A BRDF argument: a `Brdf`, a source for [`load`] (str or path), or a `(90, 90, 180, 3)`
/// array (a MERL table).
pub(crate) fn brdf_arg(value: &Bound<'_, PyAny>) -> PyResult<Arc<dyn Brdf>> {
    if let Ok(brdf) = value.cast::<PyBrdf>() {
        return Ok(brdf.get().inner.clone());
    }
    if let Ok(array) = value.extract::<PyReadonlyArray4<'_, f64>>() {
        return Ok(Arc::new(table_of(&array, "array")?));
    }
    if let Ok(source) = value.extract::<PathBuf>() {
        return Ok(load(value.py(), source)?.inner);
    }
    Err(invalid(format!(
        "expected a specula.Brdf, a BRDF source (str or path) or a (90, 90, 180, 3) float64 array, got {}",
        value.get_type().name()?
    )))
}

/// A BRDF as a MERL table: a table as it is, anything else tabulated at the bin centres
/// (phi_h = 0), as `specula compare` does.
pub(crate) fn as_table(py: Python<'_>, brdf: &Arc<dyn Brdf>) -> MerlBrdf {
    py.detach(|| tabulate(brdf.as_ref(), 0.0))
}

/// The figures of one set of cells as a dict (`specula compare`'s columns).
pub(crate) fn figures_dict<'py>(py: Python<'py>, e: &ErrorFigures) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    dict.set_item("cells", e.cells)?;
    dict.set_item("relative_rmse", e.relative_rmse)?;
    dict.set_item("log_rmse", e.log_rmse)?;
    dict.set_item("slice_mae", e.slice_mae)?;
    Ok(dict)
}

/// Check an elevation limit of the "within" figures ([`ELEVATION_DEG`], as the CLI's
/// `--max-elevation`).
pub(crate) fn check_elevation(max_elevation_deg: f64) -> PyResult<f64> {
    ELEVATION_DEG
        .check("max_elevation_deg", max_elevation_deg)
        .or_raise()
}

/// Error figures of BRDF `a` against the reference `b`, the same as `specula compare A B`:
/// both are tabulated at the MERL bin centres (tables are used as they are), and over the
/// cells measured in both the cosine-weighted `relative_rmse`, `log_rmse` and the paper's
/// `slice_mae` (1/sr, phi_d = 90) are given for `"all"` cells above the surface and for the
/// cells whose light and camera are `"within"` `max_elevation_deg` of the normal.
/// `a` and `b` are each a `Brdf`, a source for `load` or a `(90, 90, 180, 3)` array.
/// Returns `{"all": {...}, "within": {...}}`, each with `cells`, `relative_rmse`,
/// `log_rmse`, `slice_mae`.
#[pyfunction]
#[pyo3(signature = (a, b, max_elevation_deg = 75.0))]
pub(crate) fn compare<'py>(
    py: Python<'py>,
    a: &Bound<'py, PyAny>,
    b: &Bound<'py, PyAny>,
    max_elevation_deg: f64,
) -> PyResult<Bound<'py, PyDict>> {
    check_elevation(max_elevation_deg)?;
    let (a, b) = (as_table(py, &brdf_arg(a)?), as_table(py, &brdf_arg(b)?));
    let (all, within) = py.detach(|| {
        (
            specula_core::compare::compare(&a, &b, 90.0),
            specula_core::compare::compare(&a, &b, max_elevation_deg),
        )
    });
    let dict = PyDict::new(py);
    dict.set_item("all", figures_dict(py, &all)?)?;
    dict.set_item("within", figures_dict(py, &within)?)?;
    Ok(dict)
}

/// Names of the built-in material database (the presets first, then the metals and paints
/// of docs/book/src/materials.md, "Built-in database"), each a source for `load`.
#[pyfunction]
pub(crate) fn materials() -> Vec<String> {
    specula_core::materials::builtin_database()
        .iter()
        .map(|m| m.name.clone())
        .collect()
}
