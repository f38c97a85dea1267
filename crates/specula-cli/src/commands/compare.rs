//! `specula compare`: error figures between two BRDFs.

use crate::output::error_figure;
use anyhow::Result;
use specula_accuracy::{Accuracy, USED_ELEVATION_DEG};
use specula_core::tabulate::tabulate;

/// Compare BRDF A against the reference B over the MERL grid.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The BRDF to judge.
    pub a: String,
    /// The reference BRDF.
    pub b: String,
    /// Largest elevation (degrees from the normal) of light and camera for the second set. Range:
    /// degrees above 0 and at most 90.
    #[arg(long, default_value_t = USED_ELEVATION_DEG, value_parser = crate::range::ELEVATION_DEG)]
    pub max_elevation: f64,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let phi_h_rad = specula_core::GridSpec::paper().phi_h_deg.to_radians();
    let a = tabulate(specula_formats::load_brdf(&args.a)?.as_ref(), phi_h_rad);
    let b = tabulate(specula_formats::load_brdf(&args.b)?.as_ref(), phi_h_rad);
    let accuracy = Accuracy::of(&a, &b, args.max_elevation);
    outln!("set,cells,relative_rmse,log_rmse,slice_mae");
    for (label, e) in [("within", accuracy.within), ("all", accuracy.all)] {
        outln!(
            "{label},{},{},{},{:.6e}",
            e.cells,
            error_figure(e.relative_rmse),
            error_figure(e.log_rmse),
            e.slice_mae
        );
    }
    eprintln!(
        "note: within: light and camera within {} deg of the normal; all: also the grazing cells beyond, where the surface is seen edge-on",
        args.max_elevation
    );
    Ok(())
}
