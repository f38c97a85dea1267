//! Time to compute every appearance figure (gloss at 20, 60, 85 deg, E430 haze and DOI,
//! ISO 13803 haze, five-angle colour) of one BRDF: an analytic preset, the same preset
//! tabulated into a MERL table, and a real RGL measurement when `../shared` is present.

use criterion::{criterion_group, criterion_main, Criterion};
use specula_appearance::{appearance, Options};
use specula_core::materials::preset;
use specula_core::tabulate::tabulate;
use std::f64::consts::FRAC_PI_4;

fn figures(c: &mut Criterion) {
    let options = Options::default();
    for name in ["silver-925", "green-paint"] {
        let material = preset(name).expect("a built-in preset");
        c.bench_function(&format!("appearance_{name}"), |b| {
            b.iter(|| appearance(&material, &options))
        });
    }
    let table = tabulate(
        &preset("green-paint").expect("a built-in preset"),
        FRAC_PI_4,
    );
    c.bench_function("appearance_green-paint_merl_table", |b| {
        b.iter(|| appearance(&table, &options))
    });
    let rgl = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/data/measured/rgl_bsdf/colodur_napoli_4f_rgb.bsdf"
    );
    match specula_formats::load_brdf(rgl) {
        Ok(brdf) => {
            c.bench_function("appearance_rgl_colodur_napoli_4f", |b| {
                b.iter(|| appearance(brdf.as_ref(), &options))
            });
        }
        Err(err) => eprintln!("skipping the RGL file: {err:#}"),
    }
}

criterion_group!(benches, figures);
criterion_main!(benches);
