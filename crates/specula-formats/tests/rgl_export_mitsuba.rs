//! The RGL `.bsdf` writer against Mitsuba 3.9.1's `measured` plugin (vectors made by
//! `tools/rgl_export_check.py` from the files `specula convert` writes at the default
//! resolution), for a sharp conductor (chrome, GGX alpha 0.01), the green paint (a GGX alpha
//! 0.008 coat over a diffuse base), the five real RGL files written again, their MERL
//! tabulations (`specula tabulate`, then `convert`) and three neural fits of MERL materials.
//!
//! The direction pairs are the vectors' 2100 (seeded, fixed): 1400 uniform over the
//! hemisphere pair (cos theta uniform up to 85 deg, azimuths uniform) and 700 near the mirror
//! direction (the half vector within a few degrees of the normal). Two checks per material:
//! 1. The file the writer makes now is the one Mitsuba evaluated, and Specula's reader agrees
//!    with Mitsuba on it: within 1e-3 relative where Mitsuba's f_r exceeds 1e-3 (the reader's
//!    own tolerance against Mitsuba, `rgl_mitsuba.rs`).
//! 2. Mitsuba's value of the written file against the source ([`Brdf::eval_smooth`]: a MERL
//!    table's interpolant, which the writer samples): the fraction of pairs whose luminance
//!    of f_r is within [`WITHIN`] of the source's, over all pairs and over the significant
//!    ones (the source's `f_r cos(theta_o)` at least [`SIGNIFICANT`] of its largest over the
//!    pairs: what a render integrates); and, over the pairs whose value is at least 1 % of the
//!    largest, the mean relative difference weighted by `f_r cos(theta_o)`, the median and
//!    the 90th percentile; each material's fractions must reach its claim ([`CLAIMS`]).
//!    Figures in docs/book/src/renderers.md.

mod common;

use common::{measured, test_data, MitsubaVector as Vector, RGL_MATERIALS};
use specula_core::brdf::luminance;
use specula_core::tabulate::tabulate;
use specula_core::{Brdf, GridSpec, Spherical};
use specula_formats::load_brdf;
use specula_formats::rgl::{RglBsdf, RglResolution, RglTables};
use std::sync::Arc;

/// A pair agrees with the source when the luminances differ by at most this, relative.
const WITHIN: f64 = 0.05;
/// Pairs whose `f_r cos(theta_o)` is below this fraction of the material's largest are left
/// out of the significant fraction.
const SIGNIFICANT: f64 = 1e-3;
/// Pairs below this fraction of the largest are left out of the weighted mean, median and
/// 90th percentile.
const MATTERS: f64 = 0.01;

/// The target of the issue: this fraction of all pairs within [`WITHIN`].
const TARGET: f64 = 0.95;

/// What the guide claims for each material's written file (docs/book/src/renderers.md): the
/// least fraction of all pairs and of the significant pairs within [`WITHIN`]: [`TARGET`]
/// wherever the file reaches it, below it the figure measured (to 0.1 %, rounded down). The
/// two MERL tabulations of the colour-changing films fall short over all pairs: in their
/// tails, at 1e-5 of the highlight and below, the tables' interpolants step eightfold within
/// a degree (bins reading channels clamped at zero) where the original files are smooth, and
/// no resampling at this resolution follows that within 5 % (docs/book/src/renderers.md).
const CLAIMS: [(&str, f64, f64); 15] = [
    ("chrome", TARGET, TARGET),
    ("green-paint", TARGET, TARGET),
    ("cc_ibiza_sunset_rgb", TARGET, TARGET),
    ("cc_iris_purple_gem_rgb", TARGET, TARGET),
    ("colodur_napoli_4f_rgb", TARGET, TARGET),
    ("paper_white_rgb", TARGET, TARGET),
    ("satin_rosaline_rgb", TARGET, TARGET),
    ("merl_cc_ibiza_sunset_rgb", 0.939, TARGET),
    ("merl_cc_iris_purple_gem_rgb", 0.919, TARGET),
    ("merl_colodur_napoli_4f_rgb", TARGET, TARGET),
    ("merl_paper_white_rgb", TARGET, TARGET),
    ("merl_satin_rosaline_rgb", TARGET, TARGET),
    ("nbrdf_gold-metallic-paint", TARGET, TARGET),
    ("nbrdf_specular-blue-phenolic", TARGET, 0.941),
    ("nbrdf_red-fabric", TARGET, TARGET),
];

