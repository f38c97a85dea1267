//! `specula report`: one self-contained HTML page about a measured BRDF.

use crate::output::plain;
use anyhow::{bail, Context, Result};
use specula_core::compare::compare;
use specula_core::merl::{Bin, MerlBrdf, CELLS};
use specula_core::sampling::{Family, SamplingFunction};
use specula_core::tabulate::tabulate;
use specula_core::{Brdf, Rgb};
use specula_reconstruct::provenance::{sidecar_path, Provenance};
use specula_sampling::{Probe, ProbeSettings};
use specula_visual::grid::{self, Tile};
use specula_visual::plot::probe::{interpolate, plot_probe};
use specula_visual::plot::raw_samples::{plot_raw_samples, RawSample, SampleGrid};
use specula_visual::plot::slice::{plot_slice, plot_slices_against_truth, SliceOptions};
use specula_visual::plot::ThetaHAxis;
use specula_visual::report::{
    CoverageSection, ErrorRow, ErrorSection, Figure, KHatSection, MaterialSection, Report,
};
use specula_visual::{Environment, Lighting, LinearImage, RenderSettings, Scene, ShapeKind};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

pub(crate) mod session;

/// Adaptive samples the paper places along theta_h with the fitted k (section 5.3).
const PLACED_SAMPLES: usize = 30;

/// Write one self-contained HTML report (pictures embedded, no other file needed) about a
/// measured BRDF or a measurement session: the material, k-hat of its probe (paper 5.2), the
/// coverage, renders on a sphere and a speedshape in the studio, the characteristic slice
/// (Fig. 11) and the probe against the adaptive samples (Fig. 13); with a truth, the error
/// figures and the renders beside the truth with their difference.
///
/// INPUT is a MERL .binary (for instance from `specula reconstruct`; its provenance sidecar
/// OUT.provenance.npy is used when present; --samples-csv adds the raw samples, Fig. 15) or a
/// session journal (.sqlite, from `specula measure` or `specula demo`). From a journal the
/// report shows k-hat and the probe as measured, the samples measured of each stage's plan,
/// the duration (device time: the simulated clock on the simulator) against the time
/// model's estimate, the raw samples of the main stage, and the table reconstructed from
/// them with the session's method (or --table); a simulated session's own truth gives the
/// error figures unless --truth names another. An interrupted session is reported as far as
/// it got.
///
/// Examples: specula report silver.binary --truth silver-925 --out silver.html;
/// specula report demo-out/silver-925/silver-925.session.sqlite --out silver.html
#[derive(clap::Args)]
pub struct Args {
    /// The measured BRDF (a MERL .binary file) or a session journal (.sqlite).
    pub input: PathBuf,
    /// The HTML file to write.
    #[arg(long)]
    pub out: PathBuf,
    /// The true BRDF, when known (a simulation): a preset, .toml, .binary or model:name.
    #[arg(long)]
    pub truth: Option<String>,
    /// The raw samples of the measurement (CSV theta_h,phi_h,theta_d,phi_d,r,g,b); with a
    /// .binary input only (a journal holds its samples).
    #[arg(long = "samples-csv")]
    pub samples: Option<PathBuf>,
    /// With a session journal: the MERL .binary to show instead of reconstructing the
    /// session's samples.
    #[arg(long)]
    pub table: Option<PathBuf>,
    /// Width and height of each render, pixels. Range: a whole number from 8 to 8192.
    #[arg(long, default_value_t = 320, value_parser = crate::range::IMAGE_PX)]
    pub size: usize,
    /// Camera rays per pixel of the renders. Range: a whole number from 1 to 65536.
    #[arg(long, default_value_t = 32, value_parser = crate::range::SAMPLES_PER_PIXEL)]
    pub spp: usize,
    /// The report's title (default: the input's material name).
    #[arg(long)]
    pub title: Option<String>,
}

