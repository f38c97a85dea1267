//! The BRDF source resolver: every command that takes a BRDF takes one of these strings.
//!
//! - a path to a MERL `.binary` file;
//! - a path to a material `.toml` file (schema in README);
//! - a preset name (`silver-925`, `green-paint`, `chrome`, `steel`, ...) or any name of the
//!   built-in material database (`gold-polished`, `paint-red-gloss`, ...);
//! - a published fit by `model:name` (added by the formats that provide them);
//! - a measured file recognised by its magic bytes or extension: RGL `.bsdf`, UTIA `.bin`,
//!   samples `.csv` (see [`crate::convert::FileFormat::detect`]);
//! - `sgd:NAME` and `abc:NAME` (Bagher 2012 and Löw 2012 fits of MERL-100, [`crate::fits`]),
//! - `lafortune:NAME` (Ngan et al. 2005 fits), `nbrdf:NAME` (neural fits of MERL-100),
//!   `nbrdf-rgl:NAME` and `nbrdf-nielsen:NAME` (of the RGL and Nielsen 2015 materials).

use crate::brdf_source::BrdfSource;
use crate::input::{argument_error, FormatError, Result};
use specula_core::materials::{self, Material};
use specula_core::MerlBrdf;
use std::path::Path;
use std::sync::Arc;

/// Resolves a BRDF source string, or a folder to every BRDF file in it, in name order
/// (files of a recognised format: [`crate::convert::FileFormat::detect`], MERL `.binary`,
/// material `.toml`); other files (README, checksums) are passed over.
pub fn load_brdfs(spec: &str) -> Result<Vec<BrdfSource>> {
    let folder = Path::new(spec);
    if !folder.is_dir() {
        return Ok(vec![load_brdf(spec)?]);
    }
    let mut paths: Vec<_> = std::fs::read_dir(folder)
        .map_err(|cause| FormatError::Folder {
            spec: spec.to_string(),
            cause,
        })?
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|path| path.is_file())
        .collect();
    paths.sort();
    let mut out = Vec::new();
    for path in paths {
        if is_brdf_file(&path)? {
            out.push(load_brdf(&path.to_string_lossy())?);
        }
    }
    if out.is_empty() {
        return Err(argument_error(spec, "the folder holds no BRDF file (a MERL .binary, UTIA .bin, RGL .bsdf, samples .csv or a material .toml)"));
    }
    Ok(out)
}

/// Whether [`load_brdf`] reads the file as a BRDF.
fn is_brdf_file(path: &Path) -> Result<bool> {
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    Ok(crate::convert::FileFormat::detect(path)?.is_some()
        || matches!(extension.as_deref(), Some("binary" | "toml")))
}

/// Resolves a BRDF source string (see the module documentation).
pub fn load_brdf(spec: &str) -> Result<BrdfSource> {
    if let Some((model, name)) = spec.split_once(':') {
        if model == "lafortune" {
            return Ok(Arc::new(crate::lafortune::Lafortune::by_name(name)?));
        }
        if let Some(set) = crate::nbrdf::NbrdfSet::from_prefix(model) {
            return Ok(Arc::new(crate::nbrdf::Nbrdf::load(set, name)?));
        }
        if let Some(fit) = crate::fits::FitModel::from_prefix(model) {
            return crate::fits::load_fit(fit, name);
        }
    }
    let path = Path::new(spec);
    if path.is_file() {
        if let Some(format) = crate::convert::FileFormat::detect(path)? {
            return Ok(crate::convert::Loaded::read(path, format)?.into_brdf());
        }
    }
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match extension.as_deref() {
        Some("binary") => Ok(Arc::new(MerlBrdf::read(path)?)),
        Some("toml") => Ok(Arc::new(Material::from_toml_file(path)?)),
        _ if path.is_dir() => {
            Err(argument_error(spec, "is a directory, not a BRDF file (a MERL .binary, UTIA .bin, RGL .bsdf, samples .csv or a material .toml)"))
        }
        _ if path.exists() => {
            Err(argument_error(spec, "unrecognised BRDF file (expected a MERL .binary, UTIA .bin, RGL .bsdf, samples .csv or a material .toml)"))
        }
        _ => match materials::preset(spec) {
            Some(material) => Ok(Arc::new(material)),
            None => Err(argument_error(
                spec,
                format!(
                    "no such file, preset or model fit (`specula materials` lists them){}",
                    crate::near_name::did_you_mean(spec, &crate::catalog::all_names())
                ),
            )),
        },
    }
}
