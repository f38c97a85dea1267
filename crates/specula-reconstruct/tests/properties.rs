//! Identities every reconstruction must keep, on random grids with random holes.

use proptest::prelude::*;
use specula_core::merl::{Bin, CELLS};
use specula_core::Sample;
use specula_core::{HalfDiff, Rgb};
use specula_reconstruct::provenance::CellOrigin;
use specula_reconstruct::{reconstruct, Method};

/// A random grid (sorted distinct theta_h, theta_d, phi_d in degrees) with some nodes left out.
fn grid() -> impl Strategy<Value = Vec<(f64, f64, f64)>> {
    (
        prop::collection::btree_set(0u32..9000, 3..7),
        prop::collection::btree_set(0u32..89, 2..6),
        prop::collection::btree_set(0u32..=90, 2..5),
        prop::collection::vec(any::<bool>(), 256),
    )
        .prop_map(|(h, d, p, keep)| {
            let mut out = Vec::new();
            for &th in &h {
                for &td in &d {
                    for &pd in &p {
                        out.push((th as f64 / 100.0, td as f64, pd as f64));
                    }
                }
            }
            // Node 0 always stays, so that some sample remains.
            out.iter()
                .enumerate()
                .filter(|(i, _)| keep[i % 256] || *i == 0)
                .map(|(_, v)| *v)
                .collect()
        })
}

/// Samples of `f` at the grid's configurations with light and camera above the surface (where
/// a measurement exists).
fn samples(grid: &[(f64, f64, f64)], f: impl Fn(f64, f64, f64) -> Rgb) -> Vec<Sample> {
    grid.iter()
        .map(|&(h, d, p)| (HalfDiff::from_degrees(h, 45.0, d, p), f(h, d, p)))
        .filter(|(hd, _)| {
            let (wi, wo) = hd.to_directions();
            wi.z > 0.0 && wo.z > 0.0
        })
        .map(|(hd, v)| Sample::new(hd, v))
        .collect()
}

const METHODS: [Method; 3] = [Method::Linear, Method::Log, Method::Lobe];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(6))]

    #[test]
    fn a_constant_brdf_is_reconstructed_exactly_above_the_surface(grid in grid(), c in 0.001..50.0f64) {
        let value = Rgb::new(c, 0.5 * c, 2.0 * c);
        // A grid whose every node lies below the horizon has nothing to reconstruct from.
        prop_assume!(!samples(&grid, |_, _, _| value).is_empty());
        for method in METHODS {
            let r = reconstruct(&samples(&grid, |_, _, _| value), method, "c").unwrap();
            for index in (0..CELLS).step_by(331) {
                let (wi, wo) = Bin::from_index(index).centre(0.0).to_directions();
                if wi.z <= 0.0 || wo.z <= 0.0 {
                    continue; // below the surface the lobe method gives 0, the others c
                }
                let v = r.brdf.cell(index).unwrap();
                prop_assert!((v - value).abs().max_element() <= 1e-6 * c, "{method}: cell {index}: {v} vs {value}");
            }
        }
    }

    #[test]
    fn phi_d_mirror_and_reciprocity_hold(grid in grid()) {
        let f = |h: f64, d: f64, p: f64| Rgb::new(1.0 + h, 2.0 + d / 10.0, 3.0 + (2.0 * p.to_radians()).cos());
        let direct = samples(&grid, f);
        prop_assume!(!direct.is_empty(), "every node below the horizon");
        // The same samples given at phi_d + 180 (light and camera swapped).
        let swapped: Vec<Sample> = direct.iter().map(|s| Sample::new(s.hd.swapped(), s.value)).collect();
        for method in METHODS {
            let a = reconstruct(&direct, method, "a").unwrap();
            let b = reconstruct(&swapped, method, "b").unwrap();
            for index in (0..CELLS).step_by(499) {
                let bin = Bin::from_index(index);
                let mirror = Bin { phi_d_i: 179 - bin.phi_d_i, ..bin };
                let (va, vb) = (a.brdf.cell(index).unwrap(), b.brdf.cell(index).unwrap());
                let vm = a.brdf.cell(mirror.index()).unwrap();
                // Relative to the larger value, with a floor far below the data's scale (f >= 1
                // here): a cell that underflows to 0 on one side and 2.7e-20 on the other agrees.
                let scale = |x: Rgb, y: Rgb| x.max_element().max(y.max_element()).max(1e-3);
                prop_assert!((va - vm).abs().max_element() <= 1e-12 * scale(va, vm), "{method}: {va} vs mirror {vm}");
                prop_assert!((va - vb).abs().max_element() <= 1e-9 * scale(va, vb), "{method}: {va} vs {vb}");
            }
            prop_assert_eq!(&a.provenance, &b.provenance);
        }
    }
}

#[test]
fn every_sample_marks_its_cell_measured() {
    let grid: Vec<(f64, f64, f64)> = [0.0, 0.5, 4.0, 20.0]
        .iter()
        .flat_map(|&h| {
            [0.0, 30.5, 60.2]
                .iter()
                .flat_map(move |&d| [10.3, 47.0].iter().map(move |&p| (h, d, p)))
        })
        .collect();
    let r = reconstruct(&samples(&grid, |_, _, _| Rgb::ONE), Method::Linear, "m").unwrap();
    for &(h, d, p) in &grid {
        let bin = Bin::of(HalfDiff::from_degrees(h, 45.0, d, p));
        assert_eq!(
            r.provenance.cells[bin.index()],
            CellOrigin::Measured,
            "{h} {d} {p}"
        );
    }
    // theta_d beyond the last node (60.2) is extrapolated; the lattice is complete, so cells
    // inside it are interpolated.
    assert_eq!(
        r.provenance.cells[Bin {
            theta_h_i: 20,
            theta_d_i: 75,
            phi_d_i: 30
        }
        .index()],
        CellOrigin::Extrapolated
    );
    assert_eq!(
        r.provenance.cells[Bin {
            theta_h_i: 20,
            theta_d_i: 45,
            phi_d_i: 30
        }
        .index()],
        CellOrigin::Interpolated
    );
}
