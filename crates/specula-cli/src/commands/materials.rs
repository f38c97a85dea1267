//! `specula materials`: every BRDF Specula knows by name, with where it comes from.

use anyhow::{bail, Result};
use specula_formats::catalog::groups;
use specula_formats::near_name::did_you_mean;

/// List the BRDFs every command takes by name: the presets, the built-in database and the
/// published fits, each group with its provenance (model, source, licence, built in or
/// read from the measured data directory). Files (MERL .binary, UTIA .bin, RGL .bsdf,
/// samples .csv, material .toml) are taken by path as well.
///
/// With a FILTER, only the names containing it; none matching is an error that suggests
/// the nearest names.
///
/// Example: specula materials paint
#[derive(clap::Args)]
pub(crate) struct Args {
    /// Show only the names containing this text.
    pub filter: Option<String>,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let groups = groups()?;
    let mut shown = 0;
    for group in &groups {
        let names: Vec<&String> = group
            .names
            .iter()
            .filter(|n| args.filter.as_deref().is_none_or(|f| n.contains(f)))
            .collect();
        if names.is_empty() {
            continue;
        }
        shown += names.len();
        outln!(
            "{} ({} of them): {}",
            group.pattern,
            names.len(),
            group.provenance
        );
        for name in names {
            outln!("  {name}");
        }
    }
    if let (0, Some(filter)) = (shown, &args.filter) {
        let all: Vec<String> = groups.into_iter().flat_map(|g| g.names).collect();
        bail!(
            "no material name contains '{filter}'{}",
            did_you_mean(filter, &all)
        );
    }
    Ok(())
}
