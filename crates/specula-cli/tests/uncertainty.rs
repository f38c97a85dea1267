//! The measurement uncertainty as a user meets it: `reconstruct` writes
//! `OUT.uncertainty.binary`, `info` summarises it, `appearance --csv` gives each figure's
//! expanded uncertainty in `U_` columns and `coverage` says how often it covers the truth.

use assert_cmd::Command;
use specula_core::geometry::elevation_deg;
use specula_core::merl::{Bin, MerlBrdf};
use specula_core::HalfDiff;
use specula_reconstruct::uncertainty::sidecar_path;
use std::path::Path;

fn specula() -> Command {
    Command::cargo_bin("specula").expect("the specula binary is built")
}

fn text(path: &Path) -> &str {
    path.to_str().expect("a UTF-8 temporary path")
}

fn run(args: &[&str]) -> String {
    let out = specula().args(args).output().expect("run specula");
    assert!(out.status.success(), "{out:?}");
    String::from_utf8(out.stdout).unwrap()
}

/// `specula reconstruct --samples-csv SAMPLES --out OUT`'s standard output.
fn reconstruct(samples: &Path, out: &Path) -> String {
    run(&[
        "reconstruct",
        "--samples-csv",
        text(samples),
        "--out",
        text(out),
    ])
}

/// A table reconstructed from green-paint's samples on a small plan, with its sidecars.
fn reconstructed(dir: &Path) -> std::path::PathBuf {
    let samples = dir.join("samples.csv");
    let out = dir.join("paint.binary");
    run(&[
        "evaluate",
        "--truth",
        "green-paint",
        "--theta-h-samples",
        "10",
        "--theta-d-step",
        "8",
        "--phi-d-step",
        "45",
        "--samples-out",
        text(&samples),
    ]);
    let stdout = reconstruct(&samples, &out);
    assert!(
        stdout.contains("uncertainty_within_75_deg=median"),
        "{stdout}"
    );
    assert!(stdout.contains("paint.uncertainty.binary"), "{stdout}");
    out
}

#[test]
fn reconstruct_writes_the_uncertainty_and_info_and_coverage_read_it() {
    let dir = tempfile::tempdir().unwrap();
    let out = reconstructed(dir.path());
    let table = MerlBrdf::read(&out).unwrap();
    let u = MerlBrdf::read(&sidecar_path(&out)).unwrap();
    // A value where the table has one within the samples' reach (the largest elevation of
    // their lights and cameras, and one degree more), none elsewhere; never below the
    // calibration's 0.5 %.
    let samples = std::fs::read_to_string(dir.path().join("samples.csv")).unwrap();
    let reach = samples
        .lines()
        .skip(1)
        .map(|line| {
            let a: Vec<f64> = line.split(',').map(|v| v.parse().unwrap()).collect();
            elevation_deg(HalfDiff::from_degrees(a[0], a[1], a[2], a[3]))
        })
        .fold(0.0, f64::max);
    assert!(reach > 60.0 && reach <= 75.0 + 1e-9, "{reach}");
    let mut beyond = 0;
    for index in (0..specula_core::merl::CELLS).step_by(97) {
        let elevation = elevation_deg(Bin::from_index(index).centre(0.0));
        match (table.cell(index), u.cell(index)) {
            (Some(v), Some(u)) => {
                assert!(
                    elevation <= reach + 1.0 + 1e-9,
                    "cell {index} at {elevation} deg"
                );
                for c in 0..3 {
                    assert!(u[c] >= 0.005 * v[c] * (1.0 - 1e-5), "{index} {v:?} {u:?}");
                }
            }
            (Some(_), None) if elevation > reach => beyond += 1,
            (None, None) => {}
            other => panic!("cell {index} at {elevation} deg: {other:?}"),
        }
    }
    assert!(beyond > 0);
    let info = run(&["info", text(&out)]);
    assert!(info.contains("uncertainty_within_75_deg=median"), "{info}");
    let coverage = run(&["coverage", text(&out), "green-paint"]);
    let both: Vec<&str> = coverage
        .lines()
        .find(|l| l.starts_with("both,"))
        .expect("a row for both sets")
        .split(',')
        .collect();
    let values: usize = both[1].parse().unwrap();
    let fraction: f64 = both[3].parse().unwrap();
    assert!(values > 1000, "{coverage}");
    assert!((0.0..=1.0).contains(&fraction), "{coverage}");
}

