//! The figures and sections both kinds of report share: the error figures, renders, the
//! characteristic slice, the probe and the raw samples, the peak and the coverage rows.

use crate::error::{OrReport, ReportError};
use crate::{Progress, ReportRequest};
use specula_core::compare::compare;
use specula_core::merl::{Bin, MerlBrdf, CELLS};
use specula_core::sampling::SamplingFunction;
use specula_core::shown::plain;
use specula_core::tabulate::tabulate;
use specula_core::{Brdf, ProbePoint, ProbeSpec, Sample};
use specula_reconstruct::provenance::{sidecar_path, Provenance};
use specula_visual::grid::{self, Tile};
use specula_visual::plot::probe::{interpolate, plot_probe};
use specula_visual::plot::raw_samples::plot_raw_samples;
use specula_visual::plot::slice::{
    plot_relative_uncertainty_slice, plot_slice, plot_slices_against_truth, SliceOptions,
};
use specula_visual::plot::ThetaHAxis;
use specula_visual::report::{ErrorRow, ErrorSection, Figure};
use specula_visual::{Environment, Lighting, LinearImage, RenderSettings, Scene, ShapeKind};
use std::path::Path;
use std::sync::Arc;

/// The peak among the measured cells (those a sample fell in, when the reconstruction's
/// provenance is known), saying which cells it was looked for in.
pub(crate) fn peak_fact(
    table: &MerlBrdf,
    provenance: Option<&Provenance>,
) -> Option<(String, String)> {
    let (index, v) = table.peak(|i| provenance.is_none_or(|p| p.is_measured(i)))?;
    let among = match provenance {
        Some(_) => "among the cells a sample fell in",
        None => "among the cells holding a value",
    };
    let bin = Bin::from_index(index).centre(0.0);
    Some((
        "peak f_r".into(),
        format!(
            "R {}, G {}, B {} 1/sr at θ_h {} deg, θ_d {} deg, φ_d {} deg, {among}",
            plain(v.x),
            plain(v.y),
            plain(v.z),
            plain(bin.theta_h.to_degrees()),
            plain(bin.theta_d.to_degrees()),
            plain(bin.phi_d.to_degrees())
        ),
    ))
}

/// Cells holding a value, and where they come from when the provenance sidecar is there.
pub(crate) fn coverage_rows(
    table: &MerlBrdf,
    path: &Path,
) -> Result<Vec<(String, usize, usize)>, ReportError> {
    let mut rows = vec![(
        "MERL cells holding a value".to_string(),
        table.measured_count(),
        CELLS,
    )];
    let sidecar = sidecar_path(path);
    if sidecar.exists() {
        rows.extend(provenance_rows(&Provenance::read(&sidecar).or_report()?));
    }
    Ok(rows)
}

/// The MERL cells measured directly, interpolated and extrapolated by a reconstruction.
pub(crate) fn provenance_rows(provenance: &Provenance) -> [(String, usize, usize); 3] {
    let (measured, interpolated, extrapolated) = provenance.counts();
    [
        ("cells measured directly".into(), measured, CELLS),
        ("cells interpolated".into(), interpolated, CELLS),
        ("cells extrapolated".into(), extrapolated, CELLS),
    ]
}

/// The error figures of the table against the truth, on all cells and within 75 deg.
pub(crate) fn errors(
    table: &MerlBrdf,
    truth: &dyn Brdf,
    truth_name: &str,
    progress: &dyn Progress,
) -> ErrorSection {
    progress.start("error figures", None);
    let reference = tabulate(truth, 0.0);
    let rows = [
        ("all cells above the surface", 90.0),
        ("light and camera within 75 deg", 75.0),
    ]
    .into_iter()
    .map(|(set, limit)| {
        let e = compare(table, &reference, limit);
        ErrorRow {
            set: set.to_string(),
            cells: e.cells,
            relative_rmse: e.relative_rmse,
            log_rmse: e.log_rmse,
            slice_mae: e.slice_mae,
        }
    })
    .collect();
    progress.finish();
    ErrorSection {
        truth: truth_name.to_string(),
        rows,
    }
}

/// Renders on a sphere and on a speedshape in the studio; beside the truth when known.
pub(crate) fn renders(
    sample: (&MerlBrdf, &str),
    other: Option<(&dyn Brdf, &str)>,
    options: &ReportRequest,
    progress: &dyn Progress,
) -> Result<Vec<Figure>, ReportError> {
    let studio = Lighting::Environment(Arc::new(Environment::studio()));
    let settings = RenderSettings::square(options.size_px, options.spp);
    let materials: Vec<&dyn Brdf> = std::iter::once(sample.0 as &dyn Brdf)
        .chain(other.map(|(brdf, _)| brdf))
        .collect();
    let shapes = [ShapeKind::Sphere, ShapeKind::Speedshape];
    let pixels = (options.size_px * options.size_px) as u64;
    progress.start(
        "rendering",
        Some(pixels * (materials.len() * shapes.len()) as u64),
    );
    let mut figures = Vec::new();
    for (s, shape) in shapes.into_iter().enumerate() {
        let scene = Scene::new(shape, studio.clone());
        let images: Vec<LinearImage> = materials
            .iter()
            .enumerate()
            .map(|(m, brdf)| {
                let offset = (s * materials.len() + m) as u64 * pixels;
                specula_visual::render(*brdf, &scene, &settings, &|done| {
                    progress.set(offset + done)
                })
            })
            .collect();
        let shape_name = match shape {
            ShapeKind::Sphere => "sphere",
            ShapeKind::Speedshape => "speedshape",
        };
        let labels: Vec<String> = std::iter::once(sample.1)
            .chain(other.map(|(_, label)| label))
            .map(String::from)
            .collect();
        let mut caption = format!(
            "{} on a {shape_name} in the built-in studio environment, {} x {} pixels, {} samples per pixel.",
            labels.join(" and "),
            options.size_px,
            options.size_px,
            options.spp
        );
        let mut tiles: Vec<Tile> = labels
            .into_iter()
            .zip(&images)
            .map(|(label, image)| Tile {
                label,
                image: image.to_display(0.0),
            })
            .collect();
        if images.len() == 2 {
            let difference = grid::difference(&images[0], &images[1]).or_report()?;
            caption.push_str(&format!(
                " Right: the relative difference |A-B|/max(A,B) in false colour (black 0, yellow 100 %), mean {:.1} %.",
                100.0 * difference.mean_relative
            ));
            tiles.push(Tile {
                label: "difference".into(),
                image: difference.image,
            });
        }
        figures.push(
            Figure::new(
                format!("Render, {shape_name}"),
                caption,
                &grid::compose(&tiles).or_report()?,
            )
            .or_report()?,
        );
    }
    progress.finish();
    Ok(figures)
}

