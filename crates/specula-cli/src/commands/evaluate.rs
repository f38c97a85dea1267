//! `specula evaluate`: the accuracy harness. Measures a known BRDF on a plan without noise,
//! reconstructs it and prints the error figures.

use super::grid_args::GridArgs;
use anyhow::{bail, Context, Result};
use clap::ValueEnum;
use specula_accuracy::summary::{SetSummary, REAL_SET};
use specula_accuracy::{Accuracy, Measurement, PlacementChoice, PlanSettings};
use specula_acquisition::device::Device;
use specula_acquisition::response::InstrumentResponse;
use specula_core::materials::builtin_database;
use specula_core::sampling::SamplingFunction;
use specula_core::statistics::Statistic;
use specula_core::{Brdf, GridSpec};
use specula_formats::fits::{load_model, FitModel};
use specula_formats::nbrdf::NbrdfSet;
use specula_formats::samples_csv::SampleSet;
use specula_reconstruct::Method;
use std::path::PathBuf;
use std::sync::Arc;

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
    #[arg(long, value_enum)]
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

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum MerlFits {
    Sgd,
    Abc,
    Nbrdf,
}

impl MerlFits {
    /// The 100 fitted materials.
    fn load(self) -> Result<Vec<Arc<dyn Brdf>>> {
        match self {
            MerlFits::Sgd | MerlFits::Abc => {
                let model = if self == MerlFits::Sgd {
                    FitModel::Sgd
                } else {
                    FitModel::Abc
                };
                Ok(load_model(model)?)
            }
            MerlFits::Nbrdf => Ok(NbrdfSet::Merl100.load_all()?),
        }
    }
}

/// One evaluated material.
struct Row {
    /// The source it came from (a --truth argument, `builtin`, a MERL fit set).
    set: String,
    name: String,
    k: Option<f64>,
    measured: usize,
    accuracy: Accuracy,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let grid = args.grid.grid(None)?;
    check_args(&args)?;
    let settings = plan_settings(&args, grid)?;
    let device = super::load_device(args.device.as_deref())?;
    let truths = load_truths(&args)?;
    let bar = crate::progress::bar(truths.len() as u64, "evaluating");
    let mut rows = Vec::with_capacity(truths.len());
    for (set, truth) in &truths {
        let mut row = evaluate_one(truth.as_ref(), &args, &settings, &device)?;
        row.set.clone_from(set);
        rows.push(row);
        bar.inc(1);
    }
    bar.finish_and_clear();
    print_rows(&args, &grid, &rows);
    print_set_summaries(&rows);
    Ok(())
}

/// The truths with the set each belongs to: `real` for the --truth measured files and
/// folders, `given` for other --truth sources, `builtin`, and the MERL fit sets.
fn load_truths(args: &Args) -> Result<Vec<(String, Arc<dyn Brdf>)>> {
    let mut truths = Vec::new();
    for spec in &args.truth {
        let set = if std::path::Path::new(spec).exists() && !spec.ends_with(".toml") {
            REAL_SET
        } else {
            "given"
        };
        for truth in specula_formats::load_brdfs(spec)? {
            truths.push((set.to_string(), truth));
        }
    }
    if args.builtin {
        truths.extend(
            builtin_database()
                .into_iter()
                .map(|m| ("builtin".to_string(), Arc::new(m) as Arc<dyn Brdf>)),
        );
    }
    for fits in &args.merl_fits {
        let set = fits
            .to_possible_value()
            .map_or_else(String::new, |v| format!("merl-{}", v.get_name()));
        truths.extend(fits.load()?.into_iter().map(|t| (set.clone(), t)));
    }
    Ok(truths)
}

fn check_args(args: &Args) -> Result<()> {
    if let Some(k) = args.k {
        SamplingFunction::new(args.grid.family, k)?;
    }
    if args.samples_out.is_some() && args.truth.len() != 1 {
        bail!("--samples-out needs exactly one --truth");
    }
    Ok(())
}

