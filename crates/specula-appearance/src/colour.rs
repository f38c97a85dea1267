//! Multi-angle colour of effect coatings (ASTM E2194, DIN 6175-2): CIELAB under D65 at the
//! aspecular angles of multi-angle spectrophotometers, the flop index and CIEDE2000.
//!
//! **Geometry.** Illumination at 45 deg from the normal; the viewing direction lies in the
//! plane of incidence at the aspecular angle `gamma` from the specular direction, towards
//! the illumination (ASTM E2194, E2175): 15, 25, 45, 75 and 110 deg, i.e. viewing at 30, 20
//! and 0 deg on the specular side and at 30 and 65 deg on the light's side. Each reading is
//! the BRDF at the nominal pair of directions (no aperture: the instruments' are a few
//! degrees wide, over which an effect coating's BRDF 15 deg or more from the peak is smooth).
//!
//! **Colour-space assumption.** Specula's BRDFs are RGB, not spectra. The R, G, B channels
//! are taken to be linear sRGB (IEC 61966-2-1): Rec. 709 primaries and the D65 white point,
//! so that R = G = B = 1 is the perfect reflecting diffuser's white. The reflectance factor
//! of a channel is `pi f_r` (the radiance factor under the instrument's geometry relative to
//! the perfect diffuser, CIE 15); it converts to XYZ by the sRGB matrix and to CIELAB with
//! the D65 white (CIE 15:2018). No spectral integration is done: a real instrument's D65
//! readings of a spectrally complex pigment would differ.
//!
//! Conversions and CIEDE2000 (CIE 142-2001; Sharma, Wu and Dalal 2005) come from the
//! `palette` crate.

use palette::color_difference::Ciede2000;
use palette::convert::FromColorUnclamped;
use palette::white_point::D65;
use palette::{Lab, LinSrgb, Xyz};
use specula_core::{Brdf, Rgb};
use std::f64::consts::PI;

/// Angle of illumination from the normal (ASTM E2194, DIN 6175-2).
pub const ILLUMINATION_DEG: f64 = 45.0;

/// The aspecular angles of ASTM E2194 / DIN 6175-2 multi-angle readings.
pub const ASPECULAR_DEG: [f64; 5] = [15.0, 25.0, 45.0, 75.0, 110.0];

/// CIELAB coordinates under D65: `[L*, a*, b*]`.
pub type LabD65 = [f64; 3];

/// The light's and the camera's directions of the reading at `aspecular_deg` (unit vectors
/// in the sample frame; the light on the -x side).
pub fn reading_directions(aspecular_deg: f64) -> (glam::DVec3, glam::DVec3) {
    let light = ILLUMINATION_DEG.to_radians();
    let view = (ILLUMINATION_DEG - aspecular_deg).to_radians();
    let wi = glam::DVec3::new(-light.sin(), 0.0, light.cos());
    let wo = glam::DVec3::new(view.sin(), 0.0, view.cos());
    (wi, wo)
}

/// CIELAB under D65 of a reflectance factor given as linear sRGB (see the module
/// documentation). Not clamped: near the specular an effect coating's L* exceeds 100.
pub fn lab_of_reflectance(rgb: Rgb) -> LabD65 {
    let xyz: Xyz<D65, f64> = Xyz::from_color_unclamped(LinSrgb::new(rgb.x, rgb.y, rgb.z));
    let lab: Lab<D65, f64> = Lab::from_color_unclamped(xyz);
    [lab.l, lab.a, lab.b]
}

/// CIELAB at each of [`ASPECULAR_DEG`]; `None` where the BRDF has not measured the pair.
pub fn multi_angle(brdf: &dyn Brdf) -> Vec<Option<LabD65>> {
    ASPECULAR_DEG
        .iter()
        .map(|&gamma| {
            let (wi, wo) = reading_directions(gamma);
            brdf.eval_smooth(wi, wo).map(|f| lab_of_reflectance(f * PI))
        })
        .collect()
}

/// The flop index of X-Rite and DuPont (Alman 1987), from L* at 15, 45 and 110 deg
/// aspecular: `FI = 2.69 (L*15 - L*110)^1.11 / (L*45)^0.86`; 0 for a solid colour whose
/// lightness does not fall with the angle (a negative difference counts as 0).
pub fn flop_index(l15: f64, l45: f64, l110: f64) -> f64 {
    2.69 * (l15 - l110).max(0.0).powf(1.11) / l45.powf(0.86)
}

/// CIEDE2000 colour difference between two CIELAB colours (kL = kC = kH = 1).
pub fn ciede2000(a: LabD65, b: LabD65) -> f64 {
    let lab = |c: LabD65| Lab::<D65, f64>::new(c[0], c[1], c[2]);
    lab(a).difference(lab(b))
}
