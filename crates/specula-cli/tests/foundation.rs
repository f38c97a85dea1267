//! The foundation commands as a user runs them: tabulate, info, eval, compare, and their
//! answers to bad input (one line naming the file, exit 1; usage errors exit 2).

use assert_cmd::Command;
use predicates::prelude::*;
use std::path::Path;

fn specula() -> Command {
    Command::cargo_bin("specula").expect("the specula binary is built")
}

fn write_file(path: &Path, bytes: &[u8]) {
    std::fs::write(path, bytes).expect("write a test file");
}

/// Asserts a one-line error naming `needle` and exit status 1.
fn fails_naming(cmd: &mut Command, needle: &str, problem: &str) {
    let out = cmd.output().expect("run specula");
    assert_eq!(out.status.code(), Some(1), "{out:?}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.trim_end().lines().count(), 1, "one line: {stderr}");
    assert!(stderr.contains(needle), "names {needle}: {stderr}");
    assert!(stderr.contains(problem), "says {problem}: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn usage_errors_exit_2_and_help_teaches() {
    specula().arg("info").assert().code(2);
    specula().arg("--bogus").assert().code(2);
    for command in ["tabulate", "info", "eval", "compare", "demo"] {
        specula()
            .args([command, "--help"])
            .assert()
            .success()
            .stdout(predicate::str::contains("Usage: specula"));
    }
}

#[test]
fn info_rejects_bad_files_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.binary");
    fails_naming(
        specula().arg("info").arg(&missing),
        "missing.binary",
        "cannot read",
    );
    fails_naming(
        specula().arg("info").arg(dir.path()),
        &dir.path().display().to_string(),
        "directory",
    );

    let short = dir.path().join("short.binary");
    write_file(&short, &[1, 2, 3]);
    fails_naming(
        specula().arg("info").arg(&short),
        "short.binary",
        "too short",
    );

    let mut header = Vec::new();
    for d in [90i32, 90, 1_000_000] {
        header.extend_from_slice(&d.to_le_bytes());
    }
    let absurd = dir.path().join("absurd.binary");
    write_file(&absurd, &header);
    fails_naming(
        specula().arg("info").arg(&absurd),
        "absurd.binary",
        "dimensions",
    );

    let mut truncated = Vec::new();
    for d in [90i32, 90, 180] {
        truncated.extend_from_slice(&d.to_le_bytes());
    }
    truncated.extend_from_slice(&[0u8; 800]);
    let path = dir.path().join("truncated.binary");
    write_file(&path, &truncated);
    fails_naming(
        specula().arg("info").arg(&path),
        "truncated.binary",
        "truncated",
    );
}

#[test]
fn info_and_eval_on_a_table_with_holes() {
    use specula_core::merl::{Bin, MerlBrdf, CELLS};
    use specula_core::{HalfDiff, Rgb};
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("holes.binary");
    let mut table = MerlBrdf::empty("holes");
    for i in 0..CELLS {
        table.set_cell(i, Some(Rgb::new(0.1, 0.2, 0.3)));
    }
    // A peak at a known cell and a hole at the retro-reflection of the normal.
    let peak = Bin {
        theta_h_i: 0,
        theta_d_i: 40,
        phi_d_i: 90,
    };
    table.set_cell(peak.index(), Some(Rgb::new(50.0, 60.0, 70.0)));
    let hole = Bin::of(HalfDiff::from_degrees(0.0, 0.0, 0.0, 0.0));
    table.set_cell(hole.index(), None);
    table.write(&path).unwrap();

    specula()
        .arg("info")
        .arg(&path)
        .assert()
        .success()
        .stdout(predicate::str::contains(
            "measured: 1457999 of 1458000 cells\n",
        ))
        .stdout(predicate::str::contains("theta_d 40.5 deg, phi_d 90.5 deg"));

    let dirs = dir.path().join("dirs.csv");
    std::fs::write(
        &dirs,
        "theta_i,phi_i,theta_o,phi_o\n0,0,0,0\n30,0,30,180\n95,0,30,180\n",
    )
    .unwrap();
    let out = specula()
        .arg("eval")
        .arg(&path)
        .arg("--dirs")
        .arg(&dirs)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "r,g,b");
    assert_eq!(
        lines[1], "nan,nan,nan",
        "the normal's retro-reflection was not measured"
    );
    let mirror: Vec<f64> = lines[2].split(',').map(|v| v.parse().unwrap()).collect();
    assert!((mirror[0] - 0.1).abs() < 1e-12 && (mirror[2] - 0.3).abs() < 1e-12);
    assert_eq!(lines[3], "0e0,0e0,0e0", "below the horizon");

    std::fs::write(&dirs, "theta_i,phi_i,theta_o,phi_o\n1,2,x,4\n").unwrap();
    fails_naming(
        specula().arg("eval").arg(&path).arg("--dirs").arg(&dirs),
        "dirs.csv",
        "row 2",
    );
}

#[test]
fn compare_a_table_with_itself_gives_zero() {
    use specula_core::merl::{MerlBrdf, CELLS};
    use specula_core::Rgb;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("flat.binary");
    let mut table = MerlBrdf::empty("flat");
    for i in 0..CELLS {
        table.set_cell(i, Some(Rgb::splat(0.2)));
    }
    table.write(&path).unwrap();
    let p = path.to_str().unwrap();
    specula()
        .args(["compare", p, p])
        .assert()
        .success()
        .stdout(predicate::str::contains("all,"))
        .stdout(predicate::str::contains(",0.000000,0.000000,0.000000e0"));
    fails_naming(
        specula().args(["compare", p, "no-such-material"]),
        "no-such-material",
        "no such",
    );
}

/// `evaluate --truth FOLDER` takes every measured file in the folder and summarises the real
/// truths apart from the others, real first.
#[test]
fn evaluate_takes_a_folder_of_real_measurements() {
    let folder =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/measured/rgl_bsdf");
    if !folder.is_dir() {
        eprintln!(
            "skipped: {} is absent (the shared data beside the clone as ../shared)",
            folder.display()
        );
        return;
    }
    let out = specula()
        .args(["evaluate", "--truth"])
        .arg(&folder)
        .args([
            "--truth",
            "silver-925",
            "--theta-h-samples",
            "6",
            "--theta-d-step",
            "10",
            "--phi-d-step",
            "45",
        ])
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let summaries: Vec<&str> = stdout
        .lines()
        .filter(|l| l.starts_with("# real,") || l.starts_with("# given,"))
        .collect();
    assert_eq!(summaries.len(), 4, "{stdout}");
    assert!(summaries[0].starts_with("# real,median,5,"), "{stdout}");
    assert!(summaries[2].starts_with("# given,median,1,"), "{stdout}");
    assert!(stdout.contains("\npaper_white_rgb,"), "{stdout}");
}
