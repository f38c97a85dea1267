//! Reflection haze and distinctness of image (DOI) per ASTM E430, and haze at 20 degrees
//! per ASTM E430 Test Method B / ISO 13803.
//!
//! ASTM E430 (Test Method A, 30 deg geometry, Hunter's abridged goniophotometry) reads the
//! reflectance `R_s` in the mirror direction and at fixed angles off it: 0.3 deg for
//! distinctness of image, 2 deg for narrow-angle haze (receptors at 28 or 32 deg). Its
//! figures are relative to the specimen's own specular reflectance:
//!
//! - `DOI = 100 (R_s - R_0.3) / R_s` (100 for a perfect mirror, falling as the image blurs);
//! - `haze = 100 R_2 / R_s` (0 for a perfect mirror).
//!
//! Off-specular readings here are the mean of both sides (offsets + and -).
//!
//! Test Method B and ISO 13803 read haze at 20 deg with receptors at 18.1 and 21.9 deg
//! (1.9 deg either side of the specular), beside the 20 deg gloss receptor, relative to the
//! flux of the gloss standard: `haze_20 = 100 (Phi_18.1 + Phi_21.9) / Phi_standard,20`.
//!
//! The angles above are the standards'. The sizes of E430's source and receptor slits were
//! not available to us: the slits here are our choice, narrow enough for the 0.3 deg reading
//! (source 0.05 x 1.0 deg, specular window 0.2 x 2.0 deg, off-specular windows 0.1 x 2.0 deg,
//! in the plane of measurement x across); the 20 deg haze windows are 0.8 deg wide, centred
//! on 18.1 and 21.9 deg, as high as the gloss receptor (3.6 deg), under the gloss source
//! image. Figures from another instrument's slits differ in scale, not in order.

use crate::aperture::{self, Aperture, Beams, ExtrapolatedCells, Flux};
use crate::gloss::{self, GEOMETRIES};
use specula_core::Brdf;

/// Angle of ASTM E430 Test Method A's geometry from the normal.
pub const E430_ANGLE_DEG: f64 = 30.0;
/// Offset of the distinctness-of-image reading from the specular (E430).
pub const DOI_OFFSET_DEG: f64 = 0.3;
/// Offset of the narrow-angle haze reading from the specular (E430: 28 or 32 deg).
pub const HAZE_OFFSET_DEG: f64 = 2.0;
/// Offset of the 20 deg haze receptors (E430 Test Method B, ISO 13803: 18.1 and 21.9 deg).
pub const HAZE_20_OFFSET_DEG: f64 = 1.9;

/// Our source slit for E430 (see the module documentation).
const E430_SOURCE: Aperture = Aperture {
    in_plane_deg: 0.05,
    perpendicular_deg: 1.0,
};
/// Our specular window for E430.
const E430_SPECULAR_WINDOW: Aperture = Aperture {
    in_plane_deg: 0.2,
    perpendicular_deg: 2.0,
};
/// Our off-specular windows for E430.
const E430_OFF_SPECULAR_WINDOW: Aperture = Aperture {
    in_plane_deg: 0.1,
    perpendicular_deg: 2.0,
};
/// Our 20 deg haze windows (ISO 13803).
const HAZE_20_WINDOW: Aperture = Aperture {
    in_plane_deg: 0.8,
    perpendicular_deg: 3.6,
};

/// The E430 readings and their figures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct E430 {
    /// Flux of the specular window.
    pub specular: Flux,
    /// Mean flux of the windows 0.3 deg off the specular.
    pub doi_reading: Flux,
    /// Mean flux of the windows 2 deg off the specular.
    pub haze_reading: Flux,
    /// `100 (R_s - R_0.3) / R_s`.
    pub doi: f64,
    /// `100 R_2 / R_s`.
    pub haze: f64,
}

/// Mean of the fluxes of two windows at `+offset_deg` and `-offset_deg`.
fn both_sides(
    brdf: &dyn Brdf,
    theta_deg: f64,
    source: Aperture,
    window: Aperture,
    offset_deg: f64,
    extrapolated: Option<&ExtrapolatedCells>,
) -> Flux {
    let side = |offset_deg| {
        aperture::collect(
            brdf,
            &Beams {
                theta_deg,
                source,
                window,
                offset_deg,
            },
            extrapolated,
        )
    };
    let (plus, minus) = (side(offset_deg), side(-offset_deg));
    let value = 0.5 * (plus.value + minus.value);
    let part = |f: &Flux| f.extrapolated_fraction * f.value;
    Flux {
        value,
        unmeasured_fraction: 0.5 * (plus.unmeasured_fraction + minus.unmeasured_fraction),
        extrapolated_fraction: if value > 0.0 {
            0.5 * (part(&plus) + part(&minus)) / value
        } else {
            0.0
        },
    }
}

/// DOI and haze per ASTM E430 Test Method A.
pub fn e430(brdf: &dyn Brdf, extrapolated: Option<&ExtrapolatedCells>) -> E430 {
    let specular = aperture::collect(
        brdf,
        &Beams {
            theta_deg: E430_ANGLE_DEG,
            source: E430_SOURCE,
            window: E430_SPECULAR_WINDOW,
            offset_deg: 0.0,
        },
        extrapolated,
    );
    let off = |offset_deg| {
        both_sides(
            brdf,
            E430_ANGLE_DEG,
            E430_SOURCE,
            E430_OFF_SPECULAR_WINDOW,
            offset_deg,
            extrapolated,
        )
    };
    let (doi_reading, haze_reading) = (off(DOI_OFFSET_DEG), off(HAZE_OFFSET_DEG));
    // Readings as reflectances per unit window width, so that windows of different widths
    // compare (a diffuse surface reads R_0.3 = R_s, DOI 0).
    let per_width = |f: &Flux, w: Aperture| f.value / w.in_plane_deg;
    let r_s = per_width(&specular, E430_SPECULAR_WINDOW);
    let r_doi = per_width(&doi_reading, E430_OFF_SPECULAR_WINDOW);
    let r_haze = per_width(&haze_reading, E430_OFF_SPECULAR_WINDOW);
    E430 {
        specular,
        doi_reading,
        haze_reading,
        doi: 100.0 * (r_s - r_doi) / r_s,
        haze: 100.0 * r_haze / r_s,
    }
}

/// Haze at 20 deg per ASTM E430 Test Method B / ISO 13803: the flux of both haze windows
/// relative to the black glass standard's 20 deg gloss flux, times 100.
pub fn haze_20(brdf: &dyn Brdf, extrapolated: Option<&ExtrapolatedCells>) -> (Flux, f64) {
    let geometry = GEOMETRIES[0];
    let reading = both_sides(
        brdf,
        geometry.angle_deg,
        gloss::SOURCE_IMAGE,
        HAZE_20_WINDOW,
        HAZE_20_OFFSET_DEG,
        extrapolated,
    );
    // Both windows together: twice their mean.
    (
        reading,
        100.0 * 2.0 * reading.value / geometry.standard_flux(),
    )
}
