//! `specula view`: the interactive BRDF viewer as one self-contained page
//! (`specula_report::view`).

use anyhow::Result;
use specula_report::view::{write_view, ViewOptions};
use std::path::PathBuf;

/// Write an interactive viewer of one or several BRDFs as one self-contained HTML page
/// (no network, opens from disk): the lobe as polar plots in and across the plane of
/// incidence with an incident-angle slider, linear or log; the characteristic slice
/// (theta_h x theta_d) as heatmaps on one colour scale with a phi_d slider; a sphere under a
/// point light you drag; and readouts under the pointer (angles, f_r in 1/sr per channel,
/// and for a reconstructed table whether the cell was measured, interpolated or
/// extrapolated, and its uncertainty when an OUT.uncertainty.binary lies beside it).
///
/// Examples: specula view chrome.binary sgd:chrome --out view.html;
/// specula view demo-out/silver-925/silver-925.session.sqlite silver-925 --out view.html
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The BRDFs, overlaid in this order: MERL .binary, UTIA .bin, RGL .bsdf or samples .csv
    /// files, material .toml files, preset names, model:name fits or session journals (.sqlite).
    #[arg(required = true)]
    pub brdf: Vec<String>,
    /// The HTML file to write.
    #[arg(long, value_parser = crate::output::OUTPUT_FILE)]
    pub out: PathBuf,
    /// The page's title (default: the BRDFs' names).
    #[arg(long)]
    pub title: Option<String>,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let options = ViewOptions {
        sources: args.brdf,
        title: args.title,
    };
    let summary = write_view(&options, &args.out, &crate::progress::Terminal::default())?;
    outln!(
        "wrote {} ({} BRDFs, {:.1} MB)",
        args.out.display(),
        summary.tables,
        summary.bytes as f64 / 1e6
    );
    Ok(())
}
