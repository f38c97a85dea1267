//! The 24 patches of the X-Rite ColorChecker Classic, the colour target of paper 4.1 ("we
//! perform color calibration of the camera using the X-Rite Color Checker target").
//!
//! Reference values: X-Rite's published CIE L*a*b* (D50, 2 degree observer) of the chart
//! editions from November 2014 on (X-Rite, "New color specifications for ColorChecker SG and
//! Classic charts", 2015; the same values as colour-science's "ColorChecker24 - After
//! November 2014"). They are converted here to linear sRGB (IEC 61966-2-1, D65): L*a*b* to
//! XYZ with the ICC D50 white, a Bradford adaptation to D65, and the sRGB matrix. The
//! conversion is checked against colour-science (`tools/colorchecker_reference.py`,
//! `tests/data/colorchecker_linear_srgb.csv`).
//!
//! The cyan patch lies outside the sRGB gamut (its linear red is -0.044); as a reflectance of
//! a simulated target and as a fitting reference it is clipped to 0 ([`Patch::reflectance`]).

use glam::{DMat3, DVec3};

/// One patch: its name and published L*a*b* (D50).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Patch {
    /// The patch's name, e.g. `dark skin`.
    pub name: &'static str,
    /// Published CIE L*a*b* under D50: L* in [0, 100], then a* and b*.
    pub lab_d50: [f64; 3],
}

/// The 24 patches, row by row from dark skin to black.
pub const PATCHES: [Patch; 24] = [
    patch("dark skin", 37.54, 14.37, 14.92),
    patch("light skin", 64.66, 19.27, 17.50),
    patch("blue sky", 49.32, -3.82, -22.54),
    patch("foliage", 43.46, -12.74, 22.72),
    patch("blue flower", 54.94, 9.61, -24.79),
    patch("bluish green", 70.48, -32.26, -0.37),
    patch("orange", 62.73, 35.83, 56.50),
    patch("purplish blue", 39.43, 10.75, -45.17),
    patch("moderate red", 50.57, 48.64, 16.67),
    patch("purple", 30.10, 22.54, -20.87),
    patch("yellow green", 71.77, -24.13, 58.19),
    patch("orange yellow", 71.51, 18.24, 67.37),
    patch("blue", 28.37, 15.42, -49.80),
    patch("green", 54.38, -39.72, 32.27),
    patch("red", 42.43, 51.05, 28.62),
    patch("yellow", 81.80, 2.67, 80.41),
    patch("magenta", 50.63, 51.28, -14.12),
    patch("cyan", 49.57, -29.71, -28.32),
    patch("white 9.5", 95.19, -1.03, 2.93),
    patch("neutral 8", 81.29, -0.57, 0.44),
    patch("neutral 6.5", 66.89, -0.75, -0.06),
    patch("neutral 5", 50.76, -0.13, 0.14),
    patch("neutral 3.5", 35.63, -0.46, -0.48),
    patch("black 2", 20.64, 0.07, -0.46),
];

const fn patch(name: &'static str, l: f64, a: f64, b: f64) -> Patch {
    Patch {
        name,
        lab_d50: [l, a, b],
    }
}

/// XYZ of a white point from its chromaticity, Y = 1.
fn white_xyz(x: f64, y: f64) -> DVec3 {
    DVec3::new(x / y, 1.0, (1.0 - x - y) / y)
}

/// The ICC's D50 (x, y).
const D50_XY: (f64, f64) = (0.345_702_915, 0.358_538_597);
/// sRGB's D65 (x, y).
const D65_XY: (f64, f64) = (0.3127, 0.3290);

/// Bradford's cone response matrix (Lam 1985), rows.
const BRADFORD: [[f64; 3]; 3] = [
    [0.8951, 0.2664, -0.1614],
    [-0.7502, 1.7135, 0.0367],
    [0.0389, -0.0685, 1.0296],
];

