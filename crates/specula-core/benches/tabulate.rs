//! Tabulating an analytic material into the full MERL grid (1,458,000 cells, paper section 3).
//! Compare with `tools/tabulate_numpy.py`, the same GGX conductor vectorised in numpy.
//! `evaluate_cells_*` is the evaluation alone, cell by cell (no table, no row factors), to
//! show what walking the grid by rows ([`specula_core::Brdf::eval_phi_d_row`]) saves.

use criterion::{criterion_group, criterion_main, Criterion};
use rayon::prelude::*;
use specula_core::materials::preset;
use specula_core::merl::{Bin, CELLS};
use specula_core::tabulate::tabulate;
use specula_core::Brdf;
use std::f64::consts::FRAC_PI_4;

fn tabulate_presets(c: &mut Criterion) {
    for name in ["silver-925", "green-paint"] {
        let material = preset(name).expect("a built-in preset");
        c.bench_function(&format!("tabulate_{name}"), |b| {
            b.iter(|| tabulate(&material, FRAC_PI_4))
        });
    }
    let silver = preset("silver-925").expect("a built-in preset");
    c.bench_function("evaluate_cells_silver-925", |b| {
        b.iter(|| {
            (0..CELLS)
                .into_par_iter()
                .map(|i| silver.eval_half_diff(Bin::from_index(i).centre(FRAC_PI_4)))
                .map(|v| v.map_or(0.0, |v| v.x))
                .sum::<f64>()
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = tabulate_presets
}
criterion_main!(benches);
