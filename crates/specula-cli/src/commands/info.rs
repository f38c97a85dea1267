//! `specula info`: what a BRDF source holds.

use anyhow::Result;
use specula_core::merl::MerlBrdf;
use specula_reconstruct::uncertainty::{sidecar_path, RelativeUncertainty};
use std::path::Path;

/// Describe a BRDF source: format, grid, cells, statistics, peak, albedo, uncertainty.
///
/// A measured MERL table with its `.uncertainty.binary` beside it also gets the relative
/// uncertainty of its cells.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The BRDF: a MERL .binary, UTIA .bin, RGL .bsdf or samples .csv file, a material
    /// .toml, a preset name or a model:name fit.
    pub brdf: String,
}

pub(crate) fn run(args: Args) -> Result<()> {
    out!("{}", specula_report::describe_source(&args.brdf)?);
    if let Some(line) = uncertainty_line(Path::new(&args.brdf))? {
        outln!("{line}");
    }
    Ok(())
}

/// The relative uncertainty's summary of the MERL table at `path` from its sidecar, `None`
/// when it is no `.binary` or has none.
fn uncertainty_line(path: &Path) -> Result<Option<String>> {
    let sidecar = sidecar_path(path);
    if path.extension().is_none_or(|e| e != "binary") || !sidecar.is_file() {
        return Ok(None);
    }
    let table = MerlBrdf::read(path)?;
    let absolute = MerlBrdf::read(&sidecar)?;
    Ok(RelativeUncertainty::of_tables(&table, &absolute).line())
}
