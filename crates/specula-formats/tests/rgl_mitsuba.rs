//! The RGL `.bsdf` reader against Mitsuba 3.9.1's `measured` plugin (vectors made by
//! `tools/rgl_vectors.py`): f_r within 1e-3 relative wherever Mitsuba's value exceeds 1e-3,
//! and within 1e-6 absolute of Mitsuba's value clamped at zero (as `powitacq` clamps) below.
//! A vector's `(theta_i, phi_i)` is Mitsuba's `si.wi`, the camera's direction, and `(theta_o,
//! phi_o)` the light's: Specula's `eval` takes the light first.

mod common;

use common::{measured, test_data, MitsubaVector as Vector, RGL_MATERIALS};
use specula_core::{Brdf, Spherical};
use specula_formats::rgl::RglBsdf;

#[test]
fn rgl_reader_matches_mitsuba_measured_plugin() {
    for material in RGL_MATERIALS {
        let Some(path) = measured(&format!("rgl_bsdf/{material}.bsdf")) else {
            return;
        };
        let brdf = RglBsdf::read(&path).unwrap();
        let vectors = test_data(&format!("rgl_mitsuba_{material}.csv"));
        let mut reader = csv::Reader::from_path(&vectors).unwrap();
        let (mut rows, mut compared, mut worst, mut worst_small) = (0, 0, 0.0f64, 0.0f64);
        for v in reader.deserialize::<Vector>() {
            let v = v.unwrap();
            let camera = Spherical::from_degrees(v.theta_i, v.phi_i).to_vector();
            let light = Spherical::from_degrees(v.theta_o, v.phi_o).to_vector();
            let ours = brdf.eval(light, camera).unwrap();
            rows += 1;
            for (c, reference) in [v.r, v.g, v.b].into_iter().enumerate() {
                assert!(ours[c] >= 0.0, "{material}: negative f_r {ours}");
                if reference > 1e-3 {
                    let relative = (ours[c] - reference).abs() / reference;
                    worst = worst.max(relative);
                    compared += 1;
                    assert!(
                        relative < 1e-3,
                        "{material} at ({}, {}, {}, {}) channel {c}: ours {} Mitsuba {reference}",
                        v.theta_i,
                        v.phi_i,
                        v.theta_o,
                        v.phi_o,
                        ours[c]
                    );
                } else {
                    let absolute = (ours[c] - reference.max(0.0)).abs();
                    worst_small = worst_small.max(absolute);
                    assert!(
                        absolute < 1e-6,
                        "{material} channel {c}: ours {} Mitsuba {reference}",
                        ours[c]
                    );
                }
            }
        }
        assert!(rows >= 1000, "{material}: only {rows} vectors");
        assert!(
            compared >= 1500,
            "{material}: only {compared} values above 1e-3"
        );
        println!("{material}: {rows} directions, {compared} values compared, max relative error {worst:.2e}, below 1e-3 max absolute error {worst_small:.2e}");
    }
}