pub fn run(args: Args) -> Result<()> {
    let start = Instant::now();
    let extension = args
        .input
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let session = match extension.as_deref() {
        Some("binary") => false,
        Some("sqlite") => true,
        _ => bail!(
            "{}: expected a MERL .binary file or a session journal (.sqlite)",
            args.input.display()
        ),
    };
    let mut report = if session {
        if args.samples.is_some() {
            bail!("--samples-csv is for a .binary input: a session journal holds its own samples");
        }
        session::report(&args)?
    } else {
        if args.table.is_some() {
            bail!("--table is for a session journal input: the .binary input is the table");
        }
        table_report(&args)?
    };
    report.notes.push(format!(
        "Report made in {:.1} s from {}.",
        start.elapsed().as_secs_f64(),
        args.input.display()
    ));
    report.write(&args.out)?;
    outln!("wrote {}", args.out.display());
    Ok(())
}

/// The report of a MERL table: its probe and k-hat are taken from the table itself.
fn table_report(args: &Args) -> Result<Report> {
    let table = MerlBrdf::read(&args.input)?;
    let truth = args
        .truth
        .as_deref()
        .map(specula_formats::load_brdf)
        .transpose()?;
    let name = table.name();
    let mut report = Report {
        title: args
            .title
            .clone()
            .unwrap_or_else(|| format!("BRDF report: {name}")),
        generator: generator(),
        material: Some(material(&table, &args.input)),
        ..Report::default()
    };
    let mut coverage = coverage_rows(&table, &args.input)?;
    let spinner = crate::progress::spinner("probe and k-hat");
    let settings = ProbeSettings::default();
    let probe = Probe::take(&table, &settings);
    let fit = probe
        .as_ref()
        .ok()
        .map(|p| specula_sampling::fit_k(&p.column(), Family::Exponential, PLACED_SAMPLES))
        .transpose()?;
    spinner.finish_and_clear();
    match (&probe, &fit) {
        (Ok(probe), Some(fit)) => {
            report.k_hat = Some(KHatSection {
                family: fit.function.family.to_string(),
                k: fit.function.k,
                fit_error: fit.error,
                probe_samples: probe.len(),
                placed_samples: PLACED_SAMPLES,
            });
        }
        (Err(e), _) => report.notes.push(format!("No probe could be taken: {e:#}")),
        _ => {}
    }
    if let Some(truth) = &truth {
        report.errors = Some(errors(
            &table,
            truth.as_ref(),
            args.truth.as_deref().unwrap_or(""),
        ));
    }
    report
        .figures
        .extend(renders(&table, truth.as_deref(), args)?);
    report
        .figures
        .extend(slice_figures(&table, truth.as_deref())?);
    if let (Ok(probe), Some(fit)) = (&probe, &fit) {
        let points = probe.points();
        report.figures.push(probe_figure(
            &points,
            &fit.function,
            PLACED_SAMPLES,
            settings.phi_h_deg,
            &name,
        )?);
    }
    if let Some(path) = &args.samples {
        let set = specula_formats::samples_csv::SampleSet::read(path)?;
        let raw: Vec<RawSample> = set
            .samples()
            .iter()
            .map(|s| RawSample::new(s.angles, s.value))
            .collect();
        let stem = path
            .file_stem()
            .map_or_else(|| "samples".into(), |s| s.to_string_lossy());
        let origin = path.display().to_string();
        let (measured, planned) = SampleGrid::new(&raw).context(origin.clone())?.coverage();
        report
            .figures
            .push(raw_samples_figure(&raw, &stem, &origin).context(origin)?);
        coverage.push((
            "planned cells measured (raw samples)".into(),
            measured,
            planned,
        ));
    }
    report.coverage = Some(CoverageSection { rows: coverage });
    Ok(report)
}

/// Who made the report.
fn generator() -> String {
    format!("specula {}", env!("CARGO_PKG_VERSION"))
}

/// Name, source and peak of the table.
fn material(table: &MerlBrdf, path: &Path) -> MaterialSection {
    let mut facts = vec![(
        "format".to_string(),
        "MERL .binary (90 x 90 x 180 cells)".to_string(),
    )];
    let provenance = Provenance::beside(path).ok().flatten();
    facts.extend(peak_fact(table, provenance.as_ref()));
    MaterialSection {
        name: table.name(),
        source: path.display().to_string(),
        facts,
    }
}

