//! `specula calibrate` and `specula check` end to end on the simulated device.

use assert_cmd::Command;
use predicates::prelude::*;
use specula_acquisition::calibration::Calibration;

fn specula() -> Command {
    Command::cargo_bin("specula").unwrap()
}

/// The value after `prefix` on the line that starts with it, as a number.
fn number_after(output: &str, prefix: &str) -> f64 {
    let line = output
        .lines()
        .find(|l| l.starts_with(prefix))
        .unwrap_or_else(|| panic!("no line starting {prefix:?} in\n{output}"));
    line[prefix.len()..]
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

#[test]
fn calibrate_stores_a_calibration_that_later_runs_read() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cal.toml");
    let assert = specula()
        .args([
            "calibrate",
            "--truth",
            "green-paint",
            "--seed",
            "4",
            "--out",
        ])
        .arg(&out)
        .assert()
        .success();
    let stdout = String::from_utf8_lossy(&assert.get_output().stdout).to_string();
    assert!(stdout.contains("colour matrix"), "{stdout}");
    let cal = Calibration::load(&out).unwrap();
    // The default camera: responsivity (2.2e7, 2.7e7, 1.8e7) e-/s per 1/sr at 0.25 DN/e-.
    for (gain, expected) in cal.gain_dn_s_per_sr.iter().zip([5.5e6, 6.75e6, 4.5e6]) {
        assert!(
            (gain / expected - 1.0).abs() < 0.005,
            "{gain} vs {expected}"
        );
    }
    // Off the highlight the calibrated green paint matches its truth to 2 %.
    let row = stdout
        .lines()
        .find(|l| l.starts_with("30,"))
        .expect(&stdout);
    let ratio: f64 = row.rsplit(',').next().unwrap().parse().unwrap();
    assert!((ratio - 1.0).abs() < 0.02, "{row}");
}

#[test]
fn alignment_finds_the_simulated_tilt() {
    let assert = specula()
        .args(["check", "alignment", "--truth", "silver-925"])
        .args(["--tilt", "0.25", "--tilt-azimuth-deg", "-60", "--seed", "3"])
        .assert()
        .success();
    let stdout = String::from_utf8_lossy(&assert.get_output().stdout).to_string();
    let tilt = number_after(&stdout, "tilt: ");
    assert!((tilt - 0.25).abs() < 0.05, "{stdout}");
    let azimuth = stdout
        .lines()
        .find(|l| l.starts_with("tilt: "))
        .and_then(|l| l.split("azimuth ").nth(1))
        .and_then(|s| s.split_whitespace().next())
        .map(|s| s.parse::<f64>().unwrap())
        .unwrap();
    assert!((azimuth - 300.0).abs() < 10.0, "{stdout}");
    assert!(
        stdout.contains("adjustment: tilt the sample back"),
        "{stdout}"
    );
}

#[test]
fn orientation_flags_scratches_on_the_planned_phi_h() {
    specula()
        .args(["check", "orientation", "--truth", "silver-925"])
        .args(["--scratch-orientation", "135"])
        .assert()
        .success()
        .stdout(predicate::str::contains("anisotropic: yes"))
        .stdout(predicate::str::contains(
            "planned phi_h = 45.0 deg: CONTAMINATED",
        ));
}

#[test]
fn flare_is_retaken() {
    let assert = specula()
        .args(["check", "flare", "--truth", "silver-925", "--seed", "2"])
        .assert()
        .success();
    let stdout = String::from_utf8_lossy(&assert.get_output().stdout).to_string();
    assert!(
        number_after(&stdout, "flagged, retaken at another arm position: ") >= 1.0,
        "{stdout}"
    );
}

#[test]
fn bad_input_is_one_line_and_exit_1() {
    specula()
        .args(["check", "orientation", "--truth", "no-such-material"])
        .args(["--scratch-orientation", "30"])
        .assert()
        .code(1)
        .stderr(predicate::str::contains("no-such-material"))
        .stderr(predicate::function(|s: &str| s.lines().count() == 1));
    specula()
        .args([
            "check",
            "alignment",
            "--truth",
            "silver-925",
            "--rotations",
            "2",
        ])
        .assert()
        .code(2)
        .stderr(predicate::str::contains(
            "--rotations 2: expected a whole number from 3 to 72",
        ));
    specula()
        .args([
            "calibrate",
            "--truth",
            "silver-925",
            "--out",
            "/nonexistent/dir/cal.toml",
        ])
        .assert()
        .code(2)
        .stderr(predicate::str::contains(
            "/nonexistent/dir/cal.toml: its folder /nonexistent/dir does not exist",
        ));
}
