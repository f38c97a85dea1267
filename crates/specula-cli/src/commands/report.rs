//! `specula report`: one self-contained HTML page about a measured BRDF (`specula-report`).

use anyhow::Result;
use specula_report::{write_report, ReportOptions};
use std::path::PathBuf;

/// Write one self-contained HTML report about a measured BRDF or a session.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The measured BRDF (a MERL .binary file) or a session journal (.sqlite).
    pub input: PathBuf,
    /// The HTML file to write.
    #[arg(long, value_parser = crate::output::OUTPUT_FILE)]
    pub out: PathBuf,
    /// The true BRDF, when known (a simulation): a preset, .toml, .binary or model:name.
    #[arg(long)]
    pub truth: Option<String>,
    /// The raw samples of the measurement (CSV theta_h,phi_h,theta_d,phi_d,r,g,b); with a
    /// .binary input only (a journal holds its samples).
    #[arg(long = "samples-csv")]
    pub samples: Option<PathBuf>,
    /// With a session journal: the MERL .binary to show instead of reconstructing the
    /// session's samples.
    #[arg(long)]
    pub table: Option<PathBuf>,
    /// Width and height of each render, pixels. Range: a whole number from 8 to 8192.
    #[arg(long, default_value_t = 320, value_parser = crate::range::IMAGE_PX)]
    pub size: usize,
    /// Camera rays per pixel of the renders. Range: a whole number from 1 to 65536.
    #[arg(long, default_value_t = 32, value_parser = crate::range::SAMPLES_PER_PIXEL)]
    pub spp: usize,
    /// The report's title (default: the input's material name).
    #[arg(long)]
    pub title: Option<String>,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let options = ReportOptions {
        input: args.input,
        truth: args.truth,
        samples: args.samples,
        table: args.table,
        size_px: args.size,
        spp: args.spp,
        title: args.title,
    };
    write_report(&options, &args.out, &crate::progress::Terminal::default())?;
    outln!("wrote {}", args.out.display());
    Ok(())
}
