//! The materials of a database as a user names them (`specula analyze`, `specula
//! placement`): MERL files and folders, other BRDF sources, fits tables and the built-in
//! database, as the slices the analysis of paper 5.1 reads.

use crate::error::{OrReport, ReportError};
use specula_core::materials::builtin_database;
use specula_sampling::database::{merl_files, SliceSource};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The materials of a database.
#[derive(Clone, Debug, Default)]
pub struct DatabaseRequest {
    /// MERL `.binary` files, folders of them, or any other BRDF source.
    pub sources: Vec<String>,
    /// Fits tables whose every material is added (the MERL-100 sgd or abc fits).
    pub fits: Vec<PathBuf>,
    /// Add the built-in database of specular and glossy materials.
    pub builtin: bool,
}

impl DatabaseRequest {
    /// The materials in the order given: the sources, then the fits tables' materials, then
    /// the built-in ones; at least one.
    pub fn load(&self) -> Result<Vec<SliceSource>, ReportError> {
        let mut sources = Vec::new();
        for spec in &self.sources {
            let path = Path::new(spec);
            let is_merl = path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("binary"));
            if path.is_dir() || is_merl {
                let files = merl_files(path).or_report()?;
                sources.extend(files.into_iter().map(SliceSource::MerlFile));
            } else {
                let brdf = specula_formats::load_brdf(spec).or_report()?;
                sources.push(SliceSource::Brdf(brdf));
            }
        }
        for table in &self.fits {
            let fits = specula_formats::fits::load_fits(table).or_report()?;
            sources.extend(fits.into_iter().map(SliceSource::Brdf));
        }
        if self.builtin {
            let builtin = builtin_database().into_iter();
            sources.extend(builtin.map(|m| SliceSource::Brdf(Arc::new(m))));
        }
        if sources.is_empty() {
            return Err(ReportError::Options(
                "nothing to analyse: give MERL files or folders, BRDFs, --fits FILE.csv or --builtin",
            ));
        }
        Ok(sources)
    }
}
