//! `specula probe`, `fit-k`, `analyze` and `placement` as a user runs them (issue 3).

use assert_cmd::Command;
use predicates::prelude::*;

fn specula() -> Command {
    Command::cargo_bin("specula").expect("the specula binary is built")
}

#[test]
fn probe_then_fit_k() {
    let dir = tempfile::tempdir().unwrap();
    let probe = dir.path().join("probe.csv");
    specula()
        .args([
            "probe",
            "abc:chrome-steel",
            "--probe-samples",
            "60",
            "--out",
        ])
        .arg(&probe)
        .assert()
        .success()
        .stdout(predicate::str::contains("wrote 60 samples"));
    let text = std::fs::read_to_string(&probe).unwrap();
    assert!(text.starts_with("theta_h,r,g,b\n"));
    assert_eq!(text.lines().count(), 61);

    let out = specula()
        .arg("fit-k")
        .arg(&probe)
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    let out = String::from_utf8(out).unwrap();
    let first = out.lines().next().unwrap();
    let (k, error) = first
        .strip_prefix("k=")
        .and_then(|rest| rest.split_once(" error="))
        .unwrap_or_else(|| panic!("first line '{first}'"));
    let (k, error): (f64, f64) = (k.parse().unwrap(), error.parse().unwrap());
    // A mirror-like metal crowds its samples at the peak: k well above the square root's.
    assert!(k > 3.0 && error > 0.0, "{first}");
    let positions = out
        .lines()
        .nth(2)
        .unwrap()
        .strip_prefix("theta_h_deg=")
        .unwrap();
    assert_eq!(positions.split(',').count(), 30);

    specula()
        .arg("fit-k")
        .arg(&probe)
        .args(["--family", "power", "--theta-h-samples", "10"])
        .assert()
        .success()
        .stdout(predicate::str::starts_with("k="));
}

#[test]
fn fit_k_reports_bad_input_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.csv");
    std::fs::write(&bad, "theta_h,r,g,b\n0,1,1,1\n").unwrap();
    specula()
        .arg("fit-k")
        .arg(&bad)
        .assert()
        .code(1)
        .stderr(predicate::str::contains("bad.csv").and(predicate::str::contains("at least 2")));
    specula()
        .args(["fit-k", "/nonexistent/probe.csv"])
        .assert()
        .code(1)
        .stderr(predicate::str::contains("probe.csv"));
    specula()
        .args(["fit-k", "x.csv", "--family", "cubic"])
        .assert()
        .code(2);
}

#[test]
fn analyze_writes_tables_and_a_heatmap_and_names_the_best_pair() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("analysis");
    specula()
        .args([
            "analyze",
            "abc:gold-metallic-paint",
            "sgd:blue-acrylic",
            "--out",
        ])
        .arg(&out)
        .assert()
        .success()
        .stdout(predicate::str::contains("best: "))
        .stdout(predicate::str::contains("over 2 materials"))
        .stdout(predicate::str::contains(
            "paper's pair: exponential at theta_d = 40",
        ));
    let summary = std::fs::read_to_string(out.join("analysis.csv")).unwrap();
    assert!(summary.starts_with("family,theta_d,mean_error,median_error,materials\n"));
    assert_eq!(summary.lines().count(), 1 + 3 * 90);
    let materials = std::fs::read_to_string(out.join("materials.csv")).unwrap();
    assert_eq!(materials.lines().count(), 1 + 2 * 3 * 90);
    let png = std::fs::read(out.join("analysis.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");

    specula()
        .args(["analyze", "--out"])
        .arg(&out)
        .assert()
        .code(1)
        .stderr(predicate::str::contains("nothing to analyse"));
}

#[test]
fn placement_prints_the_comparison_table() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("placement.csv");
    specula()
        .args(["placement", "abc:gold-metallic-paint", "--out"])
        .arg(&csv)
        .assert()
        .success()
        .stdout(predicate::str::contains("| square root (eq. 1) |"))
        .stdout(predicate::str::contains(
            "| oracle: DP per column on the truth | ",
        ))
        .stdout(predicate::str::contains("1 materials"));
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("material,k_hat,domain,square_root,paper,probe_samples,ours,oracle")
    );
    let row: Vec<f64> = lines
        .next()
        .unwrap()
        .split(',')
        .skip(3)
        .map(|v| v.parse().unwrap())
        .collect();
    // The oracle is the lower bound of the placements on the truth's nodes (the DP ones).
    let oracle = row[4];
    assert!(
        oracle > 0.0 && row[2] >= oracle && row[3] >= oracle,
        "{row:?}"
    );
}
