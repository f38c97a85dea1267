//! The UTIA BRDF binary: layout, byte-exact round trips, interpolation and provenance.

use specula_core::{Brdf, HalfDiff, Rgb, Spherical};
use specula_formats::nbrdf::{Nbrdf, NbrdfSet};
use specula_formats::utia::{Node, UtiaBrdf, FILE_BYTES, NODES, PHI_STEP_DEG, THETA_STEP_DEG};

/// A table whose node value encodes its indices: `ti + 10 pi + 100 tv + 1000 pv` (+ channel).
fn index_table() -> UtiaBrdf {
    let mut t = UtiaBrdf::empty("index");
    for i in 0..NODES {
        let n = Node::from_index(i);
        let v = (n.theta_i + 10 * n.phi_i + 100 * n.theta_v + 1000 * n.phi_v) as f64;
        t.set_node(i, Some(Rgb::new(v, v + 1.0, v + 2.0)));
    }
    t
}

fn encoded(ti: f64, pi: f64, tv: f64, pv: f64) -> f64 {
    ti + 10.0 * pi + 100.0 * tv + 1000.0 * pv
}

fn lookup_steps(t: &UtiaBrdf, ti: f64, pi: f64, tv: f64, pv: f64) -> Option<Rgb> {
    t.lookup_deg(
        ti * THETA_STEP_DEG,
        pi * PHI_STEP_DEG,
        tv * THETA_STEP_DEG,
        pv * PHI_STEP_DEG,
    )
}

#[test]
fn file_layout_is_planes_then_theta_i_phi_i_theta_v_phi_v() {
    let bytes = index_table().to_bytes();
    assert_eq!(bytes.len(), FILE_BYTES);
    let at = |k: usize| f64::from_le_bytes(bytes[8 * k..8 * k + 8].try_into().unwrap());
    // Second plane (green), node theta_i 3, phi_i 7, theta_v 2, phi_v 41.
    let k = NODES + ((3 * 48 + 7) * 6 + 2) * 48 + 41;
    assert_eq!(at(k), encoded(3.0, 7.0, 2.0, 41.0) + 1.0);
}

#[test]
fn bytes_and_files_round_trip_exactly() {
    let table = UtiaBrdf::tabulate(&Nbrdf::load(NbrdfSet::Merl100, "gold-metallic-paint").unwrap());
    assert_eq!(table.measured_count(), NODES);
    let bytes = table.to_bytes();
    assert_eq!(UtiaBrdf::from_bytes("x", &bytes).unwrap().to_bytes(), bytes);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("gold.bin");
    table.write(&path).unwrap();
    let back = UtiaBrdf::read(&path).unwrap();
    assert_eq!(back.to_bytes(), bytes);
    assert_eq!(back.name(), "gold");
}

#[test]
fn tabulated_nodes_hold_the_source_values() {
    let fit = Nbrdf::load(NbrdfSet::Merl100, "white-diffuse-bball").unwrap();
    let table = UtiaBrdf::tabulate(&fit);
    for index in [0, 777, 40_000, NODES - 1] {
        let (wi, wo) = Node::from_index(index).directions();
        assert_eq!(table.node(index), fit.eval(wi, wo));
        // Evaluation from directions at a node gives the node (up to angle round-off).
        let at_node = table.eval(wi, wo).unwrap();
        assert!(
            (at_node - fit.eval(wi, wo).unwrap()).length() < 1e-9,
            "node {index}"
        );
    }
}

#[test]
fn interpolation_is_quadrilinear_with_wrapping_azimuths() {
    let t = index_table();
    let v = lookup_steps(&t, 1.5, 2.25, 3.5, 10.75).unwrap();
    assert!((v.x - encoded(1.5, 2.25, 3.5, 10.75)).abs() < 1e-9, "{v}");
    assert!((v.z - v.x - 2.0).abs() < 1e-9);
    // Halfway between phi_v node 47 and node 0 (352.5 and 360 deg).
    let wrap = lookup_steps(&t, 2.0, 5.0, 1.0, 47.5).unwrap();
    let expected = 0.5 * encoded(2.0, 5.0, 1.0, 47.0) + 0.5 * encoded(2.0, 5.0, 1.0, 0.0);
    assert!((wrap.x - expected).abs() < 1e-9, "{wrap}");
    // From directions: theta_i 22.5, phi_i 18.75, theta_v 60, phi_v 91.875 degrees.
    let wi = Spherical::from_degrees(22.5, 18.75).to_vector();
    let wo = Spherical::from_degrees(60.0, 91.875).to_vector();
    let v = t.eval(wi, wo).unwrap();
    assert!((v.x - encoded(1.5, 2.5, 4.0, 12.25)).abs() < 1e-6, "{v}");
}

