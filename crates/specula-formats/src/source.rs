//! The BRDF source resolver: every command that takes a BRDF takes one of these strings.
//!
//! - a path to a MERL `.binary` file;
//! - a path to a material `.toml` file (schema in docs/book/src/materials.md);
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

/// Resolves a BRDF source string as [`load_brdf`] does, with its scratches turned to
/// `scratch_orientation_deg` when one is given ([`Material::with_scratch_orientation`],
/// paper 4.3): then `spec` must name an analytic material, a preset or a material `.toml`.
pub fn load_brdf_scratched(spec: &str, scratch_orientation_deg: Option<f64>) -> Result<BrdfSource> {
    let Some(orientation_deg) = scratch_orientation_deg else {
        return load_brdf(spec);
    };
    let material = if spec.ends_with(".toml") && Path::new(spec).is_file() {
        Material::from_toml_file(spec)?
    } else if let Some(material) = materials::preset(spec) {
        material
    } else {
        return Err(argument_error(
            spec,
            "a scratch orientation needs an analytic material (a preset name or a material .toml)",
        ));
    };
    Ok(Arc::new(material.with_scratch_orientation(orientation_deg)))
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

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::HalfDiff;

    #[test]
    fn scratches_turn_an_analytic_material_and_refuse_the_rest() {
        let (wi, wo) = HalfDiff::from_degrees(3.0, 45.0, 30.0, 90.0).to_directions();
        let expected = materials::preset("silver-925")
            .unwrap()
            .with_scratch_orientation(135.0)
            .eval_rgb(wi, wo);
        let scratched = load_brdf_scratched("silver-925", Some(135.0)).unwrap();
        assert_eq!(scratched.eval(wi, wo), Some(expected));
        let plain = load_brdf_scratched("silver-925", None).unwrap();
        assert_ne!(plain.eval(wi, wo), Some(expected));

        let dir = tempfile::tempdir().unwrap();
        let toml = dir.path().join("silver.toml");
        let material = materials::preset("silver-925").unwrap();
        std::fs::write(&toml, material.to_toml_string()).unwrap();
        let from_file = load_brdf_scratched(&toml.to_string_lossy(), Some(135.0)).unwrap();
        assert_eq!(from_file.eval(wi, wo), Some(expected));

        let err = load_brdf_scratched("sgd:chrome-steel", Some(30.0))
            .err()
            .unwrap()
            .to_string();
        assert!(
            err.starts_with("sgd:chrome-steel: ") && err.contains("analytic material"),
            "{err}"
        );
    }
}
