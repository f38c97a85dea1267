//! `convert` between MERL, UTIA, RGL and samples CSV: resampling at the target's
//! nodes, provenance of unmeasured cells, exact same-format copies, detection by content.

mod common;

use common::measured;
use specula_core::merl::{Bin, CELLS};
use specula_core::tabulate::tabulate;
use specula_core::{Brdf, MerlBrdf};
use specula_formats::convert::{convert, ConvertOptions, CsvGrid, FileFormat};
use specula_formats::load_brdf;
use specula_formats::nbrdf::{Nbrdf, NbrdfSet};
use specula_formats::rgl::{RglBsdf, RglResolution};
use specula_formats::samples_csv::SampleSet;
use specula_formats::utia::{Node, UtiaBrdf, NODES};
use std::path::Path;

const OPTIONS: ConvertOptions = ConvertOptions {
    phi_h_rad: std::f64::consts::FRAC_PI_4,
    csv_grid: CsvGrid::Merl,
    rgl: RglResolution::DEFAULT,
};

fn run(input: &Path, output: &Path) -> specula_formats::convert::Conversion {
    convert(input.to_str().unwrap(), output, &OPTIONS).unwrap()
}

/// A MERL table of a smooth fit with a hole: every cell with theta_d >= 15 deg unmeasured.
fn merl_with_hole() -> MerlBrdf {
    let mut table = tabulate(
        &Nbrdf::load(NbrdfSet::Merl100, "white-diffuse-bball").unwrap(),
        0.0,
    );
    for index in 0..CELLS {
        if Bin::from_index(index).theta_d_i >= 15 {
            table.set_cell(index, None);
        }
    }
    table
}

#[test]
fn merl_utia_and_samples_keep_provenance() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name);
    let original = merl_with_hole();
    original.write(&p("a.binary")).unwrap();

    // MERL -> UTIA: each node holds the MERL lookup at its directions, holes stay holes.
    let c = run(&p("a.binary"), &p("b.bin"));
    let utia = UtiaBrdf::read(&p("b.bin")).unwrap();
    let mut holes = 0;
    for index in 0..NODES {
        let (wi, wo) = Node::from_index(index).directions();
        let expected = original.eval(wi, wo);
        holes += usize::from(expected.is_none());
        assert_eq!(utia.node(index), expected, "node {index}");
    }
    assert!(holes > 1000 && holes < NODES - 1000, "{holes}");
    assert_eq!(
        (c.target, c.measured, c.not_measured),
        (FileFormat::Utia, NODES - holes, holes)
    );

    // UTIA -> MERL: elevations beyond the last UTIA one (75 deg) are not measured.
    let c = run(&p("b.bin"), &p("c.binary"));
    let back = MerlBrdf::read(&p("c.binary")).unwrap();
    assert_eq!(c.measured, back.measured_count());
    let grazing = Bin {
        theta_h_i: 85,
        theta_d_i: 5,
        phi_d_i: 90,
    }
    .index();
    assert_eq!(back.cell(grazing), None);
    let centre = Bin {
        theta_h_i: 30,
        theta_d_i: 20,
        phi_d_i: 45,
    };
    let expected = utia
        .eval_half_diff(centre.centre(OPTIONS.phi_h_rad))
        .unwrap();
    let got = back.cell(centre.index()).unwrap();
    assert!(
        (got - expected).length() <= 1e-14 * expected.length(),
        "{got} vs {expected}"
    );

    // MERL -> CSV -> MERL: the measured cells and their values come back.
    let c = run(&p("a.binary"), &p("d.csv"));
    assert_eq!(c.measured, original.measured_count());
    run(&p("d.csv"), &p("e.binary"));
    let again = MerlBrdf::read(&p("e.binary")).unwrap();
    let unmatched = (0..CELLS)
        .filter(|&i| again.is_measured(i) != original.is_measured(i))
        .count();
    assert_eq!(unmatched, 0, "cells measured in one table only");
    for index in (0..CELLS).step_by(997) {
        if let (Some(a), Some(b)) = (original.cell(index), again.cell(index)) {
            assert!(
                (a - b).length() <= 1e-14 * a.length(),
                "cell {index}: {a} vs {b}"
            );
        }
    }

    // Same format: exact copies.
    run(&p("a.binary"), &p("a2.binary"));
    assert_eq!(
        std::fs::read(p("a.binary")).unwrap(),
        std::fs::read(p("a2.binary")).unwrap()
    );
    run(&p("b.bin"), &p("b2.bin"));
    assert_eq!(
        std::fs::read(p("b.bin")).unwrap(),
        std::fs::read(p("b2.bin")).unwrap()
    );
    run(&p("d.csv"), &p("d2.csv"));
    assert_eq!(
        std::fs::read(p("d.csv")).unwrap(),
        std::fs::read(p("d2.csv")).unwrap()
    );

    // UTIA -> CSV: one row per measured node, with the stored values.
    let c = run(&p("b.bin"), &p("f.csv"));
    assert_eq!(c.measured, NODES - holes);
    let rows = SampleSet::read(&p("f.csv")).unwrap();
    assert_eq!(rows.samples()[0].value, utia.node(0).unwrap());
}