#[test]
fn unmeasured_nodes_and_elevations_beyond_75_are_not_measured() {
    let mut t = index_table();
    let hole = Node {
        theta_i: 2,
        phi_i: 4,
        theta_v: 3,
        phi_v: 6,
    };
    t.set_node(hole.index(), None);
    assert_eq!(t.measured_count(), NODES - 1);
    assert_eq!(t.node(hole.index()), None);
    assert_eq!(lookup_steps(&t, 2.0, 4.0, 3.0, 6.0), None);
    // Halfway to a measured neighbour: the neighbour alone (weights renormalised).
    let v = lookup_steps(&t, 2.0, 4.0, 3.0, 6.5).unwrap();
    assert!((v.x - encoded(2.0, 4.0, 3.0, 7.0)).abs() < 1e-9, "{v}");
    // Written as -1 and read back as a hole.
    let back = UtiaBrdf::from_bytes("t", &t.to_bytes()).unwrap();
    assert_eq!(back.node(hole.index()), None);
    let wi = Spherical::from_degrees(80.0, 0.0).to_vector();
    let wo = Spherical::from_degrees(30.0, 180.0).to_vector();
    assert_eq!(t.eval(wi, wo), None, "theta_i 80 > 75 deg: not measured");
    assert_eq!(t.eval(wi, -wo), Some(Rgb::ZERO), "below the horizon");
    assert!(t
        .eval_half_diff(HalfDiff::from_degrees(10.0, 45.0, 20.0, 90.0))
        .is_some());
}

#[test]
fn bad_files_are_described() {
    let good = index_table().to_bytes();
    let err = UtiaBrdf::from_bytes("x", &good[..FILE_BYTES - 8]).unwrap_err();
    assert!(
        err.starts_with("truncated") && err.contains("1990656"),
        "{err}"
    );
    let mut long = good.clone();
    long.extend_from_slice(&[0; 8]);
    assert!(UtiaBrdf::from_bytes("x", &long)
        .unwrap_err()
        .starts_with("over-long"));
    let mut nan = good.clone();
    let k = 2 * NODES
        + Node {
            theta_i: 1,
            phi_i: 0,
            theta_v: 5,
            phi_v: 47,
        }
        .index();
    nan[8 * k..8 * k + 8].copy_from_slice(&f64::NAN.to_le_bytes());
    let err = UtiaBrdf::from_bytes("x", &nan).unwrap_err();
    assert!(
        err.contains("non-finite")
            && err.contains("blue")
            && err.contains("theta_i 15 phi_i 0 theta_v 75 phi_v 352.5"),
        "{err}"
    );
}

#[test]
fn absurd_values_are_refused_at_load() {
    let mut huge = index_table().to_bytes();
    huge[8 * 5..8 * 6].copy_from_slice(&1e308f64.to_le_bytes());
    let err = UtiaBrdf::from_bytes("x", &huge).unwrap_err();
    assert_eq!(
        err.0,
        "value 1e308 above 1e10 1/sr, the most a UTIA table may hold, in the red channel at theta_i 0 phi_i 0 theta_v 0 phi_v 37.5 deg"
    );
    let negative: Vec<u8> = (0..3 * NODES)
        .flat_map(|_| (-3.0f64).to_le_bytes())
        .collect();
    let err = UtiaBrdf::from_bytes("x", &negative).unwrap_err();
    assert!(err.starts_with("no measured node"), "{err}");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("long.bin");
    std::fs::File::create(&path)
        .unwrap()
        .set_len(100 << 20)
        .unwrap();
    let err = UtiaBrdf::read(&path).unwrap_err().to_string();
    assert!(err.contains("over-long: 104857600 bytes"), "{err}");
}
