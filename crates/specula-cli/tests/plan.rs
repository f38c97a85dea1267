//! `specula plan` as a user runs it.

use assert_cmd::Command;
use predicates::prelude::*;

fn specula() -> Command {
    Command::cargo_bin("specula").expect("the specula binary is built")
}

const HEADER: &str = "index,theta_h,phi_h,theta_d,phi_d,theta_i,phi_i,theta_o,phi_o,status,\
                      turntable_deg,camera_deg,light_azimuth_deg,light_elevation_deg,time_s";

#[test]
fn small_explicit_grid_in_nested_order() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("plan.csv");
    specula()
        .args(["plan", "--theta-h-list", "0,10,40", "--theta-d-step", "30"])
        .args(["--phi-d-step", "45", "--phi-d-span", "quarter"])
        .args(["--order", "nested", "--out"])
        .arg(&out)
        .assert()
        .success()
        .stdout(predicate::str::contains("samples: 27"))
        .stdout(predicate::str::contains("measurable:"))
        .stdout(predicate::str::contains("nested"))
        .stdout(predicate::str::contains("optimized"));
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(HEADER));
    let rows: Vec<Vec<String>> = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    assert_eq!(rows.len(), 27);
    // theta_d = 0 rows are retro-reflections: occluded (or out of range).
    for row in &rows {
        if row[3].parse::<f64>().unwrap() == 0.0 {
            assert_ne!(row[9], "ok", "{row:?}");
        }
    }
    // Nested order: the measured rows come first with increasing index.
    let measured: Vec<usize> = rows
        .iter()
        .filter(|r| r[9] == "ok")
        .map(|r| r[0].parse().unwrap())
        .collect();
    assert!(measured.windows(2).all(|w| w[0] < w[1]), "{measured:?}");
}

#[test]
fn print_device_gives_a_usable_file() {
    let dir = tempfile::tempdir().unwrap();
    let device = dir.path().join("device.toml");
    let output = specula().args(["plan", "--print-device"]).output().unwrap();
    assert!(output.status.success());
    std::fs::write(&device, &output.stdout).unwrap();
    let out = dir.path().join("plan.csv");
    specula()
        .args([
            "plan",
            "--theta-h-list",
            "5",
            "--theta-d-step",
            "45",
            "--device",
        ])
        .arg(&device)
        .arg("--out")
        .arg(&out)
        .assert()
        .success();
}

#[test]
fn bad_input_is_one_line_and_exit_1() {
    let dir = tempfile::tempdir().unwrap();
    let device = dir.path().join("broken.toml");
    std::fs::write(&device, "name = 3\n").unwrap();
    let out = dir.path().join("plan.csv");
    let output = specula()
        .args(["plan", "--k", "4.78", "--device"])
        .arg(&device)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(stderr.contains("broken.toml"), "{stderr}");

    specula()
        .args(["plan", "--k", "4.78", "--theta-d-step", "0", "--out"])
        .arg(&out)
        .assert()
        .code(2)
        .stderr(predicate::str::contains(
            "--theta-d-step 0: expected degrees from 0.5 to 90",
        ));
    specula()
        .args(["plan", "--k", "-1", "--out"])
        .arg(&out)
        .assert()
        .code(2)
        .stderr(predicate::str::contains(
            "--k -1: expected a number above 0 and at most 100",
        ));
    // Neither --k nor --theta-h-list: a usage error.
    specula().args(["plan", "--out"]).arg(&out).assert().code(2);
}