#[test]
fn coverage_without_the_sidecar_names_it_once() {
    let dir = tempfile::tempdir().unwrap();
    let out = reconstructed(dir.path());
    let sidecar = sidecar_path(&out);
    std::fs::remove_file(&sidecar).unwrap();
    let output = specula()
        .args(["coverage", text(&out), "green-paint"])
        .output()
        .unwrap();
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("no uncertainty beside the table"),
        "{stderr}"
    );
    assert_eq!(stderr.matches(text(&sidecar)).count(), 1, "{stderr}");
}

#[test]
fn info_with_a_truncated_sidecar_names_it_once_and_fails() {
    let dir = tempfile::tempdir().unwrap();
    let out = reconstructed(dir.path());
    let sidecar = sidecar_path(&out);
    let bytes = std::fs::read(&sidecar).unwrap();
    std::fs::write(&sidecar, &bytes[..1000]).unwrap();
    let output = specula().args(["info", text(&out)]).output().unwrap();
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("truncated"), "{stderr}");
    assert_eq!(stderr.matches(text(&sidecar)).count(), 1, "{stderr}");
}

#[test]
fn appearance_csv_appends_the_figures_expanded_uncertainty() {
    let dir = tempfile::tempdir().unwrap();
    let out = reconstructed(dir.path());
    let csv = run(&["appearance", "--csv", "green-paint", text(&out)]);
    let lines: Vec<&str> = csv.lines().collect();
    let header: Vec<&str> = lines[0].split(',').collect();
    let column = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("no column {name}: {}", lines[0]))
    };
    // The U_ columns follow the figures, one per figure.
    assert!(column("U_gloss_20") > column("flop_index"), "{}", lines[0]);
    for figure in ["gloss_60", "gloss_85", "haze", "doi", "L_15", "flop_index"] {
        assert!(column(&format!("U_{figure}")) > column("flop_index"));
    }
    let row = |k: usize| -> Vec<&str> { lines[k].split(',').collect() };
    // The truth has no sidecar: empty; the table's U is positive and finite.
    assert_eq!(row(1)[column("U_gloss_60")], "");
    let u: f64 = row(2)[column("U_gloss_60")].parse().unwrap();
    assert!(u > 0.0 && u.is_finite(), "{}", lines[2]);
    // The planned samples stay within 75 deg of the normal: gloss 85's light and camera lie
    // beyond their reach, where the cells have no uncertainty, and so has the figure.
    assert!(!row(2)[column("gloss_85")].is_empty(), "{}", lines[2]);
    assert_eq!(row(2)[column("U_gloss_85")], "", "{}", lines[2]);
    // The text table shows it as ± U.
    let table = run(&["appearance", text(&out)]);
    assert!(table.contains(" ± "), "{table}");
}

/// One sample says nothing of how the table varies away from it: the cells off its bin get no
/// uncertainty (not the calibration's floor alone), and neither do the figures over them.
#[test]
fn a_single_sample_gives_no_uncertainty_away_from_it_nor_to_the_figures() {
    let dir = tempfile::tempdir().unwrap();
    let samples = dir.path().join("one.csv");
    std::fs::write(
        &samples,
        "theta_h,phi_h,theta_d,phi_d,r,g,b\n10.3,45,30.4,40.3,2.0,1.5,1.0\n",
    )
    .unwrap();
    let out = dir.path().join("one.binary");
    let stdout = reconstruct(&samples, &out);
    assert!(stdout.contains("given on 2 of "), "{stdout}");
    assert!(
        stdout.contains("off the plane of theta_h and theta_d and phi_d"),
        "{stdout}"
    );
    let u = MerlBrdf::read(&sidecar_path(&out)).unwrap();
    assert_eq!(u.measured_count(), 2);
    let csv = run(&["appearance", "--csv", text(&out)]);
    let lines: Vec<&str> = csv.lines().collect();
    let header: Vec<&str> = lines[0].split(',').collect();
    let row: Vec<&str> = lines[1].split(',').collect();
    for figure in ["U_gloss_20", "U_gloss_60", "U_gloss_85", "U_haze", "U_doi"] {
        let k = header.iter().position(|h| *h == figure).unwrap();
        assert_eq!(row[k], "", "{figure}: {}", lines[1]);
    }
}