/// The table's largest value (sum of R, G, B) and where it lies.
/// The peak among the measured cells (those a sample fell in, when the reconstruction's
/// provenance is known), saying which cells it was looked for in.
fn peak_fact(table: &MerlBrdf, provenance: Option<&Provenance>) -> Option<(String, String)> {
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
fn coverage_rows(table: &MerlBrdf, path: &Path) -> Result<Vec<(String, usize, usize)>> {
    let mut rows = vec![(
        "MERL cells holding a value".to_string(),
        table.measured_count(),
        CELLS,
    )];
    let sidecar = sidecar_path(path);
    if sidecar.exists() {
        rows.extend(provenance_rows(&Provenance::read(&sidecar)?));
    }
    Ok(rows)
}

/// The MERL cells measured directly, interpolated and extrapolated by a reconstruction.
fn provenance_rows(provenance: &Provenance) -> [(String, usize, usize); 3] {
    let (measured, interpolated, extrapolated) = provenance.counts();
    [
        ("cells measured directly".into(), measured, CELLS),
        ("cells interpolated".into(), interpolated, CELLS),
        ("cells extrapolated".into(), extrapolated, CELLS),
    ]
}

/// The error figures of the table against the truth, on all cells and within 75 deg.
fn errors(table: &MerlBrdf, truth: &dyn Brdf, truth_name: &str) -> ErrorSection {
    let spinner = crate::progress::spinner("error figures");
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
    spinner.finish_and_clear();
    ErrorSection {
        truth: truth_name.to_string(),
        rows,
    }
}

/// Renders on a sphere and on a speedshape in the studio; beside the truth when known.
fn renders(table: &MerlBrdf, truth: Option<&dyn Brdf>, args: &Args) -> Result<Vec<Figure>> {
    let studio = Lighting::Environment(Arc::new(Environment::studio()));
    let settings = RenderSettings::square(args.size, args.spp);
    let materials: Vec<&dyn Brdf> = std::iter::once(table as &dyn Brdf).chain(truth).collect();
    let shapes = [ShapeKind::Sphere, ShapeKind::Speedshape];
    let pixels = (args.size * args.size) as u64;
    let bar = crate::progress::bar(
        pixels * (materials.len() * shapes.len()) as u64,
        "rendering",
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
                    bar.set_position(offset + done)
                })
            })
            .collect();
        let shape_name = match shape {
            ShapeKind::Sphere => "sphere",
            ShapeKind::Speedshape => "speedshape",
        };
        let labels = match truth {
            Some(truth) => vec![
                format!("{} (measured)", table.name()),
                format!("{} (truth)", truth.name()),
            ],
            None => vec![table.name()],
        };
        let mut caption = format!(
            "{} on a {shape_name} in the built-in studio environment, {} x {} pixels, {} samples per pixel.",
            labels.join(" and "),
            args.size,
            args.size,
            args.spp
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
            let difference = grid::difference(&images[0], &images[1])?;
            caption.push_str(&format!(
                " Right: the relative difference |A-B|/max(A,B) in false colour (black 0, yellow 100 %), mean {:.1} %.",
                100.0 * difference.mean_relative
            ));
            tiles.push(Tile {
                label: "difference".into(),
                image: difference.image,
            });
        }
        figures.push(Figure::new(
            format!("Render, {shape_name}"),
            caption,
            &grid::compose(&tiles)?,
        )?);
    }
    bar.finish_and_clear();
    Ok(figures)
}

/// The characteristic slice of the table, and of the truth when known (paper Fig. 11).
fn slice_figures(table: &MerlBrdf, truth: Option<&dyn Brdf>) -> Result<Vec<Figure>> {
    let name = table.name();
    let caption = "f_r (mean of R, G, B) at φ_d = 90 deg over θ_d and θ_h, θ_h on MERL's \
         square-root axis, log false colour (paper Fig. 11); blue: not measured.";
    let options = SliceOptions::default();
    let Some(truth) = truth else {
        return Ok(vec![Figure::new(
            "Characteristic slice",
            caption,
            &plot_slice(table, &name, &options)?,
        )?]);
    };
    let truth_name = truth.name();
    let [measured, true_slice, difference] =
        plot_slices_against_truth((table, &name), (truth, &truth_name), &options)?;
    Ok(vec![
        Figure::new(
            "Characteristic slice",
            format!("{caption} On one colour scale with the truth's slice and the difference."),
            &measured,
        )?,
        Figure::new(
            "Characteristic slice of the truth",
            format!("The same slice of {truth_name}, on the same colour scale."),
            &true_slice,
        )?,
        Figure::new(
            "Characteristic slice of the difference",
            "|measured - truth| on the same slice and the same colour scale: where it is as \
             bright as the truth, the error there is 100 %.",
            &difference,
        )?,
    ])
}

