//! `specula report`: one self-contained HTML page about a measured BRDF (`specula-report`).

use anyhow::Result;
use specula_report::{write_report, ReportOptions};
use std::path::PathBuf;

/// Write one self-contained HTML report (pictures embedded, no other file needed) about a
/// measured BRDF or a measurement session: the material, k-hat of its probe (paper 5.2), the
/// coverage, renders on a sphere and a speedshape in the studio, the characteristic slice
/// (Fig. 11) and the probe against the adaptive samples (Fig. 13); with a truth, the error
/// figures and the renders beside the truth with their difference.
///
/// INPUT is a MERL .binary (for instance from `specula reconstruct`; its provenance sidecar
/// OUT.provenance.npy is used when present; --samples-csv adds the raw samples, Fig. 15) or a
/// session journal (.sqlite, from `specula measure` or `specula demo`). From a journal the
/// report shows k-hat and the probe as measured, the samples measured of each stage's plan,
/// the duration (device time: the simulated clock on the simulator) against the time
/// model's estimate, the raw samples of the main stage, and the table reconstructed from
/// them with the session's method (or --table); a simulated session's own truth gives the
/// error figures unless --truth names another. An interrupted session is reported as far as
/// it got.
///
/// Examples: specula report silver.binary --truth silver-925 --out silver.html;
/// specula report demo-out/silver-925/silver-925.session.sqlite --out silver.html
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
