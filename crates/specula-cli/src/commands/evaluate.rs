//! `specula evaluate`: the accuracy harness. Measures a known BRDF on a plan without noise,
//! reconstructs it and prints the error figures.

use super::grid_args::GridArgs;
use crate::interrupt::{blame_stop_unresumable, stop_on_ctrl_c};
use anyhow::{bail, Context, Result};
use specula_accuracy::PlacementChoice;
use specula_accuracy::{run_evaluate, EvaluateRequest, MerlFits, TruthSets};
use specula_formats::samples_csv::SampleSet;
use specula_reconstruct::Method;
use std::path::PathBuf;

/// Measure a known BRDF on a plan without noise, reconstruct it and print the error.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The ground truth: any BRDF, or a folder of measured files.
    #[arg(long, required_unless_present_any = ["builtin", "merl_fits"])]
    pub truth: Vec<String>,
    /// Also evaluate every material of the built-in database.
    #[arg(long)]
    pub builtin: bool,
    /// Also evaluate the 100 MERL materials as fitted by sgd, abc or nbrdf.
    #[arg(long)]
    pub merl_fits: Vec<MerlFits>,
    /// Reconstruction method: lobe, prior, log or linear (the paper's).
    #[arg(long, default_value = "lobe")]
    pub method: Method,
    /// k of the sampling function; default: k-hat of each probe. Range: a number above 0 and at most 100.
    #[arg(long, value_parser = crate::range::SAMPLING_K)]
    pub k: Option<f64>,
    /// theta_h placement: `function` (paper 5.2) or `probe` (least error).
    #[arg(hide_short_help = true, long, default_value_t = PlacementChoice::Function)]
    pub placement: PlacementChoice,
    #[command(flatten)]
    pub grid: GridArgs,
    /// Device description (TOML); default: the paper's UTIA gonioreflectometer.
    #[arg(long)]
    pub device: Option<PathBuf>,
    /// Largest elevation of the "within" figures. Range: degrees above 0 and at most 90.
    #[arg(hide_short_help = true, long, default_value_t = 75.0, value_parser = crate::range::ELEVATION_DEG)]
    pub max_elevation: f64,
    /// Measure through the instrument's response, as `measure` does.
    #[arg(long)]
    pub through_instrument: bool,
    /// Also write the simulated samples (CSV); one --truth only.
    #[arg(long, conflicts_with_all = ["builtin", "merl_fits"], value_parser = crate::output::OUTPUT_FILE)]
    pub samples_out: Option<PathBuf>,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let request = EvaluateRequest {
        method: args.method,
        k: args.k,
        placement: args.placement,
        family: args.grid.family,
        grid: args.grid.request(),
        max_elevation_deg: args.max_elevation,
        through_instrument: args.through_instrument,
    };
    request.validate()?;
    if args.samples_out.is_some() && args.truth.len() != 1 {
        bail!("--samples-out needs exactly one --truth");
    }
    let device = specula_acquisition::device::Device::load_or_utia(args.device.as_deref())?;
    let truths = TruthSets {
        sources: args.truth,
        builtin: args.builtin,
        merl_fits: args.merl_fits,
    }
    .load()?;
    let stop = stop_on_ctrl_c().context("cannot watch for Ctrl-C")?;
    let progress = crate::progress::Terminal::default();
    let evaluation = run_evaluate(&request, &truths, &device, &stop, &progress)
        .map_err(|e| blame_stop_unresumable(e.into(), &stop))?;
    if let (Some(path), Some((_, row))) = (&args.samples_out, evaluation.rows.first()) {
        SampleSet::new(row.name.clone(), row.samples.clone()).write(path)?;
    }
    out!("{}", evaluation.table(&request));
    Ok(())
}
