//! Reading BRDFs from everything Specula accepts: MERL tables, material presets and TOML
//! files, and (as they land) the measured formats and published model fits.

pub mod source;

pub use source::{load_brdf, BrdfSource};
