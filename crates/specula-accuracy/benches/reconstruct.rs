//! Reconstruction speed on the paper's task (5.3): the 30 x 30 x 7 plan with the exponential
//! theta_h function (k 4.78), the samples within 75 degrees of the normal (4316; the UTIA
//! device's occlusion takes the paper's count to 4073), into the 1,458,000 MERL cells.
//! `tools/reconstruct_scipy.py time` times scipy's RegularGridInterpolator on the same task.
//!
//!     cargo bench -p specula-accuracy --bench reconstruct

use criterion::{criterion_group, criterion_main, Criterion};
use specula_accuracy::{measure, within_elevation, GridPlan};
use specula_core::materials::preset;
use specula_core::sampling::{Family, SamplingFunction};
use specula_core::HalfDiff;
use specula_reconstruct::{reconstruct, Method};
use std::hint::black_box;

fn paper_task() -> Vec<specula_core::Sample> {
    let theta_h = SamplingFunction::new(Family::Exponential, 4.78)
        .unwrap()
        .positions_deg(30);
    let reached: Vec<HalfDiff> = GridPlan::paper(theta_h)
        .configurations()
        .into_iter()
        .filter(|&hd| within_elevation(hd, 75.0))
        .collect();
    measure(&preset("silver-925").unwrap(), &reached)
}

fn bench(c: &mut Criterion) {
    let samples = paper_task();
    let mut group = c.benchmark_group("reconstruct_4316_samples_to_1458000_cells");
    group.sample_size(20);
    for method in [Method::Linear, Method::Log, Method::Lobe] {
        group.bench_function(method.name(), |b| {
            b.iter(|| reconstruct(black_box(&samples), method, "bench").unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
