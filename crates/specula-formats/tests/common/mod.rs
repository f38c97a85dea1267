//! Shared helpers of the integration tests: where the measured data and the committed
//! reference vectors are.

#![allow(dead_code)]

use std::path::PathBuf;

/// A file of the measured data directory (`shared/data/measured`, or `$SPECULA_MEASURED_DIR`),
/// or `None`, with the reason printed, where the data is absent: the test then skips.
pub(crate) fn measured(relative: &str) -> Option<PathBuf> {
    let path = specula_formats::input::measured_data_dir().join(relative);
    if path.is_file() {
        Some(path)
    } else {
        eprintln!(
            "skipped: {} is absent (put the shared data beside the clone as ../shared, or set SPECULA_MEASURED_DIR)",
            path.display()
        );
        None
    }
}

/// A file of this crate's `tests/data`.
pub(crate) fn test_data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// The five isotropic RGL files shipped in `rgl_bsdf/`.
pub(crate) const RGL_MATERIALS: [&str; 5] = [
    "cc_ibiza_sunset_rgb",
    "cc_iris_purple_gem_rgb",
    "colodur_napoli_4f_rgb",
    "paper_white_rgb",
    "satin_rosaline_rgb",
];

/// One row of the Mitsuba reference vectors: a direction pair (degrees) and f_r per channel.
#[derive(serde::Deserialize)]
pub(crate) struct MitsubaVector {
    pub theta_i: f64,
    pub phi_i: f64,
    pub theta_o: f64,
    pub phi_o: f64,
    pub r: f64,
    pub g: f64,
    pub b: f64,
}
