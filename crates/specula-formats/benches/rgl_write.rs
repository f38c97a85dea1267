//! Writing an RGL `.bsdf` from a MERL table (issue 18: well under 10 s on 2 cores): the
//! tables at the default resolution (power iteration, 16 VNDF slices of 128 x 128, 16 x 96 x 96
//! MERL lookups) and their encoding. The table is `green-paint` tabulated into the MERL grid,
//! so every lookup is the nearest-bin MERL evaluation of a measured file.

use criterion::{criterion_group, criterion_main, Criterion};
use specula_core::materials::preset;
use specula_core::tabulate::tabulate;
use specula_formats::rgl::{RglResolution, RglTables};
use std::f64::consts::FRAC_PI_4;

fn write_from_merl(c: &mut Criterion) {
    let table = tabulate(&preset("green-paint").expect("a preset"), FRAC_PI_4);
    c.bench_function("rgl_write_merl_green-paint", |b| {
        b.iter(|| {
            RglTables::from_brdf(&table, RglResolution::DEFAULT, "bench")
                .expect("writable")
                .to_bytes()
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = write_from_merl
}
criterion_main!(benches);
