//! `specula demo`: the main job on the built-in default: the paper's two materials measured
//! on the simulated device, with their tables, summaries and pictures.

use super::measure::Bars;
use crate::interrupt::{blame_stop, stop_on_ctrl_c, Interrupted};
use anyhow::{Context, Result};
use specula_acquisition::device::Device;
use specula_report::{write_session_pictures, ReportRequest};
use specula_session::journal::SequentialSettings;
use specula_session::workflow::{
    default_session_path, measure, session_settings, summary_path, MeasureOutcome, MeasureSettings,
    Source,
};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The paper's two materials (section 4.2).
const MATERIALS: [&str; 2] = ["silver-925", "green-paint"];

/// Measure silver-925 and green-paint on the simulated device and report on them.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// Folder for the outputs.
    #[arg(long, default_value = "demo-out")]
    pub out: PathBuf,
    /// Seed of the simulated device (seeds other than 1 write to OUT/seed-N/).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let started = Instant::now();
    let out = if args.seed == 1 {
        args.out.clone()
    } else {
        args.out.join(format!("seed-{}", args.seed))
    };
    std::fs::create_dir_all(&out)
        .with_context(|| format!("{}: cannot create the folder", out.display()))?;
    let stop = stop_on_ctrl_c().context("cannot watch for Ctrl-C")?;
    let mut written = Vec::new();
    for name in MATERIALS {
        let dir = out.join(name);
        std::fs::create_dir_all(&dir)
            .with_context(|| format!("{}: cannot create the folder", dir.display()))?;
        let truth = specula_formats::source::load_brdf(name)?;
        let table = dir.join(format!("{name}.binary"));
        let session = default_session_path(&table);
        // A resumed session keeps its grid and how its main stage is measured; a new one is
        // measured as `specula measure` does by default, sequentially.
        let resumed = session_settings(&session)?;
        let settings = MeasureSettings {
            seed: args.seed,
            grid: resumed.as_ref().map(|s| s.grid).unwrap_or_default(),
            sequential: resumed.map_or(Some(SequentialSettings::default()), |s| s.sequential),
            ..MeasureSettings::default()
        };
        eprintln!(
            "== {name}: measuring on the simulated device, grid {}",
            settings.grid
        );
        let mut bars = Bars::default();
        let source = Source::Simulated {
            truth: truth.clone(),
            speedup: None,
        };
        let outcome = measure(
            source,
            &Device::utia(),
            &settings,
            None,
            &session,
            &table,
            stop.clone(),
            &mut bars,
        )
        .map_err(|e| blame_stop(e.into(), &stop))?;
        bars.finish();
        let summary = match outcome {
            MeasureOutcome::Complete(summary) => summary,
            MeasureOutcome::Stopped {
                stage,
                done,
                planned,
            } => {
                outln!("stopped in {name}'s {stage} stage ({done} of {planned}); run `specula demo` again to resume");
                return Err(Interrupted(format!(
                    "{done} of {planned} of {name}'s {stage} samples are journaled; run `specula demo` again to resume"
                ))
                .into());
            }
        };
        let pick = |key: &str| {
            summary
                .lines()
                .into_iter()
                .find(|l| l.starts_with(key))
                .unwrap_or_default()
        };
        outln!(
            "{name}: {}, {}, {}, {}",
            pick("k_hat="),
            pick("measured_samples="),
            pick("captures_per_sample="),
            pick("simulated_hours=")
        );
        let mut files = vec![table.clone(), summary_path(&table), session.clone()];
        files.extend(pictures(&dir, name, &table, &session)?);
        written.push((name, files));
    }
    outln!(
        "\ndemo finished in {:.0} s; everything is in {}:",
        started.elapsed().as_secs_f64(),
        out.display()
    );
    for (name, files) in written {
        outln!("{name}:");
        for file in files {
            outln!("  {}", file.display());
        }
    }
    Ok(())
}

/// Render size of the demo's pictures, pixels, and camera rays per pixel.
const RENDER_PX: usize = 256;
const RENDER_SPP: usize = 32;

/// The session report of one measured material (what `specula report SESSION --table TABLE
/// --truth NAME` writes) as report.html, and each of its pictures as a PNG file beside it;
/// prints the appearance figures with their warnings and the error against the truth.
fn pictures(dir: &Path, name: &str, table: &Path, session: &Path) -> Result<Vec<PathBuf>> {
    let options = ReportRequest {
        truth: Some(name.to_string()),
        table: Some(table.to_path_buf()),
        size_px: RENDER_PX,
        spp: RENDER_SPP,
        title: Some(format!("{name} measured on the simulated device")),
        ..ReportRequest::new(session)
    };
    let (page, files) =
        write_session_pictures(&options, dir, &crate::progress::Terminal::default())?;
    let report = &page.report;
    for table in &report.tables {
        for row in table.rows.iter().filter(|r| {
            ["gloss", "haze", "DOI", "dE00", "flop"]
                .iter()
                .any(|key| r[0].starts_with(key))
        }) {
            outln!("{name} {}: {}", row[0], row[1..].join(" / "));
        }
    }
    for warning in &page.warnings {
        eprintln!("warning: {name}: {warning}");
    }
    for row in report.errors.iter().flat_map(|e| &e.rows) {
        outln!(
            "{name} against its truth, {}: relative RMSE {:.4}, log RMSE {:.4}",
            row.set,
            row.relative_rmse,
            row.log_rmse
        );
    }
    Ok(files)
}
