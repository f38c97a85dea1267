//! `specula compare`: error figures between two BRDFs.

use anyhow::Result;
use specula_accuracy::{Accuracy, USED_ELEVATION_DEG};
use specula_core::tabulate::tabulate;

/// Compare BRDF A against the reference B over the MERL grid (both are tabulated at the
/// bin centres first, at phi_h = 45 deg as `tabulate`; MERL files are used as they are).
///
/// Figures, over the cells measured in both (averaged over R, G, B):
///
///   relative_rmse  cosine-weighted relative RMSE: sqrt(sum w^2 (a-b)^2 / sum w^2 b^2),
///                  w = cos(theta_i) cos(theta_o); 0.1 means 10 percent of B's radiance.
///
///   log_rmse       sqrt(mean (ln(1 + a cos theta_i) - ln(1 + b cos theta_i))^2): weighs the
///                  peak and the tail alike.
///
///   slice_mae      the paper's figure: mean |a - b| (1/sr) on the characteristic slice
///                  phi_d = 90 deg.
///
/// The first row, `within`, is over the cells whose light and camera are both within
/// --max-elevation of the normal (the device's reach and the region people use, 75 deg by
/// default); the second, `all`, adds the grazing cells beyond it, where the surface is seen
/// edge-on and f_r can be large and change fast (they may dominate `all`). A note on stderr
/// says so.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The BRDF to judge.
    pub a: String,
    /// The reference BRDF.
    pub b: String,
    /// Largest elevation (degrees from the normal) of light and camera for the second set.
    /// Range: degrees above 0 and at most 90.
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
            "{label},{},{:.6},{:.6},{:.6e}",
            e.cells,
            e.relative_rmse,
            e.log_rmse,
            e.slice_mae
        );
    }
    eprintln!(
        "note: within: light and camera within {} deg of the normal; all: also the grazing cells beyond, where the surface is seen edge-on",
        args.max_elevation
    );
    Ok(())
}
