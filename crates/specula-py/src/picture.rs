//! Pictures of a material (`specula render`) and the HTML report of a measurement
//! (`specula report`).

use crate::brdf::brdf_arg;
use crate::errors::{invalid, OrRaise};
use crate::interrupt::{self, Stop};
use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray3};
use pyo3::prelude::*;
use specula_core::range::CountRange;
use specula_report::{write_report, NoProgress, ReportOptions, MAX_IMAGE_PX};
use specula_visual::render::{DEFAULT_SAMPLES_PER_PIXEL, MAX_SAMPLES_PER_PIXEL};
use specula_visual::{Lighting, RenderSettings, Scene, ShapeKind};
use std::path::PathBuf;

/// Width and height of a picture, pixels (the CLI's `--size`).
const IMAGE_PX: CountRange = CountRange::from_to(8, MAX_IMAGE_PX);
/// Camera rays per pixel (the CLI's `--spp`).
const SAMPLES_PER_PIXEL: CountRange = CountRange::from_to(1, MAX_SAMPLES_PER_PIXEL);

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
    let shape: ShapeKind = shape.parse().map_err(invalid)?;
    let point_light = match light {
        None => false,
        Some("point") => true,
        Some(other) => return Err(invalid(format!("light '{other}': expected one of point"))),
    };
    let scene = Scene::new(shape, Lighting::chosen(point_light, env).or_raise()?);
    let settings = RenderSettings {
        seed,
        ..RenderSettings::square(
            IMAGE_PX.check("size", size).or_raise()?,
            SAMPLES_PER_PIXEL.check("spp", spp).or_raise()?,
        )
    };
    let brdf = brdf_arg(brdf)?;
    let image = interrupt::run(py, Stop::Abandon, move |_| {
        specula_visual::render(brdf.as_ref(), &scene, &settings, &|_| {})
    })?;
    if let Some(path) = out {
        image.save(&path, exposure).or_raise()?;
    }
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
    let options = ReportOptions {
        truth,
        samples: samples_csv,
        table,
        size_px: size,
        spp,
        title,
        ..ReportOptions::new(source)
    };
    let written = out.clone();
    interrupt::run(py, Stop::Abandon, move |_| {
        write_report(&options, &out, &NoProgress)
    })?
    .or_raise()?;
    Ok(written)
}
