//! Tabulating an analytic material into the full MERL grid (1,458,000 cells), issue 2 item 5.
//! Compare with `tools/tabulate_numpy.py`, the same GGX conductor vectorised in numpy.

use criterion::{criterion_group, criterion_main, Criterion};
use specula_core::materials::presets::preset;
use specula_core::tabulate::tabulate;

fn tabulate_presets(c: &mut Criterion) {
    for name in ["silver-925", "green-paint"] {
        let material = preset(name).expect("a built-in preset");
        c.bench_function(&format!("tabulate_{name}"), |b| {
            b.iter(|| tabulate(&material, std::f64::consts::FRAC_PI_4))
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = tabulate_presets
}
criterion_main!(benches);
