//! `specula plan`: the sparse sampling of paper 5.3 turned into device positions, with
//! reachability, occlusion, an execution order and a time estimate.

use super::grid_args::GridArgs;
use crate::interrupt::{blame_stop_unresumable, stop_on_ctrl_c};
use anyhow::{bail, Context, Result};
use specula_acquisition::ordering::transition_time_s;
use specula_acquisition::plan::PlanSummary;
use specula_formats::source::load_brdf;
use specula_session::journal::HdrChoice;
use specula_session::workflow::PlanOrder;
use specula_session::{run_plan, PlanRequest, ThetaH};
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
    let device = specula_acquisition::device::Device::load_or_utia(args.device.as_deref())?;
    if args.print_device {
        match &args.device {
            Some(_) => out!("{}", device.to_toml_string()),
            None => out!("{}", specula_acquisition::device::UTIA_TOML),
        }
        return Ok(());
    }
    let out = args.out.clone().context("--out is required")?;
    let theta_h = match (&args.theta_h_list, args.k) {
        (Some(list), _) => ThetaH::Positions(list.clone()),
        (None, Some(k)) => ThetaH::K(k),
        (None, None) => bail!("give --k or --theta-h-list"),
    };
    let truth = args.truth.as_deref().map(load_brdf).transpose()?;
    let request = PlanRequest {
        theta_h,
        family: args.grid.family,
        grid: args.grid.request(),
        order: args.order,
        hdr: args.hdr,
        truth,
    };
    request.validate()?;
    let stop = stop_on_ctrl_c().context("cannot watch for Ctrl-C")?;
    let progress = crate::progress::Terminal::default();
    let planned = run_plan(&request, &device, &stop, &progress)
        .map_err(|e| blame_stop_unresumable(e.into(), &stop))?;
    let chosen = planned.chosen(args.order);
    specula_core::atomic_file::write_with(&out, |file| {
        chosen.write_csv(file).map_err(std::io::Error::other)
    })
    .with_context(|| format!("{}: cannot write", out.display()))?;

    let (grid, nested, optimized) = (&planned.grid, &planned.nested, &planned.optimized);
    outln!("device: {}", device.name);
    outln!(
        "grid: {} theta_h x {} theta_d x {} phi_d at phi_h = {} deg (theta_d {}, phi_d step {} deg over the {})",
        planned.theta_h_deg.len(),
        grid.theta_d_deg().len(),
        grid.phi_d_deg().len(),
        grid.phi_h_deg,
        grid.theta_d,
        grid.phi_d_step_deg,
        grid.phi_d_span
    );
    let (nested_summary, optimized_summary) = planned.summaries(&device);
    print_summary(&nested_summary, &optimized_summary);
    outln!(
        "motion (moves + settling): nested {:.2} h, optimized {:.2} h ({:.0}% less)",
        transition_time_s(nested) / 3600.0,
        transition_time_s(optimized) / 3600.0,
        100.0 * (1.0 - transition_time_s(optimized) / transition_time_s(nested).max(1e-9))
    );
    outln!("captures: {}", planned.assumed);
    outln!(
        "predicted_hours={:.3}",
        chosen.summary(&device).duration_s() / 3600.0
    );
    outln!("wrote {} ({} order)", out.display(), args.order);
    Ok(())
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
