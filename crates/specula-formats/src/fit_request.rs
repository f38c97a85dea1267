//! What `specula fit` and `specula.fit` ask (the models, the elevation limit, the exports),
//! checked in one place ([`FitRequest::validate`]), and the one entry point both call
//! ([`run_fit`]): fit the models ([`fit_models`]) and write the best one for each renderer
//! asked for.

use crate::material_fit::{
    fit_models, ExportReason, FitChoice, FitError, MaterialFit, METAL_MIN_K,
};
use crate::renderer_export::ExportError;
use crate::renderer_export::{gltf_document, mitsuba_scene, mitsuba_warning, pbrt_material};
use specula_core::atomic_file::write_bytes;
use specula_core::materials::Base;
use specula_core::range::RangeError;
use specula_core::request::ELEVATION_DEG;
use specula_core::tabulate::tabulate;
use specula_core::{Brdf, GridSpec};
use std::path::{Path, PathBuf};

/// The files a fit writes, each when given.
#[derive(Debug, Clone, Default)]
pub struct FitExports {
    /// A Specula material `.toml` (loadable by every command).
    pub out: Option<PathBuf>,
    /// A Mitsuba 3 scene (`.xml`): a sphere with the material under a white environment.
    pub mitsuba: Option<PathBuf>,
    /// The pbrt-v4 `Material` directive.
    pub pbrt: Option<PathBuf>,
    /// A glTF 2.0 document (`.gltf`) holding the material.
    pub gltf: Option<PathBuf>,
}

/// What a fit is asked for.
#[derive(Debug, Clone)]
pub struct FitRequest {
    /// Which models to fit; the better one is exported.
    pub model: FitChoice,
    /// Largest elevation (degrees from the normal) of light and camera of the fitted cells,
    /// in [`ELEVATION_DEG`].
    pub max_elevation_deg: f64,
    /// The files to write.
    pub exports: FitExports,
}

impl Default for FitRequest {
    /// Both models within 75 deg, nothing written.
    fn default() -> Self {
        FitRequest {
            model: FitChoice::Both,
            max_elevation_deg: 75.0,
            exports: FitExports::default(),
        }
    }
}

impl FitRequest {
    /// Checks the elevation limit's range (the error names `max_elevation_deg`; the CLI's
    /// parser says the same words after `--max-elevation`).
    pub fn validate(&self) -> Result<(), RangeError> {
        ELEVATION_DEG
            .check("max_elevation_deg", self.max_elevation_deg)
            .map(|_| ())
    }
}

/// Why a fit request failed.
#[derive(Debug, thiserror::Error)]
pub enum FitRequestError {
    /// A value outside its range.
    #[error(transparent)]
    Range(#[from] RangeError),
    /// The named source could not be fitted.
    #[error("{name}: cannot fit")]
    Fit {
        /// The source as given.
        name: String,
        /// Why.
        source: FitError,
    },
    /// The material cannot be written for a renderer.
    #[error(transparent)]
    Export(#[from] ExportError),
    /// A file could not be written.
    #[error("{}: cannot write", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
}

/// The fits, the one exported first, and what was written.
#[derive(Debug, Clone)]
pub struct FitOutcome {
    /// The fits in the order of export ([`fit_models`]).
    pub fits: Vec<MaterialFit>,
    /// Why the first is the one exported.
    pub reason: ExportReason,
    /// What the user should know about the exported files, one line each: a conductor
    /// exported with a dielectric's `k`, a coat Mitsuba renders darker.
    pub notes: Vec<String>,
    /// The files written, in [`FitExports`]' order.
    pub written: Vec<PathBuf>,
}

impl FitOutcome {
    /// The exported fit.
    pub fn exported(&self) -> &MaterialFit {
        &self.fits[0]
    }
}

/// Fits `request`'s models to `brdf` (tabulated at the paper's phi_h into the MERL grid)
/// and writes the best for each renderer asked for; `name` is the source as given, for
/// the errors.
pub fn run_fit(
    request: &FitRequest,
    brdf: &dyn Brdf,
    name: &str,
) -> Result<FitOutcome, FitRequestError> {
    request.validate()?;
    let table = tabulate(brdf, GridSpec::paper().phi_h_deg.to_radians());
    let fits = fit_models(
        &table,
        request.model.models(),
        request.max_elevation_deg,
        &brdf.name(),
    )
    .map_err(|source| FitRequestError::Fit {
        name: name.to_string(),
        source,
    })?;
    let best = &fits[0];
    let mut notes = Vec::new();
    if let Base::Conductor(c) = &best.material.base {
        if !best.is_metal_like() {
            notes.push(format!(
                "the conductor's k is at most {:.2}, not a metal's (at least {METAL_MIN_K}): the data look dielectric; the coat model fits a dielectric",
                c.k.max_element()
            ));
        }
    }
    let exports = &request.exports;
    if exports.mitsuba.is_some() {
        notes.extend(mitsuba_warning(&best.material));
    }
    let texts = [
        (&exports.out, Ok(best.material.to_toml_string())),
        (&exports.mitsuba, mitsuba_scene(&best.material)),
        (&exports.pbrt, pbrt_material(&best.material)),
        (&exports.gltf, gltf_document(&best.material)),
    ];
    let mut written = Vec::new();
    for (path, text) in texts {
        if let Some(path) = path {
            save(path, &text?)?;
            written.push(path.clone());
        }
    }
    Ok(FitOutcome {
        reason: ExportReason::of(&fits),
        fits,
        notes,
        written,
    })
}

/// Writes `text` to `path` atomically.
fn save(path: &Path, text: &str) -> Result<(), FitRequestError> {
    write_bytes(path, text.as_bytes()).map_err(|source| FitRequestError::Write {
        path: path.to_path_buf(),
        source,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_elevation_out_of_range_is_refused_before_any_fit() {
        let request = FitRequest {
            max_elevation_deg: 95.0,
            ..FitRequest::default()
        };
        let chrome = crate::load_brdf("chrome").unwrap();
        let error = run_fit(&request, chrome.as_ref(), "chrome").unwrap_err();
        assert_eq!(
            error.to_string(),
            "max_elevation_deg 95: expected degrees above 0 and at most 90"
        );
    }
}
