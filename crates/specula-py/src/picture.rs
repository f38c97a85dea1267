//! Pictures of a material (`specula render`) and the HTML report of a measurement
//! (`specula report`).

use crate::brdf::brdf_arg;
use crate::errors::{invalid, OrRaise};
use crate::interrupt::{self, Stop};
use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray3};
use pyo3::prelude::*;
use specula_report::{run_report, NoProgress, ReportRequest};
use specula_visual::render::DEFAULT_SAMPLES_PER_PIXEL;
use specula_visual::{render_pictures, RenderRequest};
use std::path::PathBuf;

/// Render a material on a `shape` (`"sphere"` or `"speedshape"`) as `specula render` does:
/// under the environment `env` (`"studio"` by default, `"constant"`, `"constant:RADIANCE"`
/// or a latitude-longitude `.exr`) or, with `light="point"`, the standard point light; a
/// `size` x `size` picture at `spp` camera rays per pixel. `brdf` is a `Brdf`, a source or a
/// table array. With `out` the picture is written as the CLI writes it (`.png` tone-mapped
/// with `exposure` stops, `.exr` linear).
///
/// Returns the linear radiance as a `(size, size, 3)` array, top row first. Ctrl-C returns
/// at once (the render in flight finishes unseen).
#[pyfunction]
#[pyo3(signature = (brdf, out = None, shape = "sphere", env = None, light = None,
    spp = DEFAULT_SAMPLES_PER_PIXEL, size = 512, exposure = 0.0, seed = 1))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn render<'py>(
    py: Python<'py>,
    brdf: &Bound<'py, PyAny>,
    out: Option<PathBuf>,
    shape: &str,
    env: Option<&str>,
    light: Option<&str>,
    spp: usize,
    size: usize,
    exposure: f64,
    seed: u64,
) -> PyResult<Bound<'py, PyArray3<f64>>> {
    let request = RenderRequest {
        shape: shape.parse().map_err(invalid)?,
        env: env.map(str::to_string),
        light: light.map(str::parse).transpose().or_raise()?,
        spp,
        size_px: size,
        exposure_stops: exposure,
        side_by_side: false,
        seed,
        out,
    };
    request.validate(1).or_raise()?;
    let brdf = brdf_arg(brdf)?;
    let mut rendered = interrupt::run(py, Stop::Cooperative, move |stop| {
        render_pictures(&request, &[(brdf.name(), brdf)], &stop, &NoProgress)
    })?
    .or_raise()?;
    let image = rendered.images.remove(0);
    let pixels = Array3::from_shape_fn((image.height, image.width, 3), |(y, x, c)| {
        image.pixels[y * image.width + x][c]
    });
    Ok(pixels.into_pyarray(py))
}

/// Write the HTML report of a measurement (`specula report`): `source` is a MERL `.binary`
/// or a session journal; `truth` (a source, for the error figures), `samples_csv` and
/// `table` as the CLI's options; renders of `size` pixels at `spp` rays per pixel; `title`
/// for the page. Returns `out`. Ctrl-C returns at once.
#[pyfunction]
#[pyo3(signature = (source, out, truth = None, samples_csv = None, table = None, size = 320,
    spp = 32, title = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn report(
    py: Python<'_>,
    source: PathBuf,
    out: PathBuf,
    truth: Option<String>,
    samples_csv: Option<PathBuf>,
    table: Option<PathBuf>,
    size: usize,
    spp: usize,
    title: Option<String>,
) -> PyResult<PathBuf> {
    let options = ReportRequest {
        truth,
        samples: samples_csv,
        table,
        size_px: size,
        spp,
        title,
        ..ReportRequest::new(source)
    };
    let written = out.clone();
    interrupt::run(py, Stop::Abandon, move |_| {
        run_report(&options, &out, &NoProgress)
    })?
    .or_raise()?;
    Ok(written)
}
