//! The material TOML file: its schema, its checks and its one-line errors.
//!
//! ```toml
//! name = "my-chrome"
//! [base]
//! kind = "conductor"          # or "clearcoat"
//! distribution = "ggx"        # or "beckmann" (default ggx)
//! alpha = 0.02                # roughness, in [0.001, 1]
//! eta = [3.1, 3.2, 2.3]       # conductor: complex index eta + i k per channel R, G, B
//! k = [3.3, 3.3, 3.1]
//! # clearcoat instead: ior = 1.49 (default 1.5), color = [r, g, b] (base albedo, [0, 0.95])
//! [scratch]                   # optional
//! weight = 0.05               # scratched fraction of the surface, [0, 1]
//! alpha_along = 0.002
//! alpha_across = 0.2
//! orientation_deg = 30.0
//! distribution = "ggx"        # default ggx
//! ```

use super::clearcoat::{ClearCoat, MAX_BASE_ALBEDO};
use super::conductor::RoughConductor;
use super::material::{Base, Material};
use super::microfacet::Distribution;
use super::scratch::ScratchLobe;
use crate::brdf::Rgb;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// What is wrong with a material file; shown after the file's path, on one line.
#[derive(Debug, thiserror::Error)]
pub enum MaterialError {
    /// The I/O error is part of the message, not a `source`, so that error chains printed
    /// with `{:#}` show it once.
    #[error("{path}: cannot read: {error}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        error: std::io::Error,
    },
    /// A file or preset whose content is not a valid material.
    #[error("{origin}: {problem}")]
    Invalid {
        /// The file or preset.
        origin: String,
        /// The first problem, naming the field and its range.
        problem: String,
    },
}

/// The on-disk form of a [`Material`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialFile {
    /// The material's name.
    pub name: String,
    /// The `[base]` table: the conductor or clear-coated base.
    pub base: BaseFile,
    /// The optional `[scratch]` table.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scratch: Option<ScratchFile>,
}

/// The `[base]` table, selected by `kind`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum BaseFile {
    /// A rough conductor (`kind = "conductor"`).
    Conductor {
        /// The microfacet distribution (GGX unless given).
        #[serde(default)]
        distribution: Distribution,
        /// Roughness (dimensionless).
        alpha: f64,
        /// Real part of the complex index of refraction, per RGB channel.
        eta: [f64; 3],
        /// Extinction coefficient, per RGB channel.
        k: [f64; 3],
    },
    /// A clear coat over a diffuse colour (`kind = "clearcoat"`).
    Clearcoat {
        /// The coat's microfacet distribution (GGX unless given).
        #[serde(default)]
        distribution: Distribution,
        /// The coat's roughness (dimensionless).
        alpha: f64,
        /// The coat's index of refraction (1.5 unless given).
        #[serde(default = "default_coat_ior")]
        ior: f64,
        /// The diffuse albedo under the coat, linear RGB.
        color: [f64; 3],
    },
}

/// The optional `[scratch]` table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScratchFile {
    /// The scratch lobe's microfacet distribution (GGX unless given).
    #[serde(default)]
    pub distribution: Distribution,
    /// The lobe's weight against the base.
    pub weight: f64,
    /// Roughness along the scratches (dimensionless).
    pub alpha_along: f64,
    /// Roughness across the scratches (dimensionless).
    pub alpha_across: f64,
    /// Direction of the scratches from the frame's x axis, degrees.
    pub orientation_deg: f64,
}

fn default_coat_ior() -> f64 {
    1.5
}

impl Material {
    /// Reads a material file; errors name the file and the problem on one line.
    pub fn from_toml_file(path: impl AsRef<Path>) -> Result<Material, MaterialError> {
        let path = path.as_ref();
        let text =
            crate::bounded_read::read_toml_text(path).map_err(|error| MaterialError::Io {
                path: path.to_path_buf(),
                error,
            })?;
        parse(&text, &path.display().to_string())
    }

    /// Parses material TOML text; errors start with "material".
    pub fn from_toml_str(text: &str) -> Result<Material, MaterialError> {
        parse(text, "material")
    }

    /// The material as TOML text that [`Material::from_toml_str`] reads back unchanged.
    pub fn to_toml_string(&self) -> String {
        toml::to_string(&MaterialFile::from(self.clone()))
            .expect("a material file has only tables, strings, numbers and arrays")
    }
}

fn parse(text: &str, origin: &str) -> Result<Material, MaterialError> {
    let invalid = |problem: String| MaterialError::Invalid {
        origin: origin.to_string(),
        problem,
    };
    let file: MaterialFile =
        toml::from_str(text).map_err(|e| invalid(crate::toml_error::one_line(text, &e)))?;
    Material::try_from(file).map_err(invalid)
}

