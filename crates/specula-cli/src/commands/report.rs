//! `specula report`: one self-contained HTML page (or its PDF) about a measured BRDF
//! (`specula-report`).

use anyhow::Result;
use specula_report::{run_report, Audience, ReportRequest, SampleInfo};
use std::path::PathBuf;

/// Write a self-contained report (HTML, or PDF) about a BRDF source or a session.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// What to report on: a BRDF source (.binary, .bsdf, .toml, preset, fit, ...) or a session
    /// journal (.sqlite).
    pub input: PathBuf,
    /// The report's file: .html, or .pdf (printed by headless Chromium).
    #[arg(long, value_parser = crate::output::OUTPUT_FILE)]
    pub out: PathBuf,
    /// A reference BRDF to compare the figures with (e.g. chrome).
    #[arg(long)]
    pub against: Option<String>,
    /// A tolerance file (TOML, [tolerances]: gloss_20 = 5.0, ...): a verdict; exit 3 on fail.
    #[arg(long, requires = "against")]
    pub tolerances: Option<PathBuf>,
    /// The sample's identifier, on the first page.
    #[arg(long = "sample-id")]
    pub sample_id: Option<String>,
    /// Who measured the sample, on the first page.
    #[arg(long)]
    pub operator: Option<String>,
    /// For whom, on the first page.
    #[arg(long)]
    pub customer: Option<String>,
    /// Whom the report is for: customer (figures, verdicts, pictures) or engineering (all).
    #[arg(long, default_value_t = Audience::Engineering)]
    pub audience: Audience,
    /// The true BRDF, when known (a simulation): a preset, .toml, .binary or model:name.
    #[arg(long)]
    pub truth: Option<String>,
    /// The raw samples of the measurement (CSV theta_h,phi_h,theta_d,phi_d,r,g,b); with a
    /// BRDF input only (a journal holds its samples).
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
    let options = ReportRequest {
        input: args.input,
        against: args.against,
        tolerances: args.tolerances,
        sample: SampleInfo {
            sample_id: args.sample_id,
            operator: args.operator,
            customer: args.customer,
        },
        audience: args.audience,
        truth: args.truth,
        samples: args.samples,
        table: args.table,
        size_px: args.size,
        spp: args.spp,
        title: args.title,
    };
    let page = run_report(&options, &args.out, &crate::progress::Terminal::default())?;
    outln!("wrote {}", args.out.display());
    if let Some(verdict) = &page.verdict {
        outln!("verdict: {verdict}");
    }
    crate::verdict::check(page.verdict.as_slice())
}
