//! The BRDF source resolver: every command that takes a BRDF takes one of these strings.
//!
//! - a path to a MERL `.binary` file;
//! - a path to a material `.toml` file (schema in README);
//! - a preset name (`silver-925`, `green-paint`, `chrome`, `steel`, ...);
//! - a published fit by `model:name` (added by the formats that provide them).

use anyhow::{bail, Result};
use specula_core::{Brdf, MerlBrdf};
use std::path::Path;
use std::sync::Arc;

/// A loaded BRDF behind a shared pointer, so that parallel work can hold it.
pub type BrdfSource = Arc<dyn Brdf>;

/// Resolves a BRDF source string (see the module documentation).
pub fn load_brdf(spec: &str) -> Result<BrdfSource> {
    let path = Path::new(spec);
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match extension.as_deref() {
        Some("binary") => Ok(Arc::new(MerlBrdf::read(path)?)),
        _ if path.exists() => {
            bail!("{spec}: unrecognised BRDF file (expected a MERL .binary or a material .toml)")
        }
        _ => bail!("{spec}: no such file, preset or model fit"),
    }
}
