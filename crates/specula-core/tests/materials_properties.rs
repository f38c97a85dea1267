//! Physical properties every reference material must have: reciprocity, non-negativity,
//! zero below the horizon, isotropy of the bases (no dependence on phi_h) and the scratch
//! lobe's dependence on phi_h (paper section 4.3).

mod common;

use common::all_materials;
use glam::DVec3;
use specula_core::geometry::{rotate_z, HalfDiff, Spherical};
use specula_core::materials::{preset, Material};
use specula_core::{Brdf, Rgb};

/// Deterministic, well-spread direction pairs above the surface (golden-ratio sequences),
/// with a third of them near the specular peak where the values are large.
fn direction_pairs(n: usize) -> Vec<(DVec3, DVec3)> {
    let golden = 0.618_033_988_749_894_9;
    (0..n)
        .map(|i| {
            let x = |k: f64| (0.5 + k * golden * (i as f64 + 1.0)).fract();
            let wi = Spherical::new(x(1.0).acos(), x(2.0) * std::f64::consts::TAU).to_vector();
            let wo = if i % 3 == 0 {
                let near = HalfDiff::from_directions(wi, DVec3::new(-wi.x, -wi.y, wi.z));
                HalfDiff {
                    theta_h: x(3.0) * 0.05,
                    phi_h: x(4.0) * std::f64::consts::TAU,
                    ..near
                }
                .to_directions()
                .1
            } else {
                Spherical::new(x(3.0).acos(), x(4.0) * std::f64::consts::TAU).to_vector()
            };
            (wi, wo)
        })
        .filter(|(wi, wo)| wi.z > 1e-3 && wo.z > 1e-3)
        .collect()
}

fn close(a: Rgb, b: Rgb, relative: f64) -> bool {
    (a - b).abs().max_element() <= relative * a.abs().max(b.abs()).max_element().max(1e-300)
}

#[test]
fn every_material_is_reciprocal() {
    for material in all_materials() {
        for (wi, wo) in direction_pairs(300) {
            let forward = material.eval(wi, wo).unwrap();
            let backward = material.eval(wo, wi).unwrap();
            assert!(
                close(forward, backward, 1e-12),
                "{}: {wi} {wo}: {forward} vs {backward}",
                material.name
            );
        }
    }
}

#[test]
fn every_material_is_finite_and_non_negative() {
    for material in all_materials() {
        let mut largest = 0.0f64;
        for (wi, wo) in direction_pairs(600) {
            let f = material.eval(wi, wo).unwrap();
            assert!(
                f.is_finite() && f.min_element() >= 0.0,
                "{}: {wi} {wo}: {f}",
                material.name
            );
            largest = largest.max(f.max_element());
        }
        assert!(
            largest > 0.1,
            "{}: the pairs never reach the highlight",
            material.name
        );
    }
}

#[test]
fn below_the_horizon_is_zero() {
    let below = Spherical::from_degrees(95.0, 10.0).to_vector();
    let above = Spherical::from_degrees(30.0, 190.0).to_vector();
    let horizon = DVec3::X;
    for material in all_materials() {
        for (wi, wo) in [(below, above), (above, below), (horizon, above)] {
            assert_eq!(material.eval(wi, wo), Some(Rgb::ZERO), "{}", material.name);
        }
    }
}

#[test]
fn half_difference_evaluation_matches_directions() {
    for material in all_materials() {
        for (wi, wo) in direction_pairs(200) {
            let hd = HalfDiff::from_directions(wi, wo);
            let by_directions = material.eval(wi, wo).unwrap();
            let by_angles = material.eval_half_diff(hd).unwrap();
            assert!(
                close(by_directions, by_angles, 1e-8),
                "{}: {hd:?}",
                material.name
            );
        }
    }
}

/// Turning light and camera together about the normal (changing phi_h only) leaves an
/// isotropic material unchanged.
#[test]
fn isotropic_bases_do_not_depend_on_phi_h() {
    for material in all_materials().into_iter().filter(|m| m.scratch.is_none()) {
        for (wi, wo) in direction_pairs(100) {
            let reference = material.eval(wi, wo).unwrap();
            for turn_deg in [17.0f64, 90.0, 200.0] {
                let t = turn_deg.to_radians();
                let turned = material.eval(rotate_z(wi, t), rotate_z(wo, t)).unwrap();
                assert!(
                    close(reference, turned, 1e-9),
                    "{} turned {turn_deg}",
                    material.name
                );
            }
        }
    }
}

/// With scratches, the same (theta_h, theta_d, phi_d) looks different at different phi_h:
/// brightest when the half vector tilts across the scratches. Without them it does not.
#[test]
fn scratch_lobe_makes_the_brdf_depend_on_phi_h() {
    let scratched = preset("silver-925-scratched").unwrap();
    let plain = preset("silver-925").unwrap();
    let orientation_deg = scratched.scratch.as_ref().unwrap().orientation_deg;
    let at = |m: &Material, phi_h_deg: f64| {
        m.eval_half_diff(HalfDiff::from_degrees(6.0, phi_h_deg, 30.0, 90.0))
            .unwrap()
            .y
    };
    let across = at(&scratched, orientation_deg + 90.0);
    let along = at(&scratched, orientation_deg);
    assert!(across > 2.0 * along, "across {across}, along {along}");
    assert!(
        (at(&plain, orientation_deg + 90.0) - at(&plain, orientation_deg)).abs()
            < 1e-12 * at(&plain, 0.0)
    );
    // The scratched half-plane repeats every 180 degrees of phi_h.
    assert!((at(&scratched, orientation_deg + 270.0) - across).abs() < 1e-9 * across);
}
