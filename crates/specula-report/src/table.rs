//! The report of a MERL table: its probe and k-hat are taken from the table itself.

use crate::error::{OrReport, ReportError};
use crate::figures::{
    coverage_rows, errors, peak_fact, probe_figure, raw_samples_figure, renders, slice_figures,
};
use crate::view::Shown;
use crate::{generator, Progress, ReportOptions, PLACED_SAMPLES};
use specula_core::merl::MerlBrdf;
use specula_core::sampling::Family;
use specula_core::{Brdf, ProbeSpec};
use specula_reconstruct::provenance::Provenance;
use specula_sampling::Probe;
use specula_visual::plot::raw_samples::SampleGrid;
use specula_visual::report::{CoverageSection, KHatSection, MaterialSection, Report};
use std::path::Path;

/// The report of the MERL table `options.input`.
pub(crate) fn report(
    options: &ReportOptions,
    progress: &dyn Progress,
) -> Result<Report, ReportError> {
    let table = MerlBrdf::read(&options.input).or_report()?;
    let truth = options
        .truth
        .as_deref()
        .map(specula_formats::load_brdf)
        .transpose()
        .or_report()?;
    let name = table.name();
    let mut report = Report {
        title: options
            .title
            .clone()
            .unwrap_or_else(|| format!("BRDF report: {name}")),
        generator: generator(),
        material: Some(material(&table, &options.input)),
        ..Report::default()
    };
    let mut coverage = coverage_rows(&table, &options.input)?;
    progress.start("probe and k-hat", None);
    let settings = ProbeSpec::paper();
    let probe = Probe::take(&table, &settings);
    let fit = probe
        .as_ref()
        .ok()
        .map(|p| specula_sampling::fit_k(&p.column(), Family::Exponential, PLACED_SAMPLES))
        .transpose()
        .or_report()?;
    progress.finish();
    match (&probe, &fit) {
        (Ok(probe), Some(fit)) => {
            report.k_hat = Some(KHatSection {
                family: fit.function.family.to_string(),
                k: fit.function.k,
                fit_error: fit.error,
                probe_samples: probe.len(),
                placed_samples: PLACED_SAMPLES,
            });
        }
        (Err(e), _) => report.notes.push(format!("No probe could be taken: {e:#}")),
        _ => {}
    }
    if let Some(truth) = &truth {
        report.errors = Some(errors(
            &table,
            truth.as_ref(),
            options.truth.as_deref().unwrap_or(""),
            progress,
        ));
    }
    report.tables.push(crate::appearance::report_section(
        truth
            .as_ref()
            .map(|t| (options.truth.as_deref().unwrap_or(""), t.as_ref())),
        (&name, &table),
        specula_appearance::Options {
            extrapolated: crate::appearance::extrapolated_cells(&options.input.to_string_lossy())?,
            resolution_deg: None,
        },
    ));
    report
        .figures
        .extend(renders(&table, truth.as_deref(), options, progress)?);
    report
        .figures
        .extend(slice_figures(&table, truth.as_deref())?);
    let (provenance, uncertainty) = crate::view::sidecars(&options.input)?;
    let mut shown: Vec<Shown> = vec![(
        &name,
        &table,
        provenance.as_ref(),
        uncertainty.as_ref().map(|u| u as &dyn Brdf),
    )];
    if let (Some(label), Some(brdf)) = (options.truth.as_deref(), &truth) {
        shown.push((label, brdf.as_ref(), None, None));
    }
    report.viewer = Some(crate::view::viewer_of(&shown));
    if let (Ok(probe), Some(fit)) = (&probe, &fit) {
        let points = probe.points();
        report.figures.push(probe_figure(
            &points,
            &fit.function,
            PLACED_SAMPLES,
            settings.phi_h_deg,
            &name,
        )?);
    }
    if let Some(path) = &options.samples {
        let set = specula_formats::samples_csv::SampleSet::read(path).or_report()?;
        let raw = set.samples();
        let stem = path
            .file_stem()
            .map_or_else(|| "samples".into(), |s| s.to_string_lossy());
        let origin = path.display().to_string();
        let (measured, planned) = SampleGrid::new(raw)
            .map_err(|e| ReportError::within(&origin)(e.into()))?
            .coverage();
        report.figures.push(
            raw_samples_figure(raw, &stem, &origin)
                .map_err(|e| ReportError::within(&origin)(e.into()))?,
        );
        coverage.push((
            "planned cells measured (raw samples)".into(),
            measured,
            planned,
        ));
    }
    report.coverage = Some(CoverageSection { rows: coverage });
    Ok(report)
}

/// Name, source and peak of the table.
fn material(table: &MerlBrdf, path: &Path) -> MaterialSection {
    let mut facts = vec![(
        "format".to_string(),
        "MERL .binary (90 x 90 x 180 cells)".to_string(),
    )];
    let provenance = Provenance::beside(path).ok().flatten();
    facts.extend(peak_fact(table, provenance.as_ref()));
    MaterialSection {
        name: table.name(),
        source: path.display().to_string(),
        facts,
    }
}
