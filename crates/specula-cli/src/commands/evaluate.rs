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
///
/// The plan is the recommended grid unless told otherwise (see `specula plan --help`):
/// theta_h at the 16 positions of the exponential sampling function with k-hat fitted to the
/// material's probe (5.2: theta_d 40, phi_d 90, phi_h 45 deg, 90 square-root positions),
/// theta_d every 3 deg below 60 and every 1 deg from 60, phi_d 0, 30, ..., 180 deg at phi_h
/// 45 deg; --grid-preset paper gives the paper's (5.3: 30 theta_h, theta_d 0, 3, ..., 87,
/// phi_d 0, 15, ..., 90). The samples the device cannot take (limits, occlusion) are left
/// out, as a real measurement would. Samples that measure both halves of phi_d are
/// reconstructed half by half, as `specula reconstruct` does.
///
/// Figures (averaged over R, G, B; see `specula compare --help`): relative_rmse
/// (cosine-weighted), log_rmse (of ln(1 + f cos theta_i)) and slice_mae (the paper's
/// characteristic slice phi_d = 90), over the cells whose light and camera are both within
/// --max-elevation of the normal ("within") and over all cells above the surface ("all").
///
/// Examples:
///
///   specula evaluate --truth silver-925 --grid-preset paper --method linear   # the paper's pipeline
///
///   specula evaluate --builtin --method lobe                # the built-in database, a table
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The ground-truth BRDF: a measured file (RGL .bsdf, MERL .binary, UTIA .bin), a
    /// folder of them (every BRDF file in it, e.g. ../shared/data/measured/rgl_bsdf), a
    /// preset name, a material .toml or a model:name fit. Repeat for several. Real measured
    /// truths are the ones that judge a method: their figures are summarised apart from the
    /// built-in database and the fits.
    #[arg(long, required_unless_present_any = ["builtin", "merl_fits"])]
    pub truth: Vec<String>,
    /// Evaluate over every material of the built-in database (and the --truth ones) and
    /// print a table with the mean.
    #[arg(long)]
    pub builtin: bool,
    /// Evaluate over the 100 MERL materials as fitted by a published model: sgd (Bagher et
    /// al. 2012), abc (Low et al. 2012) or nbrdf (Sztrajman et al. 2021, neural). Repeat for
    /// several.
    #[arg(long, value_enum)]
    pub merl_fits: Vec<MerlFits>,
    /// Reconstruction method: lobe (ours: log ratio to a fitted microfacet lobe), prior (lobe
    /// blended with a MERL-100 data-driven prior as far as the samples trust it), log, or
    /// linear (the paper's baseline). lobe is the default because it is the best measured on
    /// real data: on the five RGL files, median 0.18 times the paper pipeline's relative RMSE
    /// on the default grid, 0.83 on the paper's samples; prior is no better there (README,
    /// "Real measured truths first").
    #[arg(long, default_value = "lobe")]
    pub method: Method,
    /// k of the theta_h sampling function; default: k-hat fitted to each material's probe.
    /// Range: a number above 0 and at most 100.
    #[arg(long, value_parser = crate::range::SAMPLING_K)]
    pub k: Option<f64>,
    /// How theta_h positions are placed: `function` (the sampling function, paper 5.2) or
    /// `probe` (the least-error placement on the material's probe).
    #[arg(long, default_value_t = PlacementChoice::Function)]
    pub placement: PlacementChoice,
    #[command(flatten)]
    pub grid: GridArgs,
    /// Device description (TOML) deciding which samples are taken; default: the paper's
    /// UTIA gonioreflectometer.
    #[arg(long)]
    pub device: Option<PathBuf>,
    /// Largest elevation (degrees from the normal) of light and camera for the "within"
    /// figures. Range: degrees above 0 and at most 90.
    #[arg(long, default_value_t = 75.0, value_parser = crate::range::ELEVATION_DEG)]
    pub max_elevation: f64,
    /// Measure through the instrument, as `specula measure` does without its noise: every
    /// sample, and the probe that places theta_h, is what a capture of the device gives
    /// (the truth integrated over the response of --device: the light's disk, the camera's
    /// pupil and the measured area; README, The instrument's response); the probe is
    /// deblurred before k is fitted and the method reconstructs through the response (`lobe`
    /// fits its lobe before the blur; `linear` and `log` have no model and keep the blur).
    #[arg(long)]
    pub through_instrument: bool,
    /// Also write the simulated samples (CSV, the input of `specula reconstruct`); one
    /// --truth only.
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
