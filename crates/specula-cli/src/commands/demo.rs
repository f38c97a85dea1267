//! `specula demo`: the main job on the built-in default: the paper's two materials measured
//! on the simulated device, with their tables, summaries and pictures.

use super::measure::Bars;
use anyhow::{Context, Result};
use image::RgbImage;
use specula_acquisition::device::Device;
use specula_core::compare::compare;
use specula_core::tabulate::tabulate;
use specula_core::{Brdf, MerlBrdf};
use specula_session::engine::stop_on_ctrl_c;
use specula_session::journal::Journal;
use specula_session::workflow::{
    default_session_path, measure, measured_samples, probe_samples, summary_path, FitRecord,
    MeasureOutcome, MeasureSettings, Source, STAGE_MAIN,
};
use specula_visual::grid::{self, Tile};
use specula_visual::plot::probe::{interpolate, plot_probe};
use specula_visual::plot::raw_samples::{plot_raw_samples, RawSample};
use specula_visual::plot::slice::{plot_slice, SliceOptions};
use specula_visual::plot::ThetaHAxis;
use specula_visual::report::{
    CoverageSection, ErrorRow, ErrorSection, Figure, KHatSection, Report,
};
use specula_visual::{Environment, Lighting, RenderSettings, Scene, ShapeKind};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// The paper's two materials (section 4.2).
const MATERIALS: [&str; 2] = ["silver-925", "green-paint"];

/// Run the main job on the built-in default: measure silver-925 and green-paint (the paper's
/// two materials) on the simulated device, the paper's way with our ordering and predicted
/// exposures, and write for each the MERL table, the summary, the session journal,
/// pictures and an HTML report; then print where everything is.
///
/// Per material, in OUT/MATERIAL/: MATERIAL.binary (the measured BRDF, MERL format),
/// MATERIAL.summary.txt (k-hat, counts, captures, simulated hours), MATERIAL.session.sqlite
/// (the journal), probe.png (the probe against the adaptive samples, paper Fig. 13),
/// raw_samples.png (the measured samples per phi_d, Fig. 15), slice.png (the measured and the
/// true characteristic slice, Fig. 11), render.png (the measured and the true material on
/// a sphere in a studio, with their difference, Fig. 16) and report.html (one self-contained
/// page with k-hat, coverage, the error against the truth and every picture).
///
/// A rerun resumes the sessions (and is quick once they are complete); Ctrl-C stops after
/// the sample in progress.
#[derive(clap::Args)]
pub struct Args {
    /// Folder for the outputs.
    #[arg(long, default_value = "demo-out")]
    pub out: PathBuf,
    /// Seed of the simulated device.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

pub fn run(args: Args) -> Result<()> {
    let started = Instant::now();
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("{}: cannot create the folder", args.out.display()))?;
    let stop = stop_on_ctrl_c().context("cannot watch for Ctrl-C")?;
    let settings = MeasureSettings {
        seed: args.seed,
        ..MeasureSettings::default()
    };
    let mut written = Vec::new();
    for name in MATERIALS {
        let dir = args.out.join(name);
        std::fs::create_dir_all(&dir)
            .with_context(|| format!("{}: cannot create the folder", dir.display()))?;
        let truth = specula_formats::source::load_brdf(name)?;
        let table = dir.join(format!("{name}.binary"));
        let session = default_session_path(&table);
        eprintln!("== {name}: measuring on the simulated device");
        let mut bars = Bars::default();
        let source = Source::Simulated {
            truth: truth.clone(),
            speedup: None,
        };
        let outcome = measure(
            source,
            &Device::utia(),
            &settings,
            &session,
            &table,
            stop.clone(),
            &mut bars,
        )?;
        bars.finish();
        let summary = match outcome {
            MeasureOutcome::Complete(summary) => summary,
            MeasureOutcome::Stopped {
                stage,
                done,
                planned,
            } => {
                println!("stopped in {name}'s {stage} stage ({done} of {planned}); run `specula demo` again to resume");
                return Ok(());
            }
        };
        let pick = |key: &str| {
            summary
                .lines()
                .into_iter()
                .find(|l| l.starts_with(key))
                .unwrap_or_default()
        };
        println!(
            "{name}: {}, {}, {}, {}",
            pick("k_hat="),
            pick("measured_samples="),
            pick("captures_per_sample="),
            pick("simulated_hours=")
        );
        let mut files = vec![table.clone(), summary_path(&table), session.clone()];
        files.extend(pictures(
            &dir,
            name,
            truth.as_ref(),
            &table,
            &session,
            &settings,
        )?);
        written.push((name, files));
    }
    println!(
        "\ndemo finished in {:.0} s; everything is in {}:",
        started.elapsed().as_secs_f64(),
        args.out.display()
    );
    for (name, files) in written {
        println!("{name}:");
        for file in files {
            println!("  {}", file.display());
        }
    }
    Ok(())
}

