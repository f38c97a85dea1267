//! The batched evaluation `Brdf::eval_pairs` gives what `Brdf::eval` gives pair by pair, for
//! every built-in material (presets, metals, paints, with and without a scratch lobe), at
//! spread directions and at the edge cases: below and on the horizon, grazing, the mirror
//! direction and normal incidence.

mod common;

use common::all_materials;
use glam::DVec3;
use specula_core::geometry::Spherical;
use specula_core::materials::conductor::RoughConductor;
use specula_core::materials::{Base, Distribution, Material};
use specula_core::{Brdf, Rgb};
use std::sync::Arc;

/// A unit direction at `theta_deg` from the normal (beyond 90: below the horizon).
fn direction(theta_deg: f64, phi_deg: f64) -> DVec3 {
    Spherical::from_degrees(theta_deg, phi_deg).to_vector()
}

/// The mirror image of `w` about the normal.
fn mirror(w: DVec3) -> DVec3 {
    DVec3::new(-w.x, -w.y, w.z)
}

/// Pairs spread over the whole sphere of directions (golden-ratio sequences, uniform in
/// cos theta), so about three in four have a direction below the horizon, and pairs near
/// the mirror direction where the values are large.
fn spread_pairs(n: usize) -> Vec<(DVec3, DVec3)> {
    let golden = 0.618_033_988_749_894_9;
    (0..n)
        .map(|i| {
            let x = |k: f64| (0.5 + k * golden * (i as f64 + 1.0)).fract();
            let on_sphere = |u: f64, v: f64| {
                Spherical::new((2.0 * u - 1.0).acos(), v * std::f64::consts::TAU).to_vector()
            };
            let wi = on_sphere(x(1.0), x(2.0));
            let wo = if i % 3 == 0 {
                let near = mirror(wi) + 0.01 * on_sphere(x(3.0), x(4.0));
                near.normalize()
            } else {
                on_sphere(x(3.0), x(4.0))
            };
            (wi, wo)
        })
        .collect()
}

/// The edge cases, each with both orders of its directions.
fn edge_pairs() -> Vec<(DVec3, DVec3)> {
    let grazing = 90.0 - 1e-7;
    let mut pairs = vec![
        (DVec3::Z, DVec3::Z),
        (direction(30.0, 10.0), mirror(direction(30.0, 10.0))),
        (direction(89.0, 200.0), mirror(direction(89.0, 200.0))),
        (direction(grazing, 0.0), mirror(direction(grazing, 0.0))),
        (direction(grazing, 0.0), direction(grazing, 0.0)),
        (direction(grazing, 45.0), DVec3::Z),
        (direction(90.0, 30.0), direction(40.0, 210.0)),
        (direction(90.0, 30.0), mirror(direction(90.0, 30.0))),
        (direction(90.5, 0.0), direction(20.0, 180.0)),
        (direction(150.0, 70.0), direction(150.0, 250.0)),
        (-DVec3::Z, DVec3::Z),
        (direction(60.0, 0.0), direction(60.0, 0.0)),
    ];
    let swapped: Vec<_> = pairs.iter().map(|&(wi, wo)| (wo, wi)).collect();
    pairs.extend(swapped);
    pairs
}

/// Checks `brdf.eval_pairs` against `brdf.eval` at every pair: 1e-12 relative, the same
/// holes.
fn assert_batch_is_per_pair(brdf: &dyn Brdf, pairs: &[(DVec3, DVec3)]) {
    let (wi, wo): (Vec<DVec3>, Vec<DVec3>) = pairs.iter().copied().unzip();
    let mut batch = vec![Some(Rgb::splat(-1.0)); pairs.len()];
    brdf.eval_pairs(&wi, &wo, &mut batch);
    for (k, (&(wi, wo), batch)) in pairs.iter().zip(&batch).enumerate() {
        let single = brdf.eval(wi, wo);
        match (single, batch) {
            (Some(single), Some(batch)) => {
                let scale = single.abs().max_element().max(f64::MIN_POSITIVE);
                assert!(
                    (single - *batch).abs().max_element() <= 1e-12 * scale,
                    "{} pair {k} ({wi}, {wo}): batch {batch} vs eval {single}",
                    brdf.name()
                );
            }
            (None, None) => {}
            _ => panic!(
                "{} pair {k} ({wi}, {wo}): batch {batch:?} vs eval {single:?}",
                brdf.name()
            ),
        }
    }
}

#[test]
fn every_material_gives_the_same_in_batch_as_pair_by_pair() {
    let mut pairs = spread_pairs(3000);
    pairs.extend(edge_pairs());
    for material in all_materials() {
        assert_batch_is_per_pair(&material, &pairs);
        // Through the pointers the Python package and the CLI hold.
        let shared: Arc<dyn Brdf> = Arc::new(material.clone());
        assert_batch_is_per_pair(&shared, &pairs);
    }
}

#[test]
fn the_batch_answers_zero_below_the_horizon_and_the_closed_form_at_the_mirror_peak() {
    let silver = specula_core::materials::preset("silver-925").expect("a preset");
    let pairs = edge_pairs();
    let (wi, wo): (Vec<DVec3>, Vec<DVec3>) = pairs.iter().copied().unzip();
    let mut out = vec![None; pairs.len()];
    silver.eval_pairs(&wi, &wo, &mut out);
    for (&(wi, wo), value) in pairs.iter().zip(&out) {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            assert_eq!(*value, Some(Rgb::ZERO), "({wi}, {wo})");
        }
    }
    // Normal incidence, mirror direction: G = 1, D = 1 / (pi alpha^2), F = F(1).
    let Base::Conductor(conductor) = &silver.base else {
        panic!("silver-925 is a conductor")
    };
    let f0 = conductor.fresnel(1.0);
    let peak = f0 / (4.0 * std::f64::consts::PI * conductor.alpha().powi(2));
    let at_peak = out[0].expect("a material answers everywhere");
    assert!((at_peak - peak).abs().max_element() <= 1e-12 * peak.max_element());
}

/// A rough conductor's batch (`RoughConductor::eval_columns`) does the operations of its
/// pair-by-pair evaluation in the same order, so its values are the same bit for bit, with
/// either distribution.
#[test]
fn a_conductor_gives_the_same_bits_in_batch_as_pair_by_pair() {
    let mut pairs = spread_pairs(3000);
    pairs.extend(edge_pairs());
    let (wi, wo): (Vec<DVec3>, Vec<DVec3>) = pairs.iter().copied().unzip();
    let beckmann = RoughConductor::new(
        Distribution::Beckmann,
        0.1,
        Rgb::new(0.2, 0.9, 1.1),
        Rgb::new(3.9, 2.4, 1.8),
    );
    let mut conductors: Vec<Material> = all_materials()
        .into_iter()
        .filter(|m| matches!(m.base, Base::Conductor(_)) && m.scratch.is_none())
        .collect();
    assert!(
        conductors.iter().any(|m| m.name == "silver-925"),
        "a GGX conductor"
    );
    conductors.push(Material::new("beckmann-metal", Base::Conductor(beckmann)));
    for material in conductors {
        let mut batch = vec![None; pairs.len()];
        material.eval_pairs(&wi, &wo, &mut batch);
        for (k, (&(wi, wo), batch)) in pairs.iter().zip(&batch).enumerate() {
            assert_eq!(*batch, material.eval(wi, wo), "{} pair {k}", material.name);
        }
    }
}
