//! Specular gloss per ISO 2813 / ASTM D523 at 20, 60 and 85 degrees.
//!
//! Specular gloss is the relative luminous reflectance factor of a specimen in the mirror
//! direction: the luminous flux the glossmeter's receptor collects from the specimen over the
//! flux it collects from the primary standard under the same geometry, times 100 gloss units
//! (ASTM D523-14, 3.1.1 and 3.1.2; ISO 2813). The primary standard is highly polished black glass
//! of refractive index 1.567 (at 587.6 nm), assigned 100 GU at each geometry. Its specular
//! reflectance is Fresnel's, and only its front surface reflects.
//!
//! Aperture sizes (ASTM D523-14 Table 1; ISO 2813 specifies the same): full angles at
//! the specimen, in the plane of measurement x perpendicular to it:
//!
//! | geometry | source image | receptor |
//! |---|---|---|
//! | 20 deg | 0.75 x 2.5 deg | 1.80 x 3.6 deg |
//! | 60 deg | 0.75 x 2.5 deg | 4.4 x 11.7 deg |
//! | 85 deg | 0.75 x 2.5 deg | 4.0 x 6.0 deg |
//!
//! (The standards' tolerances, e.g. 1.80 +- 0.05 deg, are not modelled: the nominal sizes
//! are used.) The flux is integrated over both apertures ([`crate::aperture`]); the standard's
//! flux is Fresnel's reflectance integrated over the source image, which the receptor holds
//! whole (a mirror images the source onto the receptor's centre, and every receptor is larger
//! than the source image).

use crate::aperture::{self, Aperture, Beams, ExtrapolatedCells, Flux};
use specula_core::scattering::fresnel;
use specula_core::Brdf;

/// Refractive index of the polished black glass primary standard (ASTM D523, ISO 2813).
pub const BLACK_GLASS_INDEX: f64 = 1.567;

/// The source image of every geometry (ASTM D523-14 Table 1).
pub const SOURCE_IMAGE: Aperture = Aperture {
    in_plane_deg: 0.75,
    perpendicular_deg: 2.5,
};

/// One glossmeter geometry: the angle of incidence and the receptor aperture.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlossGeometry {
    /// Angle of incidence (and of reflection) from the normal.
    pub angle_deg: f64,
    /// The receptor aperture around the mirror direction (ASTM D523-14 Table 1).
    pub receptor: Aperture,
}

/// The 20, 60 and 85 degree geometries (ASTM D523-14 Table 1).
pub const GEOMETRIES: [GlossGeometry; 3] = [
    GlossGeometry {
        angle_deg: 20.0,
        receptor: Aperture {
            in_plane_deg: 1.80,
            perpendicular_deg: 3.6,
        },
    },
    GlossGeometry {
        angle_deg: 60.0,
        receptor: Aperture {
            in_plane_deg: 4.4,
            perpendicular_deg: 11.7,
        },
    },
    GlossGeometry {
        angle_deg: 85.0,
        receptor: Aperture {
            in_plane_deg: 4.0,
            perpendicular_deg: 6.0,
        },
    },
];

impl GlossGeometry {
    /// The source image and the receptor centred on the mirror direction.
    pub fn beams(&self) -> Beams {
        Beams {
            theta_deg: self.angle_deg,
            source: SOURCE_IMAGE,
            window: self.receptor,
            offset_deg: 0.0,
        }
    }

    /// The flux the receptor collects from the black glass standard: Fresnel's reflectance
    /// of index [`BLACK_GLASS_INDEX`] over the source image.
    pub fn standard_flux(&self) -> f64 {
        aperture::source_nodes(self.angle_deg, SOURCE_IMAGE)
            .into_iter()
            .map(|(wi, weight)| weight * fresnel::dielectric(wi.z, BLACK_GLASS_INDEX))
            .sum()
    }

    /// The receptor's flux from `brdf` and its gloss in GU.
    pub fn measure(
        &self,
        brdf: &dyn Brdf,
        extrapolated: Option<&ExtrapolatedCells>,
    ) -> (Flux, f64) {
        let flux = aperture::collect(brdf, &self.beams(), extrapolated);
        let gloss = 100.0 * flux.value / self.standard_flux();
        (flux, gloss)
    }
}
