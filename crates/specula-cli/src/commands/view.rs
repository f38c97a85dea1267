//! `specula view`: the interactive BRDF viewer as one self-contained page
//! (`specula_report::view`).

use anyhow::Result;
use specula_report::view::{write_view, ViewOptions};
use std::path::PathBuf;

/// Write an interactive viewer of one or several BRDFs as one self-contained HTML page.
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
