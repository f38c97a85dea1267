//! Reading a 35 MB MERL `.binary` file (compare with `tools/merl_read_numpy.py`).

use criterion::{criterion_group, criterion_main, Criterion};
use specula_core::merl::{MerlBrdf, CELLS};
use specula_core::Rgb;

fn merl_read(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("temporary folder");
    let path = dir.path().join("bench.binary");
    let mut table = MerlBrdf::empty("bench");
    for i in 0..CELLS {
        table.set_cell(i, Some(Rgb::new(i as f64, 0.5, 1e-3 * i as f64)));
    }
    table.write(&path).expect("write the bench file");
    c.bench_function("merl_read_35MB", |b| {
        b.iter(|| MerlBrdf::read(&path).expect("read the bench file"))
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = merl_read
}
criterion_main!(benches);