/// The pictures of one measured material, and the error against its truth.
fn pictures(
    dir: &Path,
    name: &str,
    truth: &dyn Brdf,
    table: &Path,
    session: &Path,
    settings: &MeasureSettings,
) -> Result<Vec<PathBuf>> {
    let journal = Journal::open_read_only(session)?;
    let measured = MerlBrdf::read(table)?;
    let mut files = Vec::new();
    let mut figures = Vec::new();
    let mut save = |file: &str, image: RgbImage| -> Result<()> {
        let path = dir.join(file);
        image
            .save(&path)
            .with_context(|| format!("{}: cannot write", path.display()))?;
        figures.push(Figure::new(file, format!("{name}: {file}"), &image)?);
        files.push(path);
        Ok(())
    };

    // Fig. 13: the probe against the adaptive samples at k-hat.
    let probe = probe_samples(&journal)?;
    let fit: FitRecord = journal
        .meta("fit")?
        .context("the session has no fit of k")?;
    let adaptive = interpolate(
        &probe,
        &fit.function.positions_deg(settings.theta_h_samples),
    );
    let title = format!("{name} (k-hat {:.2})", fit.function.k);
    save("probe.png", plot_probe(&probe, &adaptive, &title)?)?;

    // Fig. 15: the raw samples.
    let samples = measured_samples(&journal.plan(STAGE_MAIN)?, &journal.samples(STAGE_MAIN)?);
    let raw: Vec<RawSample> = samples
        .iter()
        .map(|s| RawSample::new(s.hd, s.value))
        .collect();
    save(
        "raw_samples.png",
        plot_raw_samples(&raw, &format!("{name}: measured samples"), ThetaHAxis::Merl)?,
    )?;

    // Fig. 11: the characteristic slice, measured and true.
    let options = SliceOptions::default();
    let slices = [
        Tile {
            label: "measured on the simulated device".into(),
            image: plot_slice(&measured, &format!("{name}, measured"), &options)?,
        },
        Tile {
            label: "ground truth".into(),
            image: plot_slice(truth, &format!("{name}, truth"), &options)?,
        },
    ];
    save("slice.png", grid::compose(&slices)?)?;

    // Fig. 16: measured and true on a sphere in the studio, and their difference.
    let scene = Scene::new(
        ShapeKind::Sphere,
        Lighting::Environment(Arc::new(Environment::studio())),
    );
    let render_settings = RenderSettings::square(256, 32);
    let spinner = crate::progress::spinner("rendering");
    let images = [
        specula_visual::render(&measured, &scene, &render_settings, &|_| {}),
        specula_visual::render(truth, &scene, &render_settings, &|_| {}),
    ];
    spinner.finish_and_clear();
    let difference = grid::difference(&images[0], &images[1])?;
    let tiles = [
        Tile {
            label: format!("{name}, measured"),
            image: images[0].to_display(0.0),
        },
        Tile {
            label: format!("{name}, truth"),
            image: images[1].to_display(0.0),
        },
        Tile {
            label: "relative difference (0 to 100 %)".into(),
            image: difference.image,
        },
    ];
    save("render.png", grid::compose(&tiles)?)?;

    let errors = compare(&measured, &tabulate(truth, 0.0), 75.0);
    let report = Report {
        title: format!("{name} measured on the simulated device"),
        generator: format!("specula {} demo", env!("CARGO_PKG_VERSION")),
        k_hat: Some(KHatSection {
            family: fit.function.family.to_string(),
            k: fit.function.k,
            fit_error: fit.error,
            probe_samples: probe.len(),
            placed_samples: settings.theta_h_samples,
        }),
        coverage: Some(CoverageSection {
            rows: vec![
                (
                    "measured samples".into(),
                    samples.len(),
                    journal.plan(STAGE_MAIN)?.len(),
                ),
                (
                    "measured MERL cells".into(),
                    measured.measured_count(),
                    specula_core::merl::CELLS,
                ),
            ],
        }),
        errors: Some(ErrorSection {
            truth: name.to_string(),
            rows: vec![ErrorRow {
                set: "light and camera within 75 deg".into(),
                cells: errors.cells,
                relative_rmse: errors.relative_rmse,
                log_rmse: errors.log_rmse,
                slice_mae: errors.slice_mae,
            }],
        }),
        figures,
        ..Report::default()
    };
    let report_path = dir.join("report.html");
    report.write(&report_path)?;
    files.push(report_path);
    println!(
        "{name} against its truth, light and camera within 75 deg: relative RMSE {:.4}, log RMSE {:.4}; renders differ by {:.1} % on average",
        errors.relative_rmse,
        errors.log_rmse,
        100.0 * difference.mean_relative
    );
    Ok(files)
}