/// The cell coverage at k = 2 of `truth` measured with seed 1 on the default simulated
/// device as a lab runs it (`specula measure`, sequential, then `specula coverage`).
fn measured_coverage(truth: &str) -> f64 {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m.binary");
    run(&[
        "measure",
        "--truth",
        truth,
        "--seed",
        "1",
        "--out",
        text(&out),
    ]);
    let coverage = run(&["coverage", text(&out), truth]);
    coverage
        .lines()
        .find(|l| l.starts_with("both,"))
        .and_then(|l| l.split(',').nth(3))
        .and_then(|f| f.parse().ok())
        .unwrap_or_else(|| panic!("no coverage: {coverage}"))
}

#[test]
#[ignore = "a full simulated measurement per truth, minutes each: cargo test --release -p specula-cli --test uncertainty -- --ignored"]
fn measured_coverage_of_data_derived_truths_is_within_the_target() {
    // sgd:red-metallic-paint is a training truth (0.983 measured), abc:polyethylene a
    // held-out one (0.990): 0.910 and 0.919 before the core term, the cells within 0.26 deg
    // of the mirror direction holding the narrow spike their blurred samples do not show.
    for truth in ["sgd:red-metallic-paint", "abc:polyethylene"] {
        let fraction = measured_coverage(truth);
        assert!((0.90..=0.995).contains(&fraction), "{truth}: {fraction}");
    }
}

#[test]
#[ignore = "a full simulated measurement, minutes: cargo test --release -p specula-cli --test uncertainty -- --ignored"]
fn measured_coverage_of_a_two_lobe_truth_is_within_the_target() {
    // 0.9955 when the deblurring term counted at every theta_h; 0.977 with it within the
    // peak region, where the deblurred table's checks pass beyond it; 0.958 with a covering
    // factor per region of theta_h.
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tools/instrument_truths/two-lobe-silver-haze.toml");
    let fraction = measured_coverage(text(&path));
    assert!((0.90..=0.995).contains(&fraction), "two-lobe: {fraction}");
}

#[test]
#[ignore = "a full simulated measurement, minutes: cargo test --release -p specula-cli --test uncertainty -- --ignored"]
fn measured_coverage_of_an_analytic_truth_is_within_the_target() {
    // 1.0000 when the folds of the cross-validation refitted a lobe without the response and
    // the deblurring term counted at every theta_h; 0.991 with the folds over the deblurred
    // lobe and the term within the peak region (with seed 2 0.995, at the target's edge);
    // 0.978 with a covering factor per region of theta_h.
    let fraction = measured_coverage("chrome");
    assert!((0.90..=0.995).contains(&fraction), "chrome: {fraction}");
}

#[test]
#[ignore = "a full simulated measurement, minutes: cargo test --release -p specula-cli --test uncertainty -- --ignored"]
fn measured_coverage_of_a_metal_sharper_than_the_resolution_is_within_the_target() {
    // 0.884 when a sample's local amplitude was the root mean square of its neighbours'
    // differences, 0.911 with the scale of their median; 0.889 with a covering factor per
    // region of theta_h alone, 0.921 with the core term too (its deblurred table is 80 %
    // below the truth within 0.1 deg of the mirror direction).
    let fraction = measured_coverage("nbrdf:aluminium");
    assert!((0.90..=0.995).contains(&fraction), "aluminium: {fraction}");
}

#[test]
#[ignore = "a full simulated measurement, minutes: cargo test --release -p specula-cli --test uncertainty -- --ignored"]
fn measured_coverage_of_a_clear_coat_is_within_the_target() {
    // 0.9985 with one covering factor per axis, set by the peak's tails, which covered the
    // body several times over; 0.975 with one per region of theta_h.
    let fraction = measured_coverage("green-paint");
    assert!(
        (0.90..=0.995).contains(&fraction),
        "green-paint: {fraction}"
    );
}