/// The characteristic slice of the table, and of the truth and the difference on one colour
/// scale when the truth is known (paper Fig. 11).
pub(crate) fn slice_figures(
    table: &MerlBrdf,
    truth: Option<(&dyn Brdf, &str)>,
    uncertainty: Option<&MerlBrdf>,
) -> Result<Vec<Figure>, ReportError> {
    let mut figures = table_slice_figures(table, truth)?;
    if let Some(uncertainty) = uncertainty {
        figures.push(uncertainty_slice_figure(table, uncertainty)?);
    }
    Ok(figures)
}

/// The map of the table's relative uncertainty on its characteristic slice, beside the
/// slices.
fn uncertainty_slice_figure(
    table: &MerlBrdf,
    uncertainty: &MerlBrdf,
) -> Result<Figure, ReportError> {
    let title = format!("{}: relative uncertainty", table.name());
    Figure::new(
        "Characteristic slice of the relative uncertainty",
        "The standard uncertainty (k = 1) of the table's cells on the same slice, relative to \
         their value (the mean of R, G and B of OUT.uncertainty.binary over the mean of the \
         table), in per cent on a log false colour; blue: no value.",
        &plot_relative_uncertainty_slice(table, uncertainty, &title, &SliceOptions::default())
            .or_report()?,
    )
    .or_report()
}

/// The table's characteristic slice, with the truth's and their difference when known.
fn table_slice_figures(
    table: &MerlBrdf,
    truth: Option<(&dyn Brdf, &str)>,
) -> Result<Vec<Figure>, ReportError> {
    let name = table.name();
    let caption = "f_r (mean of R, G, B) at φ_d = 90 deg over θ_d and θ_h, θ_h on MERL's \
         square-root axis, log false colour (paper Fig. 11); blue: not measured.";
    let options = SliceOptions::default();
    let Some((truth, role)) = truth else {
        return Ok(vec![Figure::new(
            "Characteristic slice",
            caption,
            &plot_slice(table, &name, &options).or_report()?,
        )
        .or_report()?]);
    };
    let truth_name = truth.name();
    let [measured, true_slice, difference] =
        plot_slices_against_truth((table, &name), (truth, &truth_name), &options).or_report()?;
    Ok(vec![
        Figure::new(
            "Characteristic slice",
            format!("{caption} On one colour scale with the {role}'s slice and the difference."),
            &measured,
        )
        .or_report()?,
        Figure::new(
            format!("Characteristic slice of the {role}"),
            format!("The same slice of {truth_name}, on the same colour scale."),
            &true_slice,
        )
        .or_report()?,
        Figure::new(
            "Characteristic slice of the difference",
            format!(
                "|measured - {role}| on the same slice and the same colour scale: where it is \
                 as bright as the {role}, the error there is 100 %."
            ),
            &difference,
        )
        .or_report()?,
    ])
}

/// The probe's points against the `placed` positions of the fitted sampling function,
/// valued by interpolating the probe (paper Fig. 13).
pub(crate) fn probe_figure(
    probe: &[ProbePoint],
    function: &SamplingFunction,
    placed: usize,
    phi_h_deg: f64,
    name: &str,
) -> Result<Figure, ReportError> {
    let adaptive = interpolate(probe, &function.positions_deg(placed));
    Figure::new(
        "Probe against the adaptive samples",
        format!(
            "f_r at theta_d = {}, phi_d = {}, phi_h = {phi_h_deg:.1} deg: the square-root probe of \
             {} samples (solid) and the {placed} positions of the {} sampling function with \
             k-hat = {:.3} (dashed, values interpolated from the probe); below, theta_h 0 to 2 \
             deg (paper Fig. 13).",
            ProbeSpec::paper().theta_d_deg,
            ProbeSpec::paper().phi_d_deg,
            probe.len(),
            function.family,
            function.k
        ),
        &plot_probe(probe, &adaptive, name).or_report()?,
    )
    .or_report()
}

/// The raw-samples figure (paper Fig. 15) of samples from `origin`.
pub(crate) fn raw_samples_figure(
    raw: &[Sample],
    title: &str,
    origin: &str,
) -> Result<Figure, ReportError> {
    Figure::new(
        "Raw samples",
        format!(
            "The {} samples of {origin} as characteristic slices, one per phi_d (paper Fig. 15); \
             blue cells of the plan's grid were not measured.",
            raw.len()
        ),
        &plot_raw_samples(raw, title, ThetaHAxis::Merl).or_report()?,
    )
    .or_report()
}
