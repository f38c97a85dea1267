//! `specula plan`: the sparse sampling of paper 5.3 turned into device positions, with
//! reachability, occlusion, an execution order and a time estimate.

use super::grid_args::GridArgs;
use anyhow::{bail, Context, Result};
use specula_acquisition::ordering::{order, transition_time_s};
use specula_acquisition::plan::{Plan, PlanSummary};
use specula_core::sampling::SamplingFunction;
use specula_core::GridSpec;
use specula_session::estimate::{price_before_probe, ASSUMED_MATERIAL};
use specula_session::journal::HdrChoice;
use specula_session::workflow::PlanOrder;
use std::path::PathBuf;

/// Plan a measurement: grid to device positions, reachability, order and time.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// k of the sampling function (the material's k-hat). Range: a number above 0 and at most 100.
    #[arg(long, allow_negative_numbers = true, required_unless_present_any = ["theta_h_list", "print_device"], value_parser = crate::range::SAMPLING_K)]
    pub k: Option<f64>,
    /// Explicit theta_h positions, comma-separated. Range: degrees from 0 to 90.
    #[arg(long, value_delimiter = ',', conflicts_with = "k", value_parser = crate::range::THETA_H_DEG)]
    pub theta_h_list: Option<Vec<f64>>,
    #[command(flatten)]
    pub grid: GridArgs,
    /// Device description (TOML); default: the paper's UTIA gonioreflectometer.
    #[arg(long)]
    pub device: Option<PathBuf>,
    /// Order written to PLAN.csv: `optimized` or `nested` (the paper's).
    #[arg(long, default_value_t = PlanOrder::Optimized)]
    pub order: PlanOrder,
    /// HDR capture priced at each sample, as `measure --hdr`: `predicted` or `bracket`.
    #[arg(long, default_value_t = HdrChoice::Predicted)]
    pub hdr: HdrChoice,
    /// With --hdr predicted: the material whose brightness the exposures are predicted for
    /// (as `measure --truth`); default silver-925.
    #[arg(long)]
    pub truth: Option<String>,
    /// Where to write the plan (CSV).
    #[arg(long, required_unless_present = "print_device", value_parser = crate::output::OUTPUT_FILE)]
    pub out: Option<PathBuf>,
    /// Print the device description (TOML) and exit.
    #[arg(long)]
    pub print_device: bool,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let device = super::load_device(args.device.as_deref())?;
    if args.print_device {
        match &args.device {
            Some(_) => out!("{}", device.to_toml_string()),
            None => out!("{}", specula_acquisition::device::UTIA_TOML),
        }
        return Ok(());
    }
    let out = args.out.clone().context("--out is required")?;
    let grid = args.grid.grid(None)?;
    let theta_h = theta_h_positions(&args, &grid)?;
    let theta_d = grid.theta_d_deg();
    let phi_d = grid.phi_d_deg();

    let mut nested = Plan::from_grid(&theta_h, &theta_d, &phi_d, grid.phi_h_deg, &device);
    let spinner = crate::progress::spinner("ordering");
    let mut optimized = order(&nested);
    spinner.finish_and_clear();
    if args.truth.is_some() && args.hdr == HdrChoice::Bracket {
        bail!("--truth sets the brightness of predicted exposures: it needs --hdr predicted");
    }
    let truth = match args.hdr {
        HdrChoice::Predicted => Some(specula_formats::source::load_brdf(
            args.truth.as_deref().unwrap_or(ASSUMED_MATERIAL),
        )?),
        HdrChoice::Bracket => None,
    };
    let assumed = price_before_probe(
        &mut [&mut nested, &mut optimized],
        &device,
        truth,
        grid.phi_h_deg,
    )?;

    let chosen = match args.order {
        PlanOrder::Optimized => &optimized,
        PlanOrder::Nested => &nested,
    };
    specula_core::atomic_file::write_with(&out, |file| {
        chosen.write_csv(file).map_err(std::io::Error::other)
    })
    .with_context(|| format!("{}: cannot write", out.display()))?;

    outln!("device: {}", device.name);
    outln!(
        "grid: {} theta_h x {} theta_d x {} phi_d at phi_h = {} deg (theta_d {}, phi_d step {} deg over the {})",
        theta_h.len(),
        theta_d.len(),
        phi_d.len(),
        grid.phi_h_deg,
        grid.theta_d,
        grid.phi_d_step_deg,
        grid.phi_d_span
    );
    print_summary(&nested.summary(&device), &optimized.summary(&device));
    outln!(
        "motion (moves + settling): nested {:.2} h, optimized {:.2} h ({:.0}% less)",
        transition_time_s(&nested) / 3600.0,
        transition_time_s(&optimized) / 3600.0,
        100.0 * (1.0 - transition_time_s(&optimized) / transition_time_s(&nested).max(1e-9))
    );
    outln!("captures: {assumed}");
    outln!(
        "predicted_hours={:.3}",
        chosen.summary(&device).duration_s() / 3600.0
    );
    outln!("wrote {} ({} order)", out.display(), args.order);
    Ok(())
}

/// theta_h positions: the explicit list, or the sampling function's with the grid's count.
fn theta_h_positions(args: &Args, grid: &GridSpec) -> Result<Vec<f64>> {
    if let Some(list) = &args.theta_h_list {
        if list.is_empty() {
            bail!("--theta-h-list needs at least one value");
        }
        return Ok(list.clone());
    }
    let k = args.k.context("give --k or --theta-h-list")?;
    let function = SamplingFunction::new(args.grid.family, k)?;
    Ok(function.positions_deg(grid.theta_h_samples))
}

fn print_summary(nested: &PlanSummary, optimized: &PlanSummary) {
    outln!("samples: {}", nested.total);
    outln!("measurable: {}", nested.measurable);
    outln!(
        "excluded: {} (limit {}, occluded {})",
        nested.limit + nested.occluded,
        nested.limit,
        nested.occluded
    );
    for (reason, count) in &nested.occluded_by {
        outln!("  occluded, {reason}: {count}");
    }
    outln!("time           moves   settle  captures     total");
    for (label, s) in [("nested", nested), ("optimized", optimized)] {
        outln!(
            "{label:<10} {:>8.2} h {:>6.2} h {:>7.2} h {:>7.2} h",
            s.move_s / 3600.0,
            s.settle_s / 3600.0,
            s.capture_s / 3600.0,
            s.duration_s() / 3600.0
        );
    }
}
