//! The published model fits loaded by name, against the check values shipped with them.

mod common;

use common::{measured, test_data};
use specula_core::{Brdf, HalfDiff, Rgb, Spherical};
use specula_formats::lafortune::Lafortune;
use specula_formats::load_brdf;
use specula_formats::nbrdf::{Nbrdf, NbrdfSet};
use std::f64::consts::FRAC_PI_2;

#[derive(serde::Deserialize)]
struct CheckValue {
    material: String,
    theta_h_rad: f64,
    theta_d_rad: f64,
    phi_d_rad: f64,
    fr_r: f64,
    fr_g: f64,
    fr_b: f64,
}

/// All 400 check values of `merl100_nbrdf_check_values.csv` (4 angles x 100 materials).
#[test]
fn nbrdf_matches_its_check_values() {
    let path = test_data("merl100_nbrdf_check_values.csv");
    let mut reader = csv::Reader::from_path(path).unwrap();
    let mut current: Option<Nbrdf> = None;
    let (mut count, mut worst) = (0, 0.0f64);
    for row in reader.deserialize::<CheckValue>() {
        let row = row.unwrap();
        let name = format!("nbrdf:{}", row.material);
        if current.as_ref().map(|n| n.name()) != Some(name.clone()) {
            current = Some(Nbrdf::load(NbrdfSet::Merl100, &row.material).unwrap());
        }
        let net = current.as_ref().unwrap();
        let ours = net.eval_angles(row.theta_h_rad, row.theta_d_rad, row.phi_d_rad);
        let expected = Rgb::new(row.fr_r, row.fr_g, row.fr_b);
        for c in 0..3 {
            let relative = (ours[c] - expected[c]).abs() / expected[c].abs().max(1e-6);
            worst = worst.max(relative);
            assert!(
                relative < 1e-6,
                "{name} {c}: ours {} expected {}",
                ours[c],
                expected[c]
            );
        }
        count += 1;
    }
    assert_eq!(count, 400);
    println!("nbrdf: 400 check values, max relative error {worst:.2e}");
}

/// The same network through the resolver and the `Brdf` interface, from directions.
#[test]
fn nbrdf_by_name_evaluates_from_directions() {
    let brdf = load_brdf("nbrdf:gold-metallic-paint").unwrap();
    let hd = HalfDiff::new(0.261799388, 0.7, 0.5, FRAC_PI_2);
    let (wi, wo) = hd.to_directions();
    let direct = Nbrdf::load(NbrdfSet::Merl100, "gold-metallic-paint")
        .unwrap()
        .eval_angles(hd.theta_h, hd.theta_d, hd.phi_d);
    assert!((brdf.eval(wi, wo).unwrap() - direct).length() < 1e-9 * direct.length());
    // Published cross-check (PROVENANCE.md): green f_r 0.0654 at theta_h 15, theta_d 28.6 deg.
    assert!((direct.y - 0.0654).abs() < 5e-5, "{direct}");
    assert_eq!(brdf.eval(wi, -wo), Some(Rgb::ZERO), "below the horizon");
    assert_eq!(brdf.name(), "nbrdf:gold-metallic-paint");
    for spec in [
        "nbrdf-rgl:cc_iris_purple_gem_rgb",
        "nbrdf-nielsen:paintedmetal",
    ] {
        let b = load_brdf(spec).unwrap();
        assert!(b.eval(wi, wo).unwrap().min_element() > 0.0, "{spec}");
    }
    let err = load_brdf("nbrdf:no-such-paint").err().unwrap().to_string();
    assert!(
        err.contains("no-such-paint") && err.contains("100"),
        "{err}"
    );
}

/// Directions with these half-difference angles in degrees (phi_h = 0).
fn directions(theta_h: f64, theta_d: f64, phi_d: f64) -> (glam::DVec3, glam::DVec3) {
    HalfDiff::from_degrees(theta_h, 0.0, theta_d, phi_d).to_directions()
}

