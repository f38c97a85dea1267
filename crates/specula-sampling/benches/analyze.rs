//! The database analysis of paper 5.1: one material (3 families x 90 columns, each a fit of k
//! and a slice error), and a folder of MERL files against the time it takes to read them.
//!
//! There are no real MERL files here, so the folder is 8 synthetic `.binary` files made by
//! tabulating SGD fits of MERL materials (Bagher 2012). Three figures per file:
//! `read_folder`: `std::fs::read` of every file (the floor: the bytes must come in);
//! `slice_folder`: reading only the characteristic slice, one pass per file, in parallel;
//! `analyze_folder`: the whole analysis, in parallel with bounded memory. The files were just
//! written, so they come from the page cache: the read floor is memory speed, not disk speed.

use criterion::{criterion_group, criterion_main, Criterion};
use rayon::prelude::*;
use specula_core::materials::preset;
use specula_core::tabulate::tabulate;
use specula_formats::fits::{load_fit, FitModel};
use specula_sampling::analysis::analyze_slice;
use specula_sampling::database::{map_slices, SliceSource};
use specula_sampling::error::SamplingError;
use specula_sampling::merl_slice::read_merl_slice;
use specula_sampling::slice::{CharacteristicSlice, THETA_H_NODES};

const MERL_MATERIALS: [&str; 8] = [
    "chrome",
    "chrome-steel",
    "gold-metallic-paint",
    "blue-acrylic",
    "specular-black-phenolic",
    "silver-metallic-paint",
    "alum-bronze",
    "white-diffuse-bball",
];

fn one_material(c: &mut Criterion) {
    let material = preset("silver-925").expect("a built-in preset");
    let slice = CharacteristicSlice::of(&material, THETA_H_NODES);
    c.bench_function("analyze_one_brdf_slice", |b| {
        b.iter(|| analyze_slice(&slice, 30))
    });
    c.bench_function("analyze_one_brdf_with_evaluation", |b| {
        b.iter(|| analyze_slice(&CharacteristicSlice::of(&material, THETA_H_NODES), 30))
    });
}

fn merl_folder(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("temporary folder");
    let files: Vec<_> = MERL_MATERIALS
        .par_iter()
        .map(|name| {
            let fit = load_fit(FitModel::Sgd, name).expect("the SGD table is readable");
            let path = dir.path().join(format!("{name}.binary"));
            tabulate(fit.as_ref(), 0.0)
                .write(&path)
                .expect("write the table");
            path
        })
        .collect();
    let sources: Vec<SliceSource> = files.iter().cloned().map(SliceSource::MerlFile).collect();
    let mut group = c.benchmark_group("merl_folder_8_files");
    group.sample_size(10);
    group.bench_function("read_folder", |b| {
        b.iter(|| {
            files
                .par_iter()
                .map(|f| std::fs::read(f).expect("readable").len())
                .sum::<usize>()
        })
    });
    group.bench_function("slice_folder", |b| {
        b.iter(|| {
            files
                .par_iter()
                .map(|f| read_merl_slice(f).expect("a slice"))
                .count()
        })
    });
    group.bench_function("analyze_folder", |b| {
        b.iter(|| {
            map_slices(
                &sources,
                THETA_H_NODES,
                |s| Ok::<_, SamplingError>(analyze_slice(s, 30)),
                |_| {},
            )
        })
    });
    group.finish();
}

criterion_group!(benches, one_material, merl_folder);
criterion_main!(benches);
