//! The `linear` method against an independent implementation: scipy's
//! RegularGridInterpolator on the paper's task, vectors written by
//! `python3 tools/reconstruct_scipy.py vectors`.

use specula_core::Sample;
use specula_core::{HalfDiff, Rgb};
use specula_reconstruct::{reconstruct, Method};
use std::path::PathBuf;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// The samples file `theta_h,phi_h,theta_d,phi_d,r,g,b` (degrees, 1/sr).
fn read_samples(name: &str) -> Vec<Sample> {
    let text = std::fs::read_to_string(data(name)).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("theta_h,phi_h,theta_d,phi_d,r,g,b"));
    lines
        .map(|line| {
            let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
            Sample::new(
                HalfDiff::from_degrees(v[0], v[1], v[2], v[3]),
                Rgb::new(v[4], v[5], v[6]),
            )
        })
        .collect()
}

#[test]
fn linear_reconstruction_matches_scipy() {
    let samples = read_samples("paper_task_samples.csv");
    assert_eq!(samples.len(), 4316);
    let r = reconstruct(&samples, Method::Linear, "paper-task").unwrap();
    assert_eq!(r.lattice_shape, [28, 26, 7]);
    assert_eq!(
        (r.measured_nodes, r.filled_nodes),
        (4316, 28 * 26 * 7 - 4316)
    );
    let text = std::fs::read_to_string(data("paper_task_linear_scipy.csv")).unwrap();
    let mut checked = 0;
    for line in text.lines().skip(1) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let cell = r.brdf.cell(v[0] as usize).unwrap();
        for c in 0..3 {
            let expected = v[1 + c];
            assert!(
                (cell[c] - expected).abs() <= 1e-9 * (1.0 + expected.abs()),
                "cell {} channel {c}: {} vs scipy {expected}",
                v[0],
                cell[c]
            );
        }
        checked += 1;
    }
    assert!(checked > 1400, "{checked}");
}