#[test]
fn rgl_converts_to_every_writable_format() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name);
    let Some(source) = measured("rgl_bsdf/cc_iris_purple_gem_rgb.bsdf") else {
        return;
    };
    let rgl = RglBsdf::read(&source).unwrap();

    let c = run(&source, &p("rgl.binary"));
    assert_eq!((c.measured, c.not_measured), (CELLS, 0));
    let table = MerlBrdf::read(&p("rgl.binary")).unwrap();
    for index in [0, 12_345, 700_000, CELLS - 1] {
        let expected = rgl
            .eval_half_diff(Bin::from_index(index).centre(OPTIONS.phi_h_rad))
            .unwrap();
        let got = table.cell(index).unwrap();
        assert!(
            (got - expected).length() <= 1e-12 * expected.length().max(1e-300),
            "{index}"
        );
    }

    let c = run(&source, &p("rgl.bin"));
    assert_eq!(c.measured, NODES);
    let utia = UtiaBrdf::read(&p("rgl.bin")).unwrap();
    let (wi, wo) = Node::from_index(54_321).directions();
    assert_eq!(utia.node(54_321), rgl.eval(wi, wo));

    let on_utia_nodes = ConvertOptions {
        csv_grid: CsvGrid::Utia,
        ..OPTIONS
    };
    let c = convert(source.to_str().unwrap(), &p("rgl.csv"), &on_utia_nodes).unwrap();
    assert_eq!(c.measured, NODES);

    let c = convert(source.to_str().unwrap(), &p("copy.bsdf"), &OPTIONS).unwrap();
    assert_eq!((c.target, c.not_measured), (FileFormat::Rgl, 0));
    let RglResolution {
        elevations,
        sample_size,
        ..
    } = RglResolution::DEFAULT;
    assert!(c.measured > 0 && c.measured <= elevations * sample_size * sample_size);
    let back = RglBsdf::read(&p("copy.bsdf")).unwrap();
    assert!(back.description().contains("cc_iris_purple_gem_rgb"));
    let err = convert(source.to_str().unwrap(), &p("x.exr"), &OPTIONS)
        .unwrap_err()
        .to_string();
    assert!(err.contains("unknown output format"), "{err}");
}

#[test]
fn fits_convert_and_files_are_recognised_by_content() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name);
    let c = convert("nbrdf:gold-metallic-paint", &p("gold.bin"), &OPTIONS).unwrap();
    assert_eq!(c.measured, NODES);

    // No telling extension: magic bytes (RGL, MERL), the exact size (UTIA), the header (CSV).
    let Some(paper) = measured("rgl_bsdf/paper_white_rgb.bsdf") else {
        return;
    };
    std::fs::copy(paper, p("paper.dat")).unwrap();
    std::fs::copy(p("gold.bin"), p("gold.data")).unwrap();
    merl_with_hole().write(&p("merl.dat")).unwrap();
    std::fs::write(
        p("samples.txt"),
        "theta_h,phi_h,theta_d,phi_d,r,g,b\n1,0,2,3,4,5,6\n",
    )
    .unwrap();
    let expected = [
        ("paper.dat", FileFormat::Rgl),
        ("gold.data", FileFormat::Utia),
        ("merl.dat", FileFormat::Merl),
        ("samples.txt", FileFormat::SamplesCsv),
    ];
    for (name, format) in expected {
        assert_eq!(
            FileFormat::detect(&p(name)).unwrap(),
            Some(format),
            "{name}"
        );
        let brdf = load_brdf(p(name).to_str().unwrap()).unwrap();
        assert!(!brdf.name().is_empty());
    }
}

/// MERL -> RGL: the RGL nodes at unmeasured direction pairs are counted and filled from the
/// nearest measured node, so the file renders everywhere; measured pairs keep their values.
#[test]
fn rgl_output_fills_and_counts_unmeasured_nodes() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name);
    let original = merl_with_hole();
    original.write(&p("a.binary")).unwrap();
    let small = ConvertOptions {
        rgl: RglResolution {
            elevations: 8,
            ndf_size: 64,
            sample_size: 16,
        },
        ..OPTIONS
    };
    let c = convert(p("a.binary").to_str().unwrap(), &p("a.bsdf"), &small).unwrap();
    assert_eq!(c.target, FileFormat::Rgl);
    assert!(c.not_measured > 100 && c.measured > 100, "{c:?}");
    assert!(c.measured + c.not_measured <= 8 * 16 * 16);
    let rgl = RglBsdf::read(&p("a.bsdf")).unwrap();
    // theta_d = 30 deg is not measured in the source; the file holds a filled, positive value.
    let (wi, wo) = specula_core::HalfDiff::from_degrees(5.0, 0.0, 30.0, 90.0).to_directions();
    assert!(original.eval(wi, wo).is_none());
    assert!(rgl.eval(wi, wo).unwrap().min_element() > 0.0);

    let bad = ConvertOptions {
        rgl: RglResolution {
            sample_size: 3,
            ..RglResolution::DEFAULT
        },
        ..OPTIONS
    };
    let err = convert(p("a.binary").to_str().unwrap(), &p("b.bsdf"), &bad)
        .unwrap_err()
        .to_string();
    assert!(err.contains("sample size = 3 is out of range"), "{err}");
}