/// Asserts that `a`, the agreement of `material`, reaches its claim in [`CLAIMS`].
fn assert_claim(material: &str, a: &Agreement) {
    let (_, all, significant) = CLAIMS
        .iter()
        .find(|c| c.0 == material)
        .unwrap_or_else(|| panic!("{material}: no claim"));
    assert!(
        a.within_all >= *all && a.within_significant >= *significant,
        "{material}: claimed {all} of all pairs and {significant} of the significant ones: {a:?}"
    );
}

/// Agreement of Mitsuba's value of the written file with the source.
#[derive(Debug)]
struct Agreement {
    /// Fraction of all pairs within [`WITHIN`].
    within_all: f64,
    /// Fraction of the significant pairs within [`WITHIN`], and how many are significant.
    within_significant: f64,
    significant: usize,
    /// Weighted mean relative difference over every pair.
    weighted_mean_all: f64,
    /// Over the pairs that matter: their count, weighted mean, median and 90th percentile.
    compared: usize,
    weighted_mean: f64,
    median: f64,
    p90: f64,
}

/// Source and written value at one pair: luminance of f_r times cos(theta_o).
struct Pair {
    truth: f64,
    mitsuba: f64,
}

impl Pair {
    fn relative(&self) -> f64 {
        (self.mitsuba - self.truth).abs() / self.truth
    }
}

/// Runs both checks on `material` (the name of its vectors) written from `brdf`.
fn check(material: &str, brdf: &dyn Brdf) -> Agreement {
    let tables = RglTables::from_brdf(brdf, RglResolution::DEFAULT, material).unwrap();
    let written = RglBsdf::from_bytes(material, &tables.to_bytes()).unwrap();
    let path = test_data(&format!("rgl_export_mitsuba_{material}.csv"));
    let mut reader = csv::Reader::from_path(&path).unwrap();
    let mut pairs = Vec::new();
    for v in reader.deserialize::<Vector>() {
        let v = v.unwrap();
        // Mitsuba's `si.wi` (theta_i, phi_i) is the camera's direction, its `wo` the light's.
        let camera = Spherical::from_degrees(v.theta_i, v.phi_i).to_vector();
        let light = Spherical::from_degrees(v.theta_o, v.phi_o).to_vector();
        let mitsuba = glam::DVec3::new(v.r, v.g, v.b);
        let ours = written.eval(light, camera).unwrap();
        for c in 0..3 {
            if mitsuba[c] > 1e-3 {
                let relative = (ours[c] - mitsuba[c]).abs() / mitsuba[c];
                assert!(
                    relative < 1e-3,
                    "{material} at {:?}: reader {ours} Mitsuba {mitsuba}",
                    (v.theta_i, v.phi_i, v.theta_o, v.phi_o)
                );
            }
        }
        let truth = brdf.eval_smooth(light, camera).unwrap();
        pairs.push(Pair {
            truth: luminance(truth) * light.z,
            mitsuba: luminance(mitsuba) * light.z,
        });
    }
    assert_eq!(pairs.len(), 2100, "{material}: the vectors' pairs");
    let agreement = agreement(&pairs);
    println!("{material}: {agreement:?}");
    agreement
}

/// The figures of [`Agreement`] over `pairs`.
fn agreement(pairs: &[Pair]) -> Agreement {
    let peak = pairs.iter().map(|p| p.truth).fold(0.0, f64::max);
    let within = |set: &[&Pair]| {
        set.iter().filter(|p| p.relative() <= WITHIN).count() as f64 / set.len() as f64
    };
    let weighted_mean = |set: &[&Pair]| {
        set.iter().map(|p| (p.mitsuba - p.truth).abs()).sum::<f64>()
            / set.iter().map(|p| p.truth).sum::<f64>()
    };
    let above =
        |floor: f64| -> Vec<&Pair> { pairs.iter().filter(|p| p.truth >= floor * peak).collect() };
    let all: Vec<&Pair> = pairs.iter().collect();
    let significant = above(SIGNIFICANT);
    let matters = above(MATTERS);
    let mut relative: Vec<f64> = matters.iter().map(|p| p.relative()).collect();
    relative.sort_by(f64::total_cmp);
    Agreement {
        within_all: within(&all),
        within_significant: within(&significant),
        significant: significant.len(),
        weighted_mean_all: weighted_mean(&all),
        compared: matters.len(),
        weighted_mean: weighted_mean(&matters),
        median: relative[relative.len() / 2],
        p90: relative[relative.len() * 9 / 10],
    }
}

