//! The report's appearance section (`specula-appearance`'s figures of the table and of the
//! truth), and the extrapolated cells a table's provenance marks.

use crate::error::{OrReport, ReportError};
use specula_appearance::aperture::ExtrapolatedCells;
use specula_appearance::figures::text_rows;
use specula_appearance::{appearance, Appearance, Differences, Options};
use specula_core::Brdf;
use specula_reconstruct::provenance::{sidecar_path, Provenance};
use specula_visual::report::TableSection;
use std::path::Path;

/// The cells a reconstruction extrapolated, from the provenance sidecar beside a `.binary`
/// (none for other sources or without a sidecar).
pub fn extrapolated_cells(spec: &str) -> Result<Option<ExtrapolatedCells>, ReportError> {
    let path = Path::new(spec);
    let sidecar = sidecar_path(path);
    if path.extension().and_then(|e| e.to_str()) != Some("binary") || !sidecar.is_file() {
        return Ok(None);
    }
    let provenance = Provenance::read(&sidecar).or_report()?;
    Ok(extrapolated_cells_of(&provenance))
}

/// The extrapolated cells of a reconstruction's provenance.
pub fn extrapolated_cells_of(provenance: &Provenance) -> Option<ExtrapolatedCells> {
    ExtrapolatedCells::new(
        provenance
            .cells
            .iter()
            .map(|c| c.is_extrapolated())
            .collect(),
    )
}

/// The report's appearance section: the figures of the measured table (with `options`)
/// and, when known, of the truth it is compared with, first, the table's differences to it.
pub fn report_section(
    truth: Option<(&str, &dyn Brdf)>,
    table: (&str, &dyn Brdf),
    options: Options,
) -> TableSection {
    let mut labels = Vec::new();
    let mut figures = Vec::new();
    if let Some((label, brdf)) = truth {
        labels.push(format!("{label} (truth)"));
        figures.push(appearance(brdf, &Options::default()));
    }
    labels.push(table.0.to_string());
    figures.push(appearance(table.1, &options));
    let differences: Option<Vec<Differences>> = truth
        .is_some()
        .then(|| figures.iter().map(|f| f.against(&figures[0])).collect());
    let refs: Vec<&Appearance> = figures.iter().collect();
    let mut header = vec!["figure".to_string()];
    header.extend(labels.iter().cloned());
    let mut notes = vec![
        "Gloss per ISO 2813 / ASTM D523 (GU; black glass of index 1.567 = 100), haze and DOI per ASTM E430 (30 deg), haze at 20 deg per ISO 13803, CIELAB under D65 at the aspecular angles of ASTM E2194 (illumination 45 deg). R, G, B are taken as linear sRGB (Rec. 709 primaries, D65 white). In brackets: the difference to the truth; dE00: CIEDE2000 to it.".to_string(),
    ];
    for (label, f) in labels.iter().zip(&figures) {
        notes.extend(f.warnings.iter().map(|w| format!("Warning, {label}: {w}.")));
    }
    TableSection {
        title: "Appearance".into(),
        header,
        rows: text_rows(&refs, differences.as_deref()),
        notes,
    }
}
