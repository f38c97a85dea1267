//! Appearance figures for the coatings industry from any BRDF: specular gloss (ISO 2813 /
//! ASTM D523), reflection haze and distinctness of image (ASTM E430, ISO 13803) and
//! multi-angle colour (ASTM E2194 / DIN 6175-2: CIELAB under D65, flop index, CIEDE2000).
//!
//! A glossmeter and a multi-angle spectrophotometer each read a few integrals of the
//! material's BRDF; with the whole BRDF they are computed here by integrating it over the
//! standards' apertures ([`aperture`]), for any [`specula_core::Brdf`].

pub mod aperture;
pub mod colour;
pub mod figures;
pub mod gloss;
pub mod haze;
pub mod tolerance;
pub mod uncertainty;

pub use figures::{appearance, Appearance, Differences, Options, Warning};
pub use tolerance::{Tolerances, Verdict};
