//! The interactive viewer (`specula_visual::viewer`) of BRDFs already loaded: each one's
//! compact table with the origin and uncertainty of its cells when known. The report of a
//! table or a session embeds it ([`viewer_of`]); `specula view` (`crate::view`) writes the
//! same tables as a page of its own.

use specula_core::Brdf;
use specula_reconstruct::provenance::Provenance;
use specula_visual::viewer::{viewer_fragment, CompactTable};

/// The compact table of a BRDF, with the origin of its cells and their uncertainty when
/// known.
pub(crate) fn compact_table(
    name: &str,
    brdf: &dyn Brdf,
    provenance: Option<&Provenance>,
    uncertainty: Option<&dyn Brdf>,
) -> CompactTable {
    let mut table = CompactTable::new(name, brdf);
    if let Some(provenance) = provenance {
        table = table.with_origins(|cell| provenance.cells[cell] as u8);
    }
    if let Some(uncertainty) = uncertainty {
        table = table.with_uncertainty(uncertainty);
    }
    table
}

/// One BRDF of a viewer the report embeds: its name, f_r, and the provenance and
/// uncertainty of its cells when known.
pub(crate) type Shown<'a> = (
    &'a str,
    &'a dyn Brdf,
    Option<&'a Provenance>,
    Option<&'a dyn Brdf>,
);

/// The viewer of BRDFs already loaded, as the report embeds it.
pub(crate) fn viewer_of(sources: &[Shown]) -> String {
    let tables: Vec<CompactTable> = sources
        .iter()
        .map(|(name, brdf, provenance, uncertainty)| {
            compact_table(name, *brdf, *provenance, *uncertainty)
        })
        .collect();
    viewer_fragment(&tables)
}
