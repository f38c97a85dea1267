//! `specula materials`: every BRDF Specula knows by name, with where it comes from.

use anyhow::{bail, Result};
use specula_formats::catalog::groups;
use specula_formats::near_name::did_you_mean;

/// List the BRDFs every command takes by name, with their provenance.
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
