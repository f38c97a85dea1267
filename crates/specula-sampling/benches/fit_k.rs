//! Fitting k (paper 5.2) to the probe of a built-in material: one evaluation of the fit error
//! and the whole search (coarse scan, fine scan, Brent), per family; and the practical
//! placement (dense log-spline model + dynamic programme) for the planner.

use criterion::{criterion_group, criterion_main, Criterion};
use specula_core::materials::preset;
use specula_core::sampling::{Family, SamplingFunction};
use specula_core::ProbeSpec;
use specula_sampling::fit::{fit_error, fit_k};
use specula_sampling::place_theta_h;
use specula_sampling::probe::Probe;

fn fit(c: &mut Criterion) {
    for name in ["silver-925", "green-paint"] {
        let material = preset(name).expect("a built-in preset");
        let probe = Probe::take(&material, &ProbeSpec::default()).expect("a probe");
        let column = probe.column();
        let function = SamplingFunction::new(Family::Exponential, 5.0).expect("valid k");
        c.bench_function(&format!("fit_error_{name}"), |b| {
            b.iter(|| fit_error(&column, &function, 30))
        });
        for family in [Family::Exponential, Family::Power] {
            c.bench_function(&format!("fit_k_{family}_{name}"), |b| {
                b.iter(|| fit_k(&column, family, 30).expect("a fit"))
            });
        }
        c.bench_function(&format!("place_theta_h_{name}"), |b| {
            b.iter(|| place_theta_h(&probe, 30))
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = fit
}
criterion_main!(benches);
