//! `specula analyze`: the database analysis of paper 5.1.

use crate::output::plain;
use crate::progress;
use anyhow::{bail, Context, Result};
use specula_core::materials::database::builtin_database;
use specula_core::sampling::Family;
use specula_core::GridSpec;
use specula_sampling::analysis::{analyze_slice, write_materials_csv, BestPair, DatabaseSummary};
use specula_sampling::database::{map_slices, merl_files, SliceSource};
use specula_sampling::slice::{CharacteristicSlice, PROBE_THETA_D_DEG, THETA_H_NODES};
use specula_visual::heatmap::Heatmap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The materials of a database: the arguments shared by `analyze` and `placement`.
#[derive(clap::Args)]
pub(crate) struct DatabaseArgs {
    /// MERL .binary files, folders of them (every *.binary inside), or any other BRDF (a
    /// preset, a material .toml, a model:name fit such as sgd:chrome-steel).
    pub sources: Vec<String>,
    /// Add the built-in database of specular and glossy materials (see docs/book/src/materials.md).
    #[arg(long)]
    pub builtin: bool,
    /// Add every material of a fits table: shared/data/measured/merl_fits_djbrdf/
    /// merl_sgd_bagher2012.csv or merl_abc_low2012.csv (the MERL-100 materials).
    #[arg(long)]
    pub fits: Vec<PathBuf>,
}

impl DatabaseArgs {
    /// The sources in the order given: arguments, then fits tables, then the built-in ones.
    pub(crate) fn sources(&self) -> Result<Vec<SliceSource>> {
        let mut sources = Vec::new();
        for spec in &self.sources {
            let path = Path::new(spec);
            let is_merl = path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("binary"));
            if path.is_dir() || is_merl {
                sources.extend(merl_files(path)?.into_iter().map(SliceSource::MerlFile));
            } else {
                sources.push(SliceSource::Brdf(specula_formats::load_brdf(spec)?));
            }
        }
        for table in &self.fits {
            let fits = specula_formats::fits::load_fits(table)?;
            sources.extend(fits.into_iter().map(SliceSource::Brdf));
        }
        if self.builtin {
            sources.extend(
                builtin_database()
                    .into_iter()
                    .map(|m| SliceSource::Brdf(Arc::new(m))),
            );
        }
        if sources.is_empty() {
            bail!("nothing to analyse: give MERL files or folders, BRDFs, --fits FILE.csv or --builtin");
        }
        Ok(sources)
    }

    /// Runs `work` on every material's characteristic slice (a BRDF's on `nodes` theta_h
    /// nodes) in parallel with a progress bar; the first failure (naming its source) stops
    /// the command.
    pub(crate) fn map<T: Send>(
        &self,
        label: &str,
        nodes: usize,
        work: impl Fn(&CharacteristicSlice) -> Result<T> + Sync,
    ) -> Result<Vec<T>> {
        let sources = self.sources()?;
        let bar = progress::bar(sources.len() as u64, label);
        let results = map_slices(&sources, nodes, work, |_| bar.inc(1));
        bar.finish_and_clear();
        results
            .into_iter()
            .zip(&sources)
            .map(|(r, s)| r.with_context(|| format!("{}: analysis failed", s.name())))
            .collect()
    }
}

/// Find the sampling function and column that rebuild a database best (paper 5.1).
#[derive(clap::Args)]
pub(crate) struct Args {
    #[command(flatten)]
    pub database: DatabaseArgs,
    /// Number of theta_h samples of the sparse measurement. Range: a whole number from 2 to 360.
    #[arg(long, default_value_t = GridSpec::paper().theta_h_samples, value_parser = crate::range::THETA_H_SAMPLES)]
    pub theta_h_samples: usize,
    /// Output folder (created if missing).
    #[arg(long)]
    pub out: PathBuf,
}

pub(crate) fn run(args: Args) -> Result<()> {
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("{}: cannot create the folder", args.out.display()))?;
    let analyses = args.database.map("analysing", THETA_H_NODES, |slice| {
        Ok(analyze_slice(slice, args.theta_h_samples))
    })?;
    let summary = DatabaseSummary::of(&analyses);
    summary.write_csv(&args.out.join("analysis.csv"))?;
    write_materials_csv(&analyses, &args.out.join("materials.csv"))?;
    let Some(best) = summary.best() else {
        bail!("no material had a measured column");
    };
    heatmap(
        &summary,
        analyses.len(),
        args.theta_h_samples,
        best_cell(&best),
    )
    .write_png(&args.out.join("analysis.png"))?;

    outln!(
        "best: {} at theta_d = {} deg: mean error {} 1/sr, median {} 1/sr over {} materials",
        best.family,
        best.theta_d_deg,
        plain(best.mean),
        plain(best.median),
        analyses.len()
    );
    let f = Family::ALL
        .iter()
        .position(|f| *f == Family::Exponential)
        .expect("listed");
    outln!(
        "paper's pair: exponential at theta_d = {PROBE_THETA_D_DEG} deg: mean error {} 1/sr, median {} 1/sr",
        plain(summary.mean[f][PROBE_THETA_D_DEG]),
        plain(summary.median[f][PROBE_THETA_D_DEG])
    );
    for family in Family::ALL {
        // A family without a measured column prints as column 0 with an infinite error.
        let (j, mean) = summary.best_column(family).unwrap_or((0, f64::INFINITY));
        outln!(
            "  {family:<12} best column theta_d = {j:>2} deg: mean error {} 1/sr",
            plain(mean)
        );
    }
    outln!("  (base-k is the exponential family with k_base = e^k_exp: their errors agree to rounding)");
    outln!(
        "wrote analysis.csv, materials.csv and analysis.png to {}",
        args.out.display()
    );
    Ok(())
}

fn best_cell(best: &BestPair) -> (usize, usize) {
    let row = Family::ALL
        .iter()
        .position(|f| *f == best.family)
        .expect("listed");
    (row, best.theta_d_deg)
}

fn heatmap(
    summary: &DatabaseSummary,
    materials: usize,
    samples: usize,
    best: (usize, usize),
) -> Heatmap {
    Heatmap {
        title: format!("Mean slice error over {materials} materials: k fitted on column theta_d, {samples} samples"),
        x_label: "theta_d of the column k is fitted on (deg)".into(),
        x_values: (0..summary.mean[0].len()).map(|j| j as f64).collect(),
        row_labels: Family::ALL.iter().map(|f| f.name().to_string()).collect(),
        values: summary.mean.to_vec(),
        log_scale: true,
        value_label: "mean abs. error (1/sr)".into(),
        highlight: Some(best),
    }
}
