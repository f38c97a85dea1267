//! The RGL `.bsdf` writer against Mitsuba 3.9.1's `measured` plugin (vectors made by
//! `tools/rgl_export_check.py` from the files `specula convert` writes at the default
//! resolution), for a sharp conductor (chrome, GGX alpha 0.01), the green paint (a GGX alpha
//! 0.008 coat over a diffuse base) and a real RGL file written again by Specula.
//!
//! Two checks per material:
//! 1. The file the writer makes now is the one Mitsuba evaluated, and Specula's reader agrees
//!    with Mitsuba on it: within 1e-3 relative where Mitsuba's f_r exceeds 1e-3 (the reader's
//!    own tolerance against Mitsuba, `rgl_mitsuba.rs`).
//! 2. Mitsuba's value of the written file agrees with Specula's evaluation of the source where
//!    the BRDF matters: at the values whose `f_r cos(theta_o)` is at least [`SIGNIFICANT`] of
//!    the material's largest, the mean relative difference weighted by `f_r cos(theta_o)`
//!    (what a render integrates), the median and the 90th percentile; and the weighted mean
//!    over all 2100 pairs (the diffuse and tail values too). The bounds are about twice the
//!    figures measured (docs/book/src/renderers.md): the format's own
//!    interpolation error at the default resolution (bilinear over each elevation's warped
//!    sample grid, linear between the 16 elevations), largest for the paint, whose sharp coat
//!    gets few samples near grazing incidence because its diffuse base spreads the
//!    retro-reflection's distribution over the hemisphere.

mod common;

use common::{test_data, MitsubaVector as Vector};
use specula_core::brdf::luminance;
use specula_core::{Brdf, Spherical};
use specula_formats::rgl::{RglBsdf, RglResolution, RglTables};
use specula_formats::{input::measured_data_dir, load_brdf};

/// Values below this fraction of the material's largest `f_r cos(theta_o)` are not compared
/// with the source (they still are in check 1).
const SIGNIFICANT: f64 = 0.01;

/// Agreement of Mitsuba with the source over the significant values.
#[derive(Debug)]
struct Agreement {
    /// Weighted mean relative difference over every pair.
    weighted_mean_all: f64,
    compared: usize,
    weighted_mean: f64,
    median: f64,
    p90: f64,
}

/// Runs both checks on `material` (the name of its vectors) written from `source`.
fn check(material: &str, source: &str) -> Agreement {
    let brdf = load_brdf(source).unwrap();
    let tables = RglTables::from_brdf(brdf.as_ref(), RglResolution::DEFAULT, material).unwrap();
    let written = RglBsdf::from_bytes(material, &tables.to_bytes()).unwrap();
    let path = test_data(&format!("rgl_export_mitsuba_{material}.csv"));
    let mut reader = csv::Reader::from_path(&path).unwrap();
    let mut rows = Vec::new();
    for v in reader.deserialize::<Vector>() {
        let v = v.unwrap();
        // Mitsuba's `si.wi` (theta_i, phi_i) is the camera's direction, its `wo` the light's.
        let camera = Spherical::from_degrees(v.theta_i, v.phi_i).to_vector();
        let light = Spherical::from_degrees(v.theta_o, v.phi_o).to_vector();
        let mitsuba = glam::DVec3::new(v.r, v.g, v.b);
        let ours = written.eval(light, camera).unwrap();
        for c in 0..3 {
            if mitsuba[c] > 1e-3 {
                let relative = (ours[c] - mitsuba[c]).abs() / mitsuba[c];
                assert!(
                    relative < 1e-3,
                    "{material} at {:?}: reader {ours} Mitsuba {mitsuba}",
                    (v.theta_i, v.phi_i, v.theta_o, v.phi_o)
                );
            }
        }
        let truth = brdf.eval(light, camera).unwrap();
        rows.push((luminance(truth) * light.z, luminance(mitsuba) * light.z));
    }
    assert!(
        rows.len() >= 2000,
        "{material}: only {} vectors",
        rows.len()
    );
    let weighted_mean_all = rows.iter().map(|(t, m)| (m - t).abs()).sum::<f64>()
        / rows.iter().map(|(t, _)| t).sum::<f64>();
    let peak = rows.iter().map(|r| r.0).fold(0.0, f64::max);
    let significant: Vec<(f64, f64)> = rows
        .into_iter()
        .filter(|(truth, _)| *truth >= SIGNIFICANT * peak)
        .collect();
    let weighted_mean = significant.iter().map(|(t, m)| (m - t).abs()).sum::<f64>()
        / significant.iter().map(|(t, _)| t).sum::<f64>();
    let mut relative: Vec<f64> = significant.iter().map(|(t, m)| (m - t).abs() / t).collect();
    relative.sort_by(f64::total_cmp);
    let agreement = Agreement {
        weighted_mean_all,
        compared: relative.len(),
        weighted_mean,
        median: relative[relative.len() / 2],
        p90: relative[relative.len() * 9 / 10],
    };
    println!("{material}: {agreement:?}");
    agreement
}

#[test]
fn sharp_conductor_agrees_with_mitsuba() {
    let a = check("chrome", "chrome");
    assert!(a.compared >= 300, "{a:?}");
    assert!(
        a.weighted_mean < 0.005 && a.median < 0.002 && a.p90 < 0.01,
        "{a:?}"
    );
    assert!(a.weighted_mean_all < 0.01, "{a:?}");
}

#[test]
fn green_paint_agrees_with_mitsuba() {
    let a = check("green-paint", "green-paint");
    assert!(a.compared >= 200, "{a:?}");
    assert!(
        a.weighted_mean < 0.06 && a.median < 0.025 && a.p90 < 0.08,
        "{a:?}"
    );
    assert!(a.weighted_mean_all < 0.06, "{a:?}");
}

#[test]
fn real_rgl_file_round_trips_through_mitsuba() {
    let file = measured_data_dir().join("rgl_bsdf/cc_ibiza_sunset_rgb.bsdf");
    if !file.is_file() {
        println!(
            "skipped: {} not found (the measured data of ../shared)",
            file.display()
        );
        return;
    }
    let a = check("cc_ibiza_sunset_rgb", file.to_str().unwrap());
    assert!(a.compared >= 500, "{a:?}");
    assert!(
        a.weighted_mean < 0.03 && a.median < 0.005 && a.p90 < 0.04,
        "{a:?}"
    );
    assert!(a.weighted_mean_all < 0.03, "{a:?}");
}
