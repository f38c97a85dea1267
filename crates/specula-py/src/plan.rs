//! The plan of paper 5.3 (`specula plan`) as a dict of arrays.

use crate::errors::{invalid, OrRaise};
use crate::interrupt::{self, Stop};
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use specula_acquisition::device::Device;
use specula_acquisition::plan::{Plan, PlanSummary};
use specula_core::grid::{GridOverrides, PhiDSpan, ThetaDSteps};
use specula_core::progress::NoProgress;
use specula_core::request::{GridPreset, GridRequest};
use specula_core::Spherical;
use specula_session::workflow::{HdrChoice, PlanOrder};
use specula_session::{run_plan, PlanError, PlanRequest, ThetaH};
use std::path::PathBuf;

/// The options of a measurement grid shared by `plan`, `evaluate` and `measure` (the CLI's
/// `GridArgs`) as given (`None`: the preset's value): a preset (`"recommended"`, the
/// default, or `"paper"`) whose values the other arguments replace one by one.
pub(crate) struct GridArgs<'a, 'py> {
    pub(crate) grid_preset: Option<&'a str>,
    pub(crate) theta_h_samples: Option<usize>,
    pub(crate) theta_d_step_deg: Option<&'a Bound<'py, PyAny>>,
    pub(crate) phi_d_step_deg: Option<f64>,
    pub(crate) phi_d_span: Option<&'a str>,
    pub(crate) phi_h_deg: Option<f64>,
}

impl GridArgs<'_, '_> {
    /// The grid request of the arguments given: `theta_d_step_deg` is a number (an even
    /// step) or a str `"STEP:GRAZING@FROM"`; the ranges are checked by the request.
    pub(crate) fn request(&self) -> PyResult<GridRequest> {
        Ok(GridRequest {
            preset: self
                .grid_preset
                .map(str::parse::<GridPreset>)
                .transpose()
                .or_raise()?,
            overrides: GridOverrides {
                theta_h_samples: self.theta_h_samples,
                theta_d: self.theta_d_step_deg.map(theta_d_steps).transpose()?,
                phi_d_step_deg: self.phi_d_step_deg,
                phi_d_span: self
                    .phi_d_span
                    .map(str::parse::<PhiDSpan>)
                    .transpose()
                    .or_raise()?,
                phi_h_deg: self.phi_h_deg,
            },
        })
    }
}

/// theta_d's steps from a number (an even step, degrees) or a str (`"3"`, `"3:1@60"`); the
/// ranges are checked with the rest of the request.
fn theta_d_steps(value: &Bound<'_, PyAny>) -> PyResult<ThetaDSteps> {
    match value.extract::<f64>() {
        Ok(step_deg) => Ok(ThetaDSteps::even(step_deg)),
        Err(_) => value
            .extract::<String>()
            .map_err(|_| invalid("theta_d_step_deg must be a number of degrees or a str STEP:GRAZING@FROM, e.g. '3:1@60'"))?
            .parse::<ThetaDSteps>()
            .or_raise(),
    }
}

/// The device description at `path`, or the paper's UTIA gonioreflectometer.
pub(crate) fn device(path: Option<PathBuf>) -> PyResult<Device> {
    Device::load_or_utia(path.as_deref()).or_raise()
}

