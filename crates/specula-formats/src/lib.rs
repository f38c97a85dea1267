//! Reading BRDFs from everything Specula accepts: MERL tables, material presets and TOML
//! files, and (as they land) the measured formats and published model fits.

mod brdf_source;
pub mod catalog;
pub mod convert;
pub mod directions_csv;
mod fit_request;
pub mod fits;
pub mod input;
pub mod lafortune;
mod malformed;
pub mod material_fit;
pub mod nbrdf;
pub mod near_name;
pub mod renderer_export;
pub mod rgl;
pub mod samples_csv;
pub mod source;
pub mod utia;

pub use brdf_source::BrdfSource;
pub use fit_request::{run_fit, FitExports, FitOutcome, FitRequest, FitRequestError};
pub use source::{load_brdf, load_brdfs};