/// XYZ (D65) to linear sRGB, IEC 61966-2-1, rows.
const XYZ_TO_SRGB: [[f64; 3]; 3] = [
    [3.2406, -1.5372, -0.4986],
    [-0.9689, 1.8758, 0.0415],
    [0.0557, -0.2040, 1.0570],
];

fn from_rows(rows: [[f64; 3]; 3]) -> DMat3 {
    DMat3::from_cols_array_2d(&rows).transpose()
}

/// CIE L*a*b* to XYZ relative to `white`.
pub fn lab_to_xyz(lab: [f64; 3], white: DVec3) -> DVec3 {
    let fy = (lab[0] + 16.0) / 116.0;
    let fx = fy + lab[1] / 500.0;
    let fz = fy - lab[2] / 200.0;
    let delta = 6.0 / 29.0;
    let inverse = |t: f64| {
        if t > delta {
            t * t * t
        } else {
            3.0 * delta * delta * (t - 4.0 / 29.0)
        }
    };
    white * DVec3::new(inverse(fx), inverse(fy), inverse(fz))
}

/// The Bradford adaptation from `from` to `to` white.
fn bradford(from: DVec3, to: DVec3) -> DMat3 {
    let cone = from_rows(BRADFORD);
    let scale = DMat3::from_diagonal((cone * to) / (cone * from));
    cone.inverse() * scale * cone
}

/// L*a*b* (D50) to linear sRGB (D65), unclipped.
pub fn lab_d50_to_linear_srgb(lab: [f64; 3]) -> DVec3 {
    let d50 = white_xyz(D50_XY.0, D50_XY.1);
    let d65 = white_xyz(D65_XY.0, D65_XY.1);
    from_rows(XYZ_TO_SRGB) * bradford(d50, d65) * lab_to_xyz(lab, d50)
}

impl Patch {
    /// The patch's linear sRGB value, unclipped.
    pub fn linear_srgb(&self) -> DVec3 {
        lab_d50_to_linear_srgb(self.lab_d50)
    }

    /// The patch's diffuse reflectance per channel: its linear sRGB value clipped to `[0, 1]`.
    pub fn reflectance(&self) -> DVec3 {
        self.linear_srgb().clamp(DVec3::ZERO, DVec3::ONE)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// colour-science's conversion of the same chart (tools/colorchecker_reference.py).
    fn colour_science() -> Vec<(String, DVec3)> {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/data/colorchecker_linear_srgb.csv"
        );
        let mut reader = csv::Reader::from_path(path).expect("reference file");
        reader
            .records()
            .map(|r| {
                let r = r.expect("row");
                let v = |i: usize| r[i].parse::<f64>().expect("number");
                (r[0].to_string(), DVec3::new(v(1), v(2), v(3)))
            })
            .collect()
    }

    #[test]
    fn conversion_matches_colour_science() {
        let reference = colour_science();
        assert_eq!(reference.len(), 24);
        for (patch, (name, expected)) in PATCHES.iter().zip(&reference) {
            assert!(name.starts_with(patch.name), "{name} vs {}", patch.name);
            let got = patch.linear_srgb();
            // The 4-digit IEC matrix against colour-science's full-precision one.
            assert!(
                (got - *expected).abs().max_element() < 1e-3,
                "{name}: {got} vs {expected}"
            );
        }
    }

    #[test]
    fn white_point_maps_to_white_and_greys_stay_grey() {
        let white = lab_d50_to_linear_srgb([100.0, 0.0, 0.0]);
        assert!((white - DVec3::ONE).abs().max_element() < 1e-3, "{white}");
        for patch in &PATCHES[18..] {
            let v = patch.linear_srgb();
            assert!(
                v.max_element() - v.min_element() < 0.06 * v.max_element(),
                "{}",
                patch.name
            );
        }
        let cyan = PATCHES[17];
        assert!(cyan.linear_srgb().x < 0.0 && cyan.reflectance().x == 0.0);
    }
}