/// The MERL tabulation of a real RGL file, as `specula tabulate` writes it.
fn merl_tabulation(rgl_file: &str) -> Option<Arc<dyn Brdf>> {
    let path = measured(&format!("rgl_bsdf/{rgl_file}.bsdf"))?;
    let original = load_brdf(path.to_str().unwrap()).unwrap();
    let phi_h_rad = GridSpec::paper().phi_h_deg.to_radians();
    Some(Arc::new(tabulate(original.as_ref(), phi_h_rad)))
}

#[test]
fn sharp_conductor_agrees_with_mitsuba() {
    let a = check("chrome", load_brdf("chrome").unwrap().as_ref());
    assert_claim("chrome", &a);
    assert!(a.within_all >= 0.99, "{a:?}");
    assert!(a.compared >= 300, "{a:?}");
    // The peak: 0.018 % weighted mean, 0.015 % median, 0.07 % 90th percentile.
    assert!(
        a.weighted_mean < 0.0004 && a.median < 0.0003 && a.p90 < 0.0015,
        "{a:?}"
    );
    assert!(a.weighted_mean_all < 0.0004, "{a:?}");
}

#[test]
fn green_paint_agrees_with_mitsuba_at_95_percent_of_pairs() {
    let a = check("green-paint", load_brdf("green-paint").unwrap().as_ref());
    assert_claim("green-paint", &a);
    assert!(a.compared >= 200, "{a:?}");
    assert!(
        a.weighted_mean < 0.005 && a.median < 0.0025 && a.p90 < 0.007,
        "{a:?}"
    );
    assert!(a.weighted_mean_all < 0.005, "{a:?}");
}

#[test]
fn real_rgl_file_round_trips_through_mitsuba() {
    let Some(file) = measured("rgl_bsdf/cc_ibiza_sunset_rgb.bsdf") else {
        return;
    };
    let a = check(
        "cc_ibiza_sunset_rgb",
        load_brdf(file.to_str().unwrap()).unwrap().as_ref(),
    );
    assert_claim("cc_ibiza_sunset_rgb", &a);
    assert!(a.significant >= 500, "{a:?}");
    assert!(a.compared >= 500, "{a:?}");
    assert!(
        a.weighted_mean < 0.005 && a.median < 0.0008 && a.p90 < 0.008,
        "{a:?}"
    );
    assert!(a.weighted_mean_all < 0.005, "{a:?}");
}

#[test]
fn the_other_real_rgl_files_round_trip_through_mitsuba() {
    for name in &RGL_MATERIALS[1..] {
        let Some(file) = measured(&format!("rgl_bsdf/{name}.bsdf")) else {
            return;
        };
        let a = check(name, load_brdf(file.to_str().unwrap()).unwrap().as_ref());
        assert_claim(name, &a);
    }
}

#[test]
fn merl_tabulations_of_the_real_files_agree_with_mitsuba() {
    for name in RGL_MATERIALS {
        let Some(brdf) = merl_tabulation(name) else {
            return;
        };
        let material = format!("merl_{name}");
        let a = check(&material, brdf.as_ref());
        assert_claim(&material, &a);
    }
}

#[test]
fn neural_fits_agree_with_mitsuba() {
    for name in [
        "gold-metallic-paint",
        "specular-blue-phenolic",
        "red-fabric",
    ] {
        if measured("merl_nbrdf/merl100_nbrdf_weights_f32le.bin").is_none() {
            return;
        }
        let brdf = load_brdf(&format!("nbrdf:{name}")).unwrap();
        let material = format!("nbrdf_{name}");
        let a = check(&material, brdf.as_ref());
        assert_claim(&material, &a);
    }
}
