//! Colour for display: luminance, tone mapping, sRGB encoding and the false-colour scale of
//! the slice plots.
//!
//! Renders are linear radiance (what the EXR output keeps); a PNG is for eyes, so it is
//! exposed, tone-mapped with the ACES filmic curve (Narkowicz 2015 fit) and sRGB-encoded.

use glam::DVec3;

/// The colour of a cell that was not measured (paper Fig. 15: "non-measured blue areas").
pub const UNMEASURED_BLUE: [u8; 3] = [36, 84, 230];

pub use specula_core::brdf::luminance;

/// The sRGB transfer function (IEC 61966-2-1) of a linear value in `[0, 1]`.
pub fn srgb_encode(linear: f64) -> f64 {
    let x = linear.clamp(0.0, 1.0);
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// The ACES filmic tone curve (Narkowicz 2015): linear scene value to `[0, 1]`, keeping
/// highlights up to about 10 times the exposure from clipping abruptly.
pub fn aces_filmic(x: f64) -> f64 {
    let x = x.max(0.0);
    ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

/// A linear radiance as an 8-bit sRGB pixel after scaling by `2^exposure_ev` and tone mapping.
pub fn display_rgb8(linear: DVec3, exposure_ev: f64) -> [u8; 3] {
    let scale = exposure_ev.exp2();
    let channel = |v: f64| {
        let v = if v.is_finite() { v } else { 0.0 };
        (srgb_encode(aces_filmic(v * scale)) * 255.0).round() as u8
    };
    [channel(linear.x), channel(linear.y), channel(linear.z)]
}

/// The false colour (inferno: black, purple, orange, pale yellow; no blue, so that
/// [`UNMEASURED_BLUE`] stands out) of a value `t` in `[0, 1]`.
pub fn false_colour(t: f64) -> [u8; 3] {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let c = colorous::INFERNO.eval_continuous(t);
    [c.r, c.g, c.b]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_matches_the_standard_at_known_points() {
        assert_eq!(srgb_encode(0.0), 0.0);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-12);
        // 18 percent grey encodes to about 0.461 (118 of 255).
        assert!((srgb_encode(0.18) - 0.4614).abs() < 1e-3);
        // The two pieces meet continuously.
        let below = srgb_encode(0.003_130_7);
        let above = srgb_encode(0.003_130_9);
        assert!((below - above).abs() < 1e-5);
    }

    #[test]
    fn tone_curve_is_monotone_and_bounded() {
        let mut last = -1.0;
        for i in 0..1000 {
            let v = aces_filmic(i as f64 * 0.05);
            assert!(v >= last && (0.0..=1.0).contains(&v));
            last = v;
        }
        assert_eq!(display_rgb8(DVec3::ZERO, 0.0), [0, 0, 0]);
        assert_eq!(display_rgb8(DVec3::splat(f64::NAN), 0.0), [0, 0, 0]);
    }

    #[test]
    fn false_colour_has_no_blue_dominant_entries() {
        for i in 0..=100 {
            let [r, g, b] = false_colour(i as f64 / 100.0);
            assert!(!(b > r && b > g && b > 120), "{i}: {r} {g} {b}");
        }
        assert!((luminance(DVec3::ONE) - 1.0).abs() < 1e-12);
    }
}
