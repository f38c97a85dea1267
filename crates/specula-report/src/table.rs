//! The report of a BRDF source (a MERL table, a measured file, a material, a fit): its
//! probe and k-hat are taken from its table.

use crate::error::{OrReport, ReportError};
use crate::figures::{
    coverage_rows, errors, peak_fact, probe_figure, raw_samples_figure, renders, slice_figures,
};
use crate::viewer::Shown;
use crate::{
    generator, header, layout, today, Audience, Page, Progress, ReportRequest, PLACED_SAMPLES,
};
use specula_appearance::Tolerances;
use specula_core::merl::MerlBrdf;
use specula_core::sampling::Family;
use specula_core::tabulate::tabulate;
use specula_core::{Brdf, ProbeSpec};
use specula_formats::BrdfSource;
use specula_reconstruct::provenance::Provenance;
use specula_sampling::Probe;
use specula_visual::plot::raw_samples::SampleGrid;
use specula_visual::report::{CoverageSection, KHatSection, MaterialSection, Report};
use std::path::Path;

/// The report of the BRDF source `options.input`: a MERL `.binary` as it is, any other
/// source tabulated on the MERL grid for the renders and the engineering sections (probe,
/// coverage, slices); the appearance figures are the source's own.
pub(crate) fn report(
    options: &ReportRequest,
    progress: &dyn Progress,
) -> Result<Page, ReportError> {
    let spec = options.input.to_string_lossy();
    let is_binary = options
        .input
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("binary"));
    // A .binary is its own table; any other source is tabulated for the pictures.
    let (table, source): (MerlBrdf, Option<BrdfSource>) = if is_binary {
        (MerlBrdf::read(&options.input).or_report()?, None)
    } else {
        let source = specula_formats::load_brdf(&spec).or_report()?;
        progress.start("tabulating on the MERL grid", None);
        let mut table = tabulate(source.as_ref(), 0.0);
        table.set_name(source.name());
        progress.finish();
        (table, Some(source))
    };
    let brdf: &dyn Brdf = source.as_deref().unwrap_or(&table);
    let name = brdf.name();
    let truth = options
        .truth
        .as_deref()
        .map(specula_formats::load_brdf)
        .transpose()
        .or_report()?;
    let against = options
        .against
        .as_deref()
        .map(specula_formats::load_brdf)
        .transpose()
        .or_report()?;
    let tolerances = options
        .tolerances
        .as_deref()
        .map(Tolerances::read)
        .transpose()
        .or_report()?;
    let engineering = options.audience == Audience::Engineering;
    let mut report = Report {
        title: options
            .title
            .clone()
            .unwrap_or_else(|| format!("BRDF report: {name}")),
        generator: generator(),
        layout: layout(options),
        header: header(options, today()),
        material: Some(material(&table, &options.input, &spec, is_binary)),
        ..Report::default()
    };
    // A file holds a measurement; a preset, a material file or a fit is a model.
    let sample_label = if is_measured_file(&options.input) {
        format!("{name} (measured)")
    } else {
        name.clone()
    };
    // Without a session nothing here was simulated: a truth given is a reference.
    let reference = match (&against, &truth) {
        (Some(brdf), _) => Some(brdf),
        (None, Some(brdf)) => Some(brdf),
        _ => None,
    }
    .map(|brdf| (format!("{} (reference)", brdf.name()), brdf.as_ref()));
    let section = crate::appearance::report_section(
        reference
            .as_ref()
            .map(|(label, brdf)| (label.as_str(), *brdf)),
        (&sample_label, brdf),
        specula_appearance::Options {
            extrapolated: crate::appearance::extrapolated_cells(&spec)?,
            resolution_deg: None,
        },
        tolerances.as_ref(),
    );
    report.tables.push(section.table);
    report.figures.extend(renders(
        (&table, &sample_label),
        reference
            .as_ref()
            .map(|(label, brdf)| (*brdf, label.as_str())),
        options,
        progress,
    )?);
    let (provenance, uncertainty) = crate::view::sidecars(&options.input)?;
    let mut shown: Vec<Shown> = vec![(
        &sample_label,
        &table,
        provenance.as_ref(),
        uncertainty.as_ref().map(|u| u as &dyn Brdf),
    )];
    if let Some((label, brdf)) = &reference {
        shown.push((label, *brdf, None, None));
    }
    // The interactive viewer is the engineer's: the customer's page keeps to the
    // figures, the verdict and the pictures.
    if engineering {
        report.viewer = Some(crate::viewer::viewer_of(&shown));
        engineering_sections(
            &mut report,
            options,
            (&table, uncertainty.as_ref()),
            truth.as_deref(),
            progress,
        )?;
    }
    Ok(Page {
        report,
        verdict: section.verdict,
        warnings: section.warnings,
    })
}

/// True when `input` is a measured file (not a material `.toml`, a preset or a fit).
fn is_measured_file(input: &Path) -> bool {
    input.is_file()
        && !input
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("toml"))
}

/// The engineer's sections of a table's report: k-hat of its probe, the coverage, the error
/// figures against a truth, the slices with the map of the table's relative uncertainty when
/// its sidecar is there, the probe and the raw samples.
fn engineering_sections(
    report: &mut Report,
    options: &ReportRequest,
    (table, uncertainty): (&MerlBrdf, Option<&MerlBrdf>),
    truth: Option<&dyn Brdf>,
    progress: &dyn Progress,
) -> Result<(), ReportError> {
    let name = table.name();
    let mut coverage = coverage_rows(table, &options.input)?;
    progress.start("probe and k-hat", None);
    let settings = ProbeSpec::paper();
    let probe = Probe::take(table, &settings);
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
    if let Some(truth) = truth {
        report.errors = Some(errors(
            table,
            truth,
            options.truth.as_deref().unwrap_or(""),
            progress,
        ));
    }
    report.figures.extend(slice_figures(
        table,
        truth.map(|t| (t, "reference")),
        uncertainty,
    )?);
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
    Ok(())
}

/// Name, source and peak of the table.
fn material(table: &MerlBrdf, path: &Path, spec: &str, is_binary: bool) -> MaterialSection {
    let format = if is_binary {
        "MERL .binary (90 x 90 x 180 cells)"
    } else {
        "read by its format; tabulated on the MERL grid (90 x 90 x 180 cells) for the pictures"
    };
    let mut facts = vec![("format".to_string(), format.to_string())];
    let provenance = Provenance::beside(path).ok().flatten();
    facts.extend(peak_fact(table, provenance.as_ref()));
    MaterialSection {
        name: table.name(),
        source: spec.to_string(),
        facts,
    }
}
