//! `specula info`: what a BRDF source holds.

use anyhow::Result;

/// Describe a BRDF source: format, grid, measured cells, per-channel statistics, peak.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The BRDF: a MERL .binary, UTIA .bin, RGL .bsdf or samples .csv file, a material
    /// .toml, a preset name or a model:name fit.
    pub brdf: String,
}

pub(crate) fn run(args: Args) -> Result<()> {
    out!("{}", specula_report::describe_source(&args.brdf)?);
    Ok(())
}