/// The plan settings the flags describe, on `grid`.
fn plan_settings(args: &Args, grid: GridSpec) -> Result<PlanSettings> {
    let placement = args.placement.placement(args.grid.family, args.k)?;
    Ok(PlanSettings { placement, grid })
}

/// The plan for one material, its noise-free measurement, the reconstruction and the error.
fn evaluate_one(
    truth: &dyn Brdf,
    args: &Args,
    settings: &PlanSettings,
    device: &Device,
) -> Result<Row> {
    let name = truth.name();
    let response = instrument_response(args, device);
    let measurement = Measurement::simulate_through(truth, settings, device, response.as_ref())?;
    let measured = measurement.samples.len();
    if let Some(path) = &args.samples_out {
        SampleSet::new(name.clone(), measurement.samples.clone()).write(path)?;
    }
    let accuracy = measurement
        .accuracy(truth, args.method, args.max_elevation, response.as_ref())
        .with_context(|| format!("{name}: reconstructing {measured} samples"))?;
    Ok(Row {
        set: String::new(),
        name,
        k: measurement.k,
        measured,
        accuracy,
    })
}

/// The response the harness measures through (`--through-instrument`), else none.
fn instrument_response(args: &Args, device: &Device) -> Option<InstrumentResponse> {
    args.through_instrument.then(|| device.response())
}

fn print_rows(args: &Args, grid: &GridSpec, rows: &[Row]) {
    outln!(
        "# method {}{}, grid {} (theta_h by {}); within = light and camera <= {} deg",
        args.method,
        if args.through_instrument {
            " through the instrument's response"
        } else {
            ""
        },
        grid,
        match args.placement {
            PlacementChoice::Function => format!("the {} function", args.grid.family),
            PlacementChoice::Probe => "probe placement".to_string(),
        },
        args.max_elevation
    );
    outln!("material,k,measured,rel_rmse_within,log_rmse_within,slice_mae_within,rel_rmse_all,log_rmse_all,slice_mae_all");
    for row in rows {
        let k = row.k.map_or(String::new(), |k| format!("{k:.3}"));
        print_figures(&row.name, &k, row.measured as f64, &row.accuracy);
    }
    if rows.len() > 1 {
        let accuracies: Vec<Accuracy> = rows.iter().map(|r| r.accuracy).collect();
        let accuracy = Accuracy::combined(&accuracies, Statistic::Mean);
        let mut measured: Vec<f64> = rows.iter().map(|r| r.measured as f64).collect();
        let measured = Statistic::Mean.of(&mut measured);
        print_figures(&format!("mean of {}", rows.len()), "", measured, &accuracy);
    }
}

fn print_figures(name: &str, k: &str, measured: f64, a: &Accuracy) {
    outln!(
        "{name},{k},{measured:.0},{:.5},{:.5},{:.4e},{:.5},{:.5},{:.4e}",
        a.within.relative_rmse,
        a.within.log_rmse,
        a.within.slice_mae,
        a.all.relative_rmse,
        a.all.log_rmse,
        a.all.slice_mae
    );
}

/// For several truths: the median and the mean of each set's figures, real measured truths
/// first (`# set,statistic,materials,` and the figure columns).
fn print_set_summaries(rows: &[Row]) {
    if rows.len() < 2 {
        return;
    }
    outln!("# per set: set,statistic,materials,rel_rmse_within,log_rmse_within,slice_mae_within,rel_rmse_all,log_rmse_all,slice_mae_all");
    for summary in SetSummary::of(rows.iter().map(|r| (r.set.as_str(), r.accuracy))) {
        let a = &summary.accuracy;
        outln!(
            "# {},{},{},{:.5},{:.5},{:.4e},{:.5},{:.5},{:.4e}",
            summary.set,
            summary.statistic.name(),
            summary.materials,
            a.within.relative_rmse,
            a.within.log_rmse,
            a.within.slice_mae,
            a.all.relative_rmse,
            a.all.log_rmse,
            a.all.slice_mae
        );
    }
}