/// Plan a measurement (paper 5.3, `specula plan`): the grid of theta_h (the sampling
/// function `family` with `k`, or the explicit `theta_h_deg` positions) x theta_d (0, step,
/// ... below 90, or `"STEP:GRAZING@FROM"`: finer from FROM) x phi_d (0, step, ... up to 90
/// with `phi_d_span="quarter"`, up to 180 with `"half-turn"`) at one phi_h, as positions of
/// `device` (a device TOML, default the paper's UTIA goniometer), classified `ok`, `limit`
/// or `occluded`, ordered (`order`: `"optimized"` or `"nested"`) and timed. The grid
/// arguments left `None` take `grid_preset`'s values: `"recommended"` (the default: 16
/// theta_h, theta_d `"3:1@60"`, phi_d step 30 over the half turn, phi_h 45) or `"paper"` (30,
/// 3, 15 over the quarter, 45).
///
/// Returns a dict of arrays in execution order, one entry per sample, the columns of
/// `specula plan`'s CSV: `index`, `theta_h_deg`, `phi_h_deg`, `theta_d_deg`, `phi_d_deg`,
/// `theta_i_deg`, `phi_i_deg`, `theta_o_deg`, `phi_o_deg`, `status` (str), `turntable_deg`,
/// `camera_deg`, `light_azimuth_deg`, `light_elevation_deg` (NaN when excluded), `time_s`;
/// and `"summary"`: counts and times (s) of the nested and the optimized order, and
/// `"captures"`, what the capture times assume. The capture at each sample follows `hdr` as
/// `specula measure` takes it (`"predicted"`: one frame at the exposure for the brightness of
/// `truth`, default silver-925; `"bracket"`: the device file's bracket), as `specula plan`.
/// Ctrl-C returns at once (the ordering is not stoppable; its result is dropped).
#[pyfunction]
#[pyo3(signature = (k = None, theta_h_deg = None, family = "exponential", grid_preset = None,
    theta_h_samples = None, theta_d_step_deg = None, phi_d_step_deg = None, phi_d_span = None,
    phi_h_deg = None, order = "optimized", device = None, hdr = "predicted", truth = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn plan<'py>(
    py: Python<'py>,
    k: Option<f64>,
    theta_h_deg: Option<Vec<f64>>,
    family: &str,
    grid_preset: Option<&str>,
    theta_h_samples: Option<usize>,
    theta_d_step_deg: Option<&Bound<'py, PyAny>>,
    phi_d_step_deg: Option<f64>,
    phi_d_span: Option<&str>,
    phi_h_deg: Option<f64>,
    order: &str,
    device: Option<PathBuf>,
    hdr: &str,
    truth: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    let theta_h = match (k, theta_h_deg) {
        (Some(_), Some(_)) => return Err(invalid("give k or theta_h_deg, not both")),
        (None, None) => return Err(invalid("give k or theta_h_deg")),
        (Some(k), None) => ThetaH::K(k),
        (None, Some(list)) => ThetaH::Positions(list),
    };
    let truth = truth
        .map(specula_formats::source::load_brdf)
        .transpose()
        .or_raise()?;
    let request = PlanRequest {
        theta_h,
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
        order: order.parse::<PlanOrder>().or_raise()?,
        hdr: hdr.parse::<HdrChoice>().or_raise()?,
        truth,
    };
    request.validate().or_raise()?;
    let device = self::device(device)?;
    let (chosen, nested_summary, optimized_summary, assumed) =
        // Abandoned on Ctrl-C: the call returns at once, and the plan left on its thread
        // stops at its next step.
        interrupt::run(py, Stop::Abandon, move |stop| {
            let planned = run_plan(&request, &device, &stop, &NoProgress)?;
            let (nested, optimized) = planned.summaries(&device);
            let chosen = match request.order {
                PlanOrder::Optimized => planned.optimized,
                PlanOrder::Nested => planned.nested,
            };
            Ok::<_, PlanError>((chosen, nested, optimized, planned.assumed))
        })?
        .or_raise()?;
    let dict = plan_dict(py, &chosen)?;
    dict.set_item("captures", assumed)?;
    let summary = PyDict::new(py);
    summary.set_item("nested", summary_dict(py, &nested_summary)?)?;
    summary.set_item("optimized", summary_dict(py, &optimized_summary)?)?;
    dict.set_item("summary", summary)?;
    Ok(dict)
}

/// The plan's samples as columns.
fn plan_dict<'py>(py: Python<'py>, plan: &Plan) -> PyResult<Bound<'py, PyDict>> {
    let samples = &plan.samples;
    let column = |f: &dyn Fn(&specula_acquisition::plan::PlannedSample) -> f64| {
        samples.iter().map(f).collect::<Vec<f64>>().into_pyarray(py)
    };
    let dict = PyDict::new(py);
    let index: Vec<i64> = samples.iter().map(|s| s.index as i64).collect();
    dict.set_item("index", index.into_pyarray(py))?;
    dict.set_item("theta_h_deg", column(&|s| s.hd.theta_h.to_degrees()))?;
    dict.set_item("phi_h_deg", column(&|s| s.hd.phi_h.to_degrees()))?;
    dict.set_item("theta_d_deg", column(&|s| s.hd.theta_d.to_degrees()))?;
    dict.set_item("phi_d_deg", column(&|s| s.hd.phi_d.to_degrees()))?;
    dict.set_item(
        "theta_i_deg",
        column(&|s| Spherical::from_vector(s.wi).theta_rad.to_degrees()),
    )?;
    dict.set_item(
        "phi_i_deg",
        column(&|s| Spherical::from_vector(s.wi).phi_rad.to_degrees()),
    )?;
    dict.set_item(
        "theta_o_deg",
        column(&|s| Spherical::from_vector(s.wo).theta_rad.to_degrees()),
    )?;
    dict.set_item(
        "phi_o_deg",
        column(&|s| Spherical::from_vector(s.wo).phi_rad.to_degrees()),
    )?;
    let status: Vec<&str> = samples.iter().map(|s| s.status.name()).collect();
    let numpy = py.import("numpy")?;
    dict.set_item("status", numpy.call_method1("array", (status,))?)?;
    for (axis, name) in [
        "turntable_deg",
        "camera_deg",
        "light_azimuth_deg",
        "light_elevation_deg",
    ]
    .into_iter()
    .enumerate()
    {
        dict.set_item(
            name,
            column(&|s| s.axes().map_or(f64::NAN, |a| a.to_degrees()[axis])),
        )?;
    }
    dict.set_item("time_s", column(&|s| s.time_s))?;
    Ok(dict)
}

/// A plan summary: counts, and the time model's seconds.
fn summary_dict<'py>(py: Python<'py>, s: &PlanSummary) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    dict.set_item("total", s.total)?;
    dict.set_item("measurable", s.measurable)?;
    dict.set_item("limit", s.limit)?;
    dict.set_item("occluded", s.occluded)?;
    dict.set_item("occluded_by", s.occluded_by.clone())?;
    dict.set_item("move_s", s.move_s)?;
    dict.set_item("settle_s", s.settle_s)?;
    dict.set_item("capture_s", s.capture_s)?;
    dict.set_item("duration_s", s.duration_s())?;
    Ok(dict)
}
