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

use anyhow::{bail, Result};
use specula_core::materials::{self, Material};
use specula_core::{Brdf, MerlBrdf};
use std::path::Path;
use std::sync::Arc;

/// A loaded BRDF behind a shared pointer, so that parallel work can hold it.
pub type BrdfSource = Arc<dyn Brdf>;

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
            bail!("{spec}: is a directory, not a BRDF file (a MERL .binary, UTIA .bin, RGL .bsdf, samples .csv or a material .toml)")
        }
        _ if path.exists() => {
            bail!("{spec}: unrecognised BRDF file (expected a MERL .binary, UTIA .bin, RGL .bsdf, samples .csv or a material .toml)")
        }
        _ => match materials::preset(spec) {
            Some(material) => Ok(Arc::new(material)),
            None => bail!(
                "{spec}: no such file, preset or model fit (`specula materials` lists them){}",
                crate::catalog::did_you_mean(spec, &crate::catalog::all_names())
            ),
        },
    }
}
