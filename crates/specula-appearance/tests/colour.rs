//! Multi-angle colour: CIEDE2000 against Sharma et al. 2005's published test pairs, CIELAB of
//! known reflectances, the E2194 geometry and the flop index.

use glam::DVec3;
use specula_appearance::colour::{self, ASPECULAR_DEG};
use specula_appearance::{appearance, Options};
use specula_core::{Brdf, Rgb};
use std::f64::consts::PI;

#[test]
fn ciede2000_matches_sharma_2005_to_its_printed_precision() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/ciede2000_sharma2005.csv"
    );
    let mut reader = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_path(path)
        .expect("the committed test data");
    let mut pairs = 0;
    for record in reader.records() {
        let v: Vec<f64> = record
            .expect("a row")
            .iter()
            .map(|x| x.parse().expect("a number"))
            .collect();
        let (a, b) = ([v[0], v[1], v[2]], [v[3], v[4], v[5]]);
        // Printed to 4 decimals: agreement within half a unit of the last digit, both ways.
        for (x, y) in [(a, b), (b, a)] {
            let de = colour::ciede2000(x, y);
            assert!(
                (de - v[6]).abs() <= 5e-5,
                "pair {}: {de:.6} vs {}",
                pairs + 1,
                v[6]
            );
        }
        pairs += 1;
    }
    assert_eq!(pairs, 34);
}

#[test]
fn cielab_of_known_reflectances() {
    // The D65 white (R = G = B = 1) is L* 100, a* = b* = 0; an 18 % grey is
    // L* = 116 0.18^(1/3) - 16 (CIE 15), still neutral. (palette derives the sRGB matrix
    // from the primaries and takes D65 as XYZ (0.95047, 1, 1.08883): they agree to 2e-5.)
    let white = colour::lab_of_reflectance(Rgb::ONE);
    assert!(
        (white[0] - 100.0).abs() < 1e-4 && white[1].abs() < 1e-4 && white[2].abs() < 1e-4,
        "{white:?}"
    );
    let grey = colour::lab_of_reflectance(Rgb::splat(0.18));
    let expected = 116.0 * 0.18f64.cbrt() - 16.0;
    assert!(
        (grey[0] - expected).abs() < 1e-4 && grey[1].abs() < 1e-4,
        "{grey:?}"
    );
    // Brighter than the white diffuser, as effect coatings are near the specular: L* goes on
    // above 100 (116 2^(1/3) - 16 for twice the white), not clamped.
    let bright = colour::lab_of_reflectance(Rgb::splat(2.0));
    assert!(
        (bright[0] - (116.0 * 2f64.cbrt() - 16.0)).abs() < 1e-3,
        "{bright:?}"
    );
    // Pure sRGB red: CIELAB (53.24, 80.09, 67.20), the commonly tabulated value.
    let red = colour::lab_of_reflectance(Rgb::new(1.0, 0.0, 0.0));
    for (got, want) in red.iter().zip([53.24, 80.09, 67.20]) {
        assert!((got - want).abs() < 0.01, "{red:?}");
    }
}

#[test]
fn the_reading_directions_are_e2194s() {
    // Aspecular angle gamma: from the specular direction towards the light; the viewing
    // direction's angle to the specular direction is gamma.
    for gamma in ASPECULAR_DEG {
        let (wi, wo) = colour::reading_directions(gamma);
        let specular = DVec3::new(-wi.x, -wi.y, wi.z);
        assert!((wi.z.acos().to_degrees() - 45.0).abs() < 1e-9);
        assert!(
            (specular.angle_between(wo).to_degrees() - gamma).abs() < 1e-9,
            "{gamma}"
        );
        assert!(wo.z > 0.0);
    }
}

/// A grey Lambertian surface.
struct Lambertian(f64);

impl Brdf for Lambertian {
    fn eval(&self, _wi: DVec3, _wo: DVec3) -> Option<Rgb> {
        Some(Rgb::splat(self.0 / PI))
    }
    fn name(&self) -> String {
        "lambertian".into()
    }
}

#[test]
fn a_diffuse_surface_has_one_colour_at_every_angle_and_no_flop() {
    let figures = appearance(&Lambertian(0.5), &Options::default());
    let first = figures.colour[0].unwrap();
    for lab in &figures.colour {
        let lab = lab.unwrap();
        assert!(colour::ciede2000(lab, first) < 1e-9);
    }
    assert!(
        (first[0] - (116.0 * 0.5f64.cbrt() - 16.0)).abs() < 1e-4,
        "{first:?}"
    );
    assert_eq!(figures.flop_index, Some(0.0));
}

#[test]
fn the_flop_index_has_alman_s_form() {
    // FI = 2.69 (L15 - L110)^1.11 / L45^0.86; a typical silver metallic (L* 130 / 50 / 20)
    // flops strongly (about 16).
    let fi = colour::flop_index(130.0, 50.0, 20.0);
    let expected = 2.69 * 110f64.powf(1.11) / 50f64.powf(0.86);
    assert!((fi - expected).abs() < 1e-12);
    assert!(fi > 10.0 && fi < 20.0, "{fi}");
}
