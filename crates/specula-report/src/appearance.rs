//! The report's appearance section (`specula-appearance`'s figures of the table and of the
//! truth), and the extrapolated cells a table's provenance marks.

use crate::error::{OrReport, ReportError};
use specula_appearance::aperture::ExtrapolatedCells;
use specula_appearance::figures::text_rows;
use specula_appearance::{appearance, Appearance, Differences, Options, Tolerances, Verdict};
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

/// The report's appearance section, the verdict on the sample and the figures' warnings.
#[derive(Debug, Clone)]
pub struct AppearanceSection {
    /// The section's table.
    pub table: TableSection,
    /// The verdict of the tolerances on the sample, when tolerances were given.
    pub verdict: Option<Verdict>,
    /// Where a figure rests on extrapolated or unmeasured cells, or on angles finer than
    /// the instrument resolves, each line naming the BRDF (`chrome (reference): gloss_85:
    /// ...`): the page shows them, and whoever prints the figures elsewhere prints them too.
    pub warnings: Vec<String>,
}

/// The report's appearance section: the figures of the sample (with `options`) and, when
/// known, of the reference (or truth) it is compared with, first, the sample's differences
/// to it and, with `tolerances`, the verdict on them. Labels are given whole ("chrome
/// (reference)").
pub fn report_section(
    reference: Option<(&str, &dyn Brdf)>,
    sample: (&str, &dyn Brdf),
    options: Options,
    tolerances: Option<&Tolerances>,
) -> AppearanceSection {
    let mut labels = Vec::new();
    let mut figures = Vec::new();
    if let Some((label, brdf)) = reference {
        labels.push(label.to_string());
        figures.push(appearance(brdf, &Options::default()));
    }
    labels.push(sample.0.to_string());
    figures.push(appearance(sample.1, &options));
    let differences: Option<Vec<Differences>> = reference
        .is_some()
        .then(|| figures.iter().map(|f| f.against(&figures[0])).collect());
    let verdict = tolerances
        .zip(differences.as_ref())
        .and_then(|(t, d)| d.last().map(|d| t.verdict(d)));
    let refs: Vec<&Appearance> = figures.iter().collect();
    let mut header = vec!["figure".to_string()];
    header.extend(labels.iter().cloned());
    let mut rows = text_rows(&refs, differences.as_deref());
    let mut notes = vec![
        "Gloss per ISO 2813 / ASTM D523 (GU; black glass of index 1.567 = 100), haze and DOI per ASTM E430 (30 deg), haze at 20 deg per ISO 13803, CIELAB under D65 at the aspecular angles of ASTM E2194 (illumination 45 deg). R, G, B are taken as linear sRGB (Rec. 709 primaries, D65 white).".to_string(),
    ];
    if let Some((label, _)) = reference {
        notes.push(format!(
            "In brackets: the difference to {label}; dE00: CIEDE2000 to it."
        ));
    }
    if let (Some(verdict), Some(tolerances)) = (&verdict, tolerances) {
        let mut row = vec!["verdict".to_string()];
        row.extend(labels[..labels.len() - 1].iter().map(|_| String::new()));
        row.push(verdict.to_string());
        rows.push(row);
        let limits: Vec<String> = tolerances
            .limits()
            .iter()
            .map(|(name, limit)| format!("{name} {limit}"))
            .collect();
        notes.push(format!(
            "Verdict: pass when every figure's |difference| is within its tolerance ({}).",
            limits.join(", ")
        ));
    }
    let warnings: Vec<String> = labels
        .iter()
        .zip(&figures)
        .flat_map(|(label, f)| f.warnings.iter().map(move |w| format!("{label}: {w}")))
        .collect();
    notes.extend(warnings.iter().map(|w| format!("Warning, {w}.")));
    AppearanceSection {
        table: TableSection {
            title: "Appearance".into(),
            header,
            rows,
            notes,
        },
        verdict,
        warnings,
    }
}