/// The Lafortune values printed in the fit's PROVENANCE.md (green channel, phi_d = 90 deg,
/// theta_d = 0.2 rad = 11.46 deg or 0.5 rad = 28.65 deg), each to the digits printed there.
#[test]
fn lafortune_matches_its_published_values() {
    if measured(specula_formats::lafortune::TABLE).is_none() {
        return;
    }
    let cases = [
        ("chrome-steel", 0.0, 0.2, 81.2, 0.05),
        ("gold-metallic-paint", 0.0, 0.2, 0.187, 5e-4),
        ("gold-metallic-paint", 15.0, 0.5, 0.0643, 5e-5),
        ("silver-metallic-paint", 0.0, 0.2, 0.511, 5e-4),
        ("blue-acrylic", 0.0, 0.2, 10.61, 5e-3),
        ("specular-black-phenolic", 0.0, 0.2, 11.17, 5e-3),
        ("white-diffuse-bball", 15.0, 0.5, 0.077, 5e-4),
    ];
    for (material, theta_h_deg, theta_d_rad, published, half_digit) in cases {
        let brdf = load_brdf(&format!("lafortune:{material}")).unwrap();
        let (wi, wo) = directions(theta_h_deg, f64::to_degrees(theta_d_rad), 90.0);
        let green = brdf.eval(wi, wo).unwrap().y;
        assert!(
            (green - published).abs() <= half_digit,
            "{material}: {green} vs {published}"
        );
    }
}

/// Gorilla's `MerlLafortune.cpp` hard-codes gold-metallic-paint's red lobe in unnormalised
/// form: `(-1.00881 (i.x o.x + i.y o.y) + 0.908947 i.z o.z)^12.8` (PROVENANCE.md). Our
/// normalised lobe must equal it (to the 6 digits printed there).
#[test]
fn lafortune_normalisation_matches_the_unnormalised_form() {
    if measured(specula_formats::lafortune::TABLE).is_none() {
        return;
    }
    let fit = Lafortune::by_name("gold-metallic-paint").unwrap();
    let diffuse_red = fit.rho_d.x / std::f64::consts::PI;
    for (ti, pi, to, po) in [
        (10.0, 0.0, 12.0, 180.0),
        (30.0, 40.0, 25.0, 230.0),
        (5.0, 10.0, 0.0, 0.0),
    ] {
        let wi = Spherical::from_degrees(ti, pi).to_vector();
        let wo = Spherical::from_degrees(to, po).to_vector();
        let ours = fit.eval(wi, wo).unwrap().x - diffuse_red;
        let dot = -1.00881 * (wi.x * wo.x + wi.y * wo.y) + 0.908947 * wi.z * wo.z;
        let gorilla = dot.max(0.0).powf(12.8);
        assert!(
            (ours - gorilla).abs() < 1e-4 * gorilla,
            "{ours} vs {gorilla}"
        );
    }
    assert!(
        load_brdf("lafortune:copper").is_ok(),
        "a non-MERL material of the table"
    );
    let err = load_brdf("lafortune:unobtainium")
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("unobtainium") && err.contains("100"), "{err}");
}

/// A folder of measured files is every BRDF in it, in name order; the README, provenance and
/// checksum files beside them are passed over.
#[test]
fn a_folder_of_measured_files_is_each_of_its_brdfs() {
    let Some(first) = measured(&format!("rgl_bsdf/{}.bsdf", common::RGL_MATERIALS[0])) else {
        return;
    };
    let folder = first.parent().unwrap();
    let brdfs = specula_formats::load_brdfs(&folder.to_string_lossy()).unwrap();
    let names: Vec<String> = brdfs.iter().map(|b| b.name()).collect();
    assert_eq!(names, common::RGL_MATERIALS.map(String::from));
    let one = specula_formats::load_brdfs(&first.to_string_lossy()).unwrap();
    assert_eq!(one.len(), 1);
    let empty = std::env::temp_dir().join(format!("specula-empty-{}", std::process::id()));
    std::fs::create_dir_all(&empty).unwrap();
    let Err(error) = specula_formats::load_brdfs(&empty.to_string_lossy()) else {
        panic!("an empty folder gave BRDFs");
    };
    assert!(error.to_string().contains("holds no BRDF file"), "{error}");
    std::fs::remove_dir(&empty).unwrap();
}
