//! The renderer's speed at the CLI's defaults: a 512 x 512 sphere under the studio environment
//! at [`DEFAULT_SAMPLES_PER_PIXEL`] (where renders converge, see `tests/convergence.rs`) on
//! 2 cores, for a measured table (the `silver-925` preset tabulated
//! into the MERL grid, nearest-bin lookups) and for the analytic preset itself.
//!
//! Run: `cargo bench -p specula-visual --bench render`. On a shared machine, compare the
//! process's CPU time too: the work is split over both cores by rows of tiles.

use criterion::{criterion_group, criterion_main, Criterion};
use specula_core::brdf::Brdf;
use specula_core::materials::preset;
use specula_core::tabulate::tabulate;
use specula_visual::render::DEFAULT_SAMPLES_PER_PIXEL;
use specula_visual::{render, Environment, Lighting, RenderSettings, Scene, ShapeKind};
use std::sync::Arc;
use std::time::Duration;

fn bench(c: &mut Criterion) {
    let analytic = preset("silver-925").expect("the silver-925 preset exists");
    let table = tabulate(&analytic, 0.0);
    let scene = Scene::new(
        ShapeKind::Sphere,
        Lighting::Environment(Arc::new(Environment::studio())),
    );
    let settings = RenderSettings::square(512, DEFAULT_SAMPLES_PER_PIXEL);
    let mut group = c.benchmark_group(format!(
        "render 512x512 {DEFAULT_SAMPLES_PER_PIXEL}spp studio"
    ));
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(30));
    let materials: [(&str, &dyn Brdf); 2] = [("merl-table", &table), ("analytic", &analytic)];
    for (label, brdf) in materials {
        group.bench_function(label, |b| {
            b.iter(|| render(brdf, &scene, &settings, &|_| {}))
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    // No HTML plots: plotters is built with its ab_glyph fonts for this crate, and criterion's
    // own plots find no font registered there.
    config = Criterion::default().without_plots();
    targets = bench
}
criterion_main!(benches);