fn check(ok: bool, field: &str, rule: &str, value: impl std::fmt::Debug) -> Result<(), String> {
    if ok {
        Ok(())
    } else {
        Err(format!("{field} must be {rule}, got {value:?}"))
    }
}

/// The largest conductor index (eta and k): measured metals stay below 15 at visible
/// wavelengths; far beyond it the Fresnel term overflows (eta = 1e300 gives NaN).
const MAX_CONDUCTOR_INDEX: f64 = 100.0;

/// Roughness below 0.001 (a lobe of ~0.06 degrees) is below what a goniometer resolves and
/// what the energy checks cover.
fn check_alpha(field: &str, alpha: f64) -> Result<(), String> {
    check(
        (0.001..=1.0).contains(&alpha),
        field,
        "in [0.001, 1]",
        alpha,
    )
}

/// A material reads and writes as its file form: `MaterialFile`'s schema, checked by
/// `TryFrom<MaterialFile>`.
impl Serialize for Material {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        MaterialFile::from(self.clone()).serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for Material {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let file = MaterialFile::deserialize(deserializer)?;
        Material::try_from(file).map_err(serde::de::Error::custom)
    }
}

impl TryFrom<MaterialFile> for Material {
    type Error = String;

    fn try_from(file: MaterialFile) -> Result<Self, String> {
        check(
            !file.name.trim().is_empty(),
            "name",
            "non-empty",
            &file.name,
        )?;
        let base = match file.base {
            BaseFile::Conductor {
                distribution,
                alpha,
                eta,
                k,
            } => {
                check_alpha("base.alpha", alpha)?;
                let eta_ok = eta.iter().all(|&e| e > 0.0 && e <= MAX_CONDUCTOR_INDEX);
                let rule = format!("in (0, {MAX_CONDUCTOR_INDEX}] in every channel");
                check(eta_ok, "base.eta", &rule, eta)?;
                let k_ok = k.iter().all(|&v| (0.0..=MAX_CONDUCTOR_INDEX).contains(&v));
                let rule = format!("in [0, {MAX_CONDUCTOR_INDEX}] in every channel");
                check(k_ok, "base.k", &rule, k)?;
                let conductor = RoughConductor::new(distribution, alpha, eta.into(), k.into());
                Base::Conductor(conductor)
            }
            BaseFile::Clearcoat {
                distribution,
                alpha,
                ior,
                color,
            } => {
                check_alpha("base.alpha", alpha)?;
                check(ior > 1.0 && ior <= 4.0, "base.ior", "in (1, 4]", ior)?;
                let color_ok = color.iter().all(|&c| (0.0..=MAX_BASE_ALBEDO).contains(&c));
                let rule = format!("in [0, {MAX_BASE_ALBEDO}] in every channel");
                check(color_ok, "base.color", &rule, color)?;
                let coat = ClearCoat::new(distribution, alpha, ior, Rgb::from(color));
                Base::ClearCoat(coat)
            }
        };
        let scratch = file.scratch.map(ScratchLobe::try_from).transpose()?;
        Ok(Material {
            name: file.name,
            base,
            scratch,
        })
    }
}

impl TryFrom<ScratchFile> for ScratchLobe {
    type Error = String;

    fn try_from(s: ScratchFile) -> Result<Self, String> {
        check(
            (0.0..=1.0).contains(&s.weight),
            "scratch.weight",
            "in [0, 1]",
            s.weight,
        )?;
        check_alpha("scratch.alpha_along", s.alpha_along)?;
        check_alpha("scratch.alpha_across", s.alpha_across)?;
        let finite = s.orientation_deg.is_finite();
        check(
            finite,
            "scratch.orientation_deg",
            "finite",
            s.orientation_deg,
        )?;
        Ok(ScratchLobe::new(
            s.distribution,
            s.weight,
            s.alpha_along,
            s.alpha_across,
            s.orientation_deg,
        ))
    }
}

impl From<Material> for MaterialFile {
    fn from(m: Material) -> Self {
        let base = match &m.base {
            Base::Conductor(c) => BaseFile::Conductor {
                distribution: c.distribution(),
                alpha: c.alpha(),
                eta: c.eta.into(),
                k: c.k.into(),
            },
            Base::ClearCoat(c) => BaseFile::Clearcoat {
                distribution: c.distribution(),
                alpha: c.alpha(),
                ior: c.ior,
                color: c.base_color.into(),
            },
        };
        let scratch = m.scratch.as_ref().map(|s| ScratchFile {
            distribution: s.distribution(),
            weight: s.weight,
            alpha_along: s.alpha_along(),
            alpha_across: s.alpha_across(),
            orientation_deg: s.orientation_deg,
        });
        MaterialFile {
            name: m.name,
            base,
            scratch,
        }
    }
}
