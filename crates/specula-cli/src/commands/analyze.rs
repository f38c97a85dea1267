//! `specula analyze`: the database analysis of paper 5.1.

use crate::progress;
use anyhow::{bail, Context, Result};
use specula_core::GridSpec;
use specula_report::{database_heatmap, DatabaseRequest};
use specula_sampling::analysis::{
    analyze_slice, findings_text, write_materials_csv, DatabaseSummary,
};
use specula_sampling::database::map_slices;
use specula_sampling::slice::{CharacteristicSlice, THETA_H_NODES};
use std::path::PathBuf;

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
    /// Runs `work` on every material's characteristic slice (a BRDF's on `nodes` theta_h
    /// nodes) in parallel with a progress bar; the first failure (naming its source) stops
    /// the command.
    pub(crate) fn map<T: Send>(
        &self,
        label: &str,
        nodes: usize,
        work: impl Fn(&CharacteristicSlice) -> Result<T> + Sync,
    ) -> Result<Vec<T>> {
        let request = DatabaseRequest {
            sources: self.sources.clone(),
            fits: self.fits.clone(),
            builtin: self.builtin,
        };
        let sources = request.load()?;
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
    let Some(findings) = findings_text(&summary, analyses.len()) else {
        bail!("no material had a measured column");
    };
    database_heatmap(&summary, analyses.len(), args.theta_h_samples)
        .write_png(&args.out.join("analysis.png"))?;
    out!("{findings}");
    outln!(
        "wrote analysis.csv, materials.csv and analysis.png to {}",
        args.out.display()
    );
    Ok(())
}
