//! `specula coverage`: whether a measured table's uncertainty covers its error against the
//! truth it was measured from (the simulator).

use anyhow::{Context, Result};
use specula_accuracy::coverage::{cell_coverage, Coverage};
use specula_accuracy::USED_ELEVATION_DEG;
use specula_core::merl::MerlBrdf;
use specula_core::tabulate::tabulate;
use specula_reconstruct::provenance::Provenance;
use specula_reconstruct::uncertainty::sidecar_path;
use std::path::PathBuf;

/// Share of a measured table's cells whose truth lies within 2u (k = 2).
///
/// From the table's .uncertainty.binary and .provenance.npy beside it, over the cells measured
/// and interpolated within --max-elevation.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The measured MERL table (`specula measure --truth ... --out TABLE`).
    pub table: PathBuf,
    /// The truth it was measured from.
    pub truth: String,
    /// Largest elevation (degrees from the normal) of light and camera. Range: degrees above
    /// 0 and at most 90.
    #[arg(long, default_value_t = USED_ELEVATION_DEG, value_parser = crate::range::ELEVATION_DEG)]
    pub max_elevation: f64,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let table = MerlBrdf::read(&args.table)?;
    let sidecar = sidecar_path(&args.table);
    if !sidecar.is_file() {
        anyhow::bail!(
            "{}: no uncertainty beside the table (measure or reconstruct writes it)",
            sidecar.display()
        );
    }
    let uncertainty = MerlBrdf::read(&sidecar)?;
    let provenance = Provenance::beside(&args.table)?
        .with_context(|| format!("{}: no provenance beside the table", args.table.display()))?;
    let phi_h_rad = specula_core::GridSpec::paper().phi_h_deg.to_radians();
    let truth = tabulate(specula_formats::load_brdf(&args.truth)?.as_ref(), phi_h_rad);
    let coverage = cell_coverage(
        &table,
        &uncertainty,
        &provenance,
        &truth,
        args.max_elevation,
    );
    outln!("cells,values,covered_k2,fraction,above");
    for (label, c) in [
        ("measured", coverage.measured),
        ("interpolated", coverage.interpolated),
        ("both", coverage.both),
    ] {
        outln!("{label},{}", row(&c));
    }
    Ok(())
}

fn row(c: &Coverage) -> String {
    format!(
        "{},{},{},{}",
        c.values,
        c.covered,
        c.fraction()
            .map_or_else(|| "none".into(), |f| format!("{f:.4}")),
        c.above
    )
}
