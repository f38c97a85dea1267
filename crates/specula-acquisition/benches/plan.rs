//! Planning the paper's 6300-sample grid (kinematics, limits and occlusion for every sample)
//! and ordering its ~4100 measurable samples (nearest neighbour, candidate-list 2-opt and
//! Or-opt, alternative re-picking).
//!
//!     cargo bench -p specula-acquisition --bench plan

use criterion::{criterion_group, criterion_main, Criterion};
use specula_acquisition::device::Device;
use specula_acquisition::ordering::order;
use specula_acquisition::plan::Plan;
use specula_core::sampling::{Family, SamplingFunction};
use std::hint::black_box;

fn paper_plan(device: &Device) -> Plan {
    let theta_h = SamplingFunction::new(Family::Exponential, 4.78)
        .expect("valid k")
        .positions_deg(30);
    let theta_d: Vec<f64> = (0..30).map(|i| 3.0 * i as f64).collect();
    let phi_d: Vec<f64> = (0..7).map(|i| 15.0 * i as f64).collect();
    Plan::from_grid(&theta_h, &theta_d, &phi_d, 45.0, device)
}

fn bench(c: &mut Criterion) {
    let device = Device::utia();
    let mut group = c.benchmark_group("plan");
    group.sample_size(10);
    group.bench_function("from_grid 6300 samples", |b| {
        b.iter(|| paper_plan(black_box(&device)))
    });
    let plan = paper_plan(&device);
    group.bench_function("order 4120 measurable samples", |b| {
        b.iter(|| order(black_box(&plan)))
    });
    group.finish();
}

criterion_group! {
    name = benches;
    // Plots off: the crate's plotters (ab_glyph fonts, for the example) has no font
    // registered for criterion's charts.
    config = Criterion::default().without_plots();
    targets = bench
}
criterion_main!(benches);