/// The probe `(theta_h deg, f)` against the `placed` positions of the fitted sampling
/// function, valued by interpolating the probe (paper Fig. 13).
fn probe_figure(
    probe: &[(f64, Rgb)],
    function: &SamplingFunction,
    placed: usize,
    phi_h_deg: f64,
    name: &str,
) -> Result<Figure> {
    let adaptive = interpolate(probe, &function.positions_deg(placed));
    Figure::new(
        "Probe against the adaptive samples",
        format!(
            "f_r at theta_d = 40, phi_d = 90, phi_h = {phi_h_deg:.1} deg: the square-root probe of \
             {} samples (solid) and the {placed} positions of the {} sampling function with \
             k-hat = {:.3} (dashed, values interpolated from the probe); below, theta_h 0 to 2 \
             deg (paper Fig. 13).",
            probe.len(),
            function.family,
            function.k
        ),
        &plot_probe(probe, &adaptive, name)?,
    )
}

/// The raw-samples figure (paper Fig. 15) of samples from `origin`.
fn raw_samples_figure(raw: &[RawSample], title: &str, origin: &str) -> Result<Figure> {
    Figure::new(
        "Raw samples",
        format!(
            "The {} samples of {origin} as characteristic slices, one per phi_d (paper Fig. 15); \
             blue cells of the plan's grid were not measured.",
            raw.len()
        ),
        &plot_raw_samples(raw, title, ThetaHAxis::Merl)?,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_report_of_a_binary_has_every_section() {
        let dir = tempfile::tempdir().unwrap();
        let binary = dir.path().join("steel.binary");
        let truth = specula_formats::load_brdf("steel").unwrap();
        tabulate(truth.as_ref(), 0.0).write(&binary).unwrap();
        let samples = dir.path().join("raw.csv");
        std::fs::write(
            &samples,
            "theta_h,phi_h,theta_d,phi_d,r,g,b\n0.1,45,10,0,5,5,5\n2,45,10,0,1,1,1\n0.1,45,40,0,4,4,4\n",
        )
        .unwrap();
        let out = dir.path().join("report.html");
        run(Args {
            input: binary,
            out: out.clone(),
            truth: Some("steel".into()),
            samples: Some(samples),
            table: None,
            size: 16,
            spp: 1,
            title: None,
        })
        .unwrap();
        let html = std::fs::read_to_string(&out).unwrap();
        for text in [
            "BRDF report: steel",
            "k-hat</th><td>",
            "1458000 of 1458000 (100.0 %)",
            "planned cells measured (raw samples)</th><td>3 of 4",
            "Against <b>steel</b>",
            "Render, sphere",
            "Render, speedshape",
            "Characteristic slice of the truth",
            "Characteristic slice of the difference",
            "Probe against the adaptive samples",
            "Raw samples",
        ] {
            assert!(html.contains(text), "missing: {text}");
        }
        // A table against itself: no error.
        assert!(html.contains("<td class=\"num\">0.0000</td>"));
        assert_eq!(html.matches("data:image/png;base64,").count(), 7);
    }

    #[test]
    fn other_inputs_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let args = |input: &str| Args {
            input: dir.path().join(input),
            out: dir.path().join("r.html"),
            truth: None,
            samples: None,
            table: None,
            size: 16,
            spp: 1,
            title: None,
        };
        let error = |args: Args| format!("{:#}", run(args).unwrap_err());
        assert!(error(args("missing.sqlite")).contains("missing.sqlite"));
        assert!(error(args("x.csv")).contains("x.csv: expected a MERL .binary file or a session"));
        assert!(error(args("missing.binary")).contains("missing.binary"));
        let with_table = Args {
            table: Some(dir.path().join("t.binary")),
            ..args("m.binary")
        };
        assert!(error(with_table).contains("--table is for a session journal"));
    }
}
