//! The interactive viewer (`specula_visual::viewer`) of BRDF sources: `specula view` writes it
//! as a page of its own ([`write_view`]); the report embeds it (`crate::viewer`).
//!
//! Every source the other commands read is taken (`specula_formats::load_brdf`: tables,
//! `.bsdf`, presets, fits, ...), and a session journal (`.sqlite`) gives the table its report
//! shows (reconstructed from its samples). A MERL `.binary` brings its sidecars when they lie
//! beside it: the provenance `OUT.provenance.npy` (each cell measured, interpolated or
//! extrapolated) and the standard uncertainty `OUT.uncertainty.binary` (a MERL table of the
//! uncertainty of f_r, 1/sr per channel).

use crate::error::{OrReport, ReportError};
use crate::viewer::compact_table;
use crate::{generator, Progress};
use specula_core::{Brdf, MerlBrdf};
use specula_reconstruct::provenance::Provenance;
use specula_visual::viewer::{viewer_page, CompactTable};
use std::path::{Path, PathBuf};

/// What `specula view` shows; the fields are its arguments.
#[derive(Clone, Debug)]
pub struct ViewOptions {
    /// The BRDF sources, overlaid in this order: anything `specula_formats::load_brdf`
    /// reads, or a session journal (`.sqlite`).
    pub sources: Vec<String>,
    /// The page's title (default: the sources' names).
    pub title: Option<String>,
}

/// What [`write_view`] wrote.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ViewSummary {
    /// Sources in the page.
    pub tables: usize,
    /// Size of the page, bytes.
    pub bytes: usize,
}

/// The uncertainty sidecar of a MERL table: `OUT.uncertainty.binary` beside `OUT.binary`.
pub fn uncertainty_path(merl_path: &Path) -> PathBuf {
    merl_path.with_extension("uncertainty.binary")
}

/// Whether `spec` names a session journal.
fn is_session(spec: &str) -> bool {
    let path = Path::new(spec);
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("sqlite"))
        && path.is_file()
}

/// The compact table of one source, with the sidecars of a MERL `.binary`.
fn source_table(spec: &str, progress: &dyn Progress) -> Result<CompactTable, ReportError> {
    if is_session(spec) {
        let (name, table, provenance) = crate::session::shown_of(Path::new(spec), progress)?;
        return Ok(compact_table(&name, &table, provenance.as_ref(), None));
    }
    let brdf = specula_formats::load_brdf(spec).or_report()?;
    let (provenance, uncertainty) = sidecars(Path::new(spec))?;
    Ok(compact_table(
        &brdf.name(),
        brdf.as_ref(),
        provenance.as_ref(),
        uncertainty.as_ref().map(|u| u as &dyn Brdf),
    ))
}

/// The sidecars beside a MERL `.binary` file: its provenance and its uncertainty, each when
/// there (none for other sources).
pub(crate) fn sidecars(path: &Path) -> Result<(Option<Provenance>, Option<MerlBrdf>), ReportError> {
    let is_merl = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("binary"))
        && path.is_file();
    if !is_merl {
        return Ok((None, None));
    }
    let uncertainty = uncertainty_path(path);
    Ok((
        Provenance::beside(path).or_report()?,
        uncertainty
            .is_file()
            .then(|| MerlBrdf::read(&uncertainty))
            .transpose()
            .or_report()?,
    ))
}

/// Write the viewer of `options.sources` to `out` as one self-contained HTML page.
pub fn write_view(
    options: &ViewOptions,
    out: &Path,
    progress: &dyn Progress,
) -> Result<ViewSummary, ReportError> {
    if options.sources.is_empty() {
        return Err(ReportError::Options("name at least one BRDF source"));
    }
    progress.start("tabulating", Some(options.sources.len() as u64));
    let mut tables = Vec::with_capacity(options.sources.len());
    for (done, spec) in options.sources.iter().enumerate() {
        tables.push(source_table(spec, progress)?);
        progress.set(done as u64 + 1);
    }
    progress.finish();
    let title = options.title.clone().unwrap_or_else(|| {
        let names: Vec<&str> = tables.iter().map(|t| t.name.as_str()).collect();
        format!("BRDF viewer: {}", names.join(", "))
    });
    let page = viewer_page(&title, &generator(), &tables);
    specula_core::atomic_file::write_bytes(out, page.as_bytes()).map_err(|source| {
        ReportError::Write {
            path: out.to_path_buf(),
            source,
        }
    })?;
    Ok(ViewSummary {
        tables: tables.len(),
        bytes: page.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::NoProgress;
    use specula_core::merl::CELLS;
    use specula_core::tabulate::tabulate;
    use specula_reconstruct::provenance::CellOrigin;

    #[test]
    fn a_table_brings_its_sidecars_and_presets_come_as_they_are() {
        let dir = tempfile::tempdir().unwrap();
        let binary = dir.path().join("steel.binary");
        let steel = specula_formats::load_brdf("steel").unwrap();
        tabulate(steel.as_ref(), 0.0).write(&binary).unwrap();
        let spec = binary.to_string_lossy().into_owned();
        let bare = source_table(&spec, &NoProgress).unwrap();
        assert!(bare.origins.is_none() && bare.uncertainty.is_none());

        let mut cells = vec![CellOrigin::Interpolated; CELLS];
        cells[0] = CellOrigin::Measured;
        Provenance { cells }
            .write(&dir.path().join("steel.provenance.npy"))
            .unwrap();
        tabulate(steel.as_ref(), 0.0)
            .write(&dir.path().join("steel.uncertainty.binary"))
            .unwrap();
        let full = source_table(&spec, &NoProgress).unwrap();
        assert!(full.origins.is_some());
        assert_eq!(full.uncertainty.as_ref(), Some(&full.values));

        let preset = source_table("steel", &NoProgress).unwrap();
        assert!(preset.origins.is_none());
        assert_eq!(preset.name, "steel");
    }

    #[test]
    fn write_view_names_what_it_cannot_read() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("view.html");
        let options = ViewOptions {
            sources: vec!["steel".into(), "no-such-thing".into()],
            title: None,
        };
        let error = write_view(&options, &out, &NoProgress).unwrap_err();
        assert!(error.to_string().contains("no-such-thing"), "{error}");
        assert!(!out.exists());
        let none = ViewOptions {
            sources: vec![],
            title: None,
        };
        assert!(write_view(&none, &out, &NoProgress).is_err());
        let ok = ViewOptions {
            sources: vec!["steel".into(), "chrome".into()],
            title: Some("two".into()),
        };
        let summary = write_view(&ok, &out, &NoProgress).unwrap();
        assert_eq!(summary.tables, 2);
        let page = std::fs::read_to_string(&out).unwrap();
        assert_eq!(page.len(), summary.bytes);
        assert!(page.contains("<title>two</title>"));
    }
}
