//! Reading BRDFs from everything Specula accepts: MERL tables, material presets and TOML
//! files, and (as they land) the measured formats and published model fits.

pub mod catalog;
pub mod convert;
pub mod fits;
pub mod input;
pub mod lafortune;
pub mod nbrdf;
pub mod rgl;
pub mod samples_csv;
pub mod source;
pub mod utia;

pub use source::{load_brdf, load_brdfs, BrdfSource};
