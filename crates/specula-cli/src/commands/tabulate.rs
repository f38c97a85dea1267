//! `specula tabulate`: any BRDF into a MERL `.binary` table at the bin centres.

use crate::range;
use anyhow::Result;
use specula_core::GridSpec;
use std::path::PathBuf;

/// Tabulate a BRDF into the MERL grid and write it as a MERL .binary file.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The BRDF: a preset name, a material .toml, a MERL .binary or a model:name fit.
    pub brdf: String,
    /// Azimuth of the half vector in degrees (matters only for anisotropic materials; 45 is the
    /// paper's choice, section 4.3). Range: degrees from -360 to 360.
    #[arg(long, default_value_t = GridSpec::paper().phi_h_deg, allow_negative_numbers = true, value_parser = range::AZIMUTH_DEG)]
    pub phi_h: f64,
    /// The MERL .binary file to write.
    #[arg(long, value_parser = crate::output::OUTPUT_FILE)]
    pub out: PathBuf,
}

pub(crate) fn run(args: Args) -> Result<()> {
    specula_core::request::check_merl_out(&args.out)?;
    let brdf = specula_formats::load_brdf(&args.brdf)?;
    let spinner = crate::progress::spinner("tabulating");
    let table = specula_core::tabulate::tabulate(brdf.as_ref(), args.phi_h.to_radians());
    spinner.finish_and_clear();
    table.write(&args.out)?;
    outln!(
        "wrote {} ({} of {} cells measured)",
        args.out.display(),
        table.measured_count(),
        specula_core::merl::CELLS
    );
    Ok(())
}
