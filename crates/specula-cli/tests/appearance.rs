//! `specula appearance` as a user runs it: the CSV header and rows, differences against a
//! reference, warnings for extrapolated cells, and its answers to bad input.

use assert_cmd::Command;
use specula_core::merl::CELLS;
use specula_reconstruct::provenance::{sidecar_path, CellOrigin, Provenance};

fn specula() -> Command {
    Command::cargo_bin("specula").expect("the specula binary is built")
}

fn run(args: &[&str]) -> (String, String) {
    let out = specula().args(args).output().expect("run specula");
    assert!(out.status.success(), "{out:?}");
    (
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

#[test]
fn csv_has_one_row_per_brdf_with_the_issue_s_header() {
    let (stdout, _) = run(&["appearance", "green-paint", "chrome", "--csv"]);
    let lines: Vec<&str> = stdout.lines().collect();
    assert!(
        lines[0].starts_with("source,gloss_20,gloss_60,gloss_85,haze,doi,"),
        "{}",
        lines[0]
    );
    assert!(lines[0].contains("L_15,a_15,b_15") && lines[0].ends_with("flop_index"));
    assert_eq!(lines.len(), 3, "{stdout}");
    let gloss_20 = |line: &str| line.split(',').nth(1).unwrap().parse::<f64>().unwrap();
    // A clear coat of index 1.49 reads under the black glass's 100 GU (its Fresnel ratio,
    // less the GGX tail outside the 20 deg receptor); polished chromium (reflectance about
    // 0.6) far above it.
    let paint = gloss_20(lines[1]);
    assert!(paint > 30.0 && paint < 100.0, "{paint}");
    assert!(gloss_20(lines[2]) > 500.0, "{}", lines[2]);
}

#[test]
fn against_a_reference_gives_differences_and_ciede2000() {
    let (stdout, _) = run(&["appearance", "silver-925", "--against", "chrome", "--csv"]);
    let lines: Vec<&str> = stdout.lines().collect();
    let header: Vec<&str> = lines[0].split(',').collect();
    assert!(header.contains(&"d_gloss_20") && header.contains(&"de00_110"));
    assert_eq!(lines.len(), 3, "the reference's row, then the BRDF's");
    let column = |row: &str, name: &str| -> f64 {
        let k = header.iter().position(|h| *h == name).unwrap();
        row.split(',').nth(k).unwrap().parse().unwrap()
    };
    assert!(lines[1].starts_with("chrome,"));
    assert_eq!(column(lines[1], "de00_45"), 0.0);
    assert!(column(lines[2], "de00_45") > 1.0, "silver is not chrome");
    let d = column(lines[2], "gloss_20") - column(lines[1], "gloss_20");
    assert!((column(lines[2], "d_gloss_20") - d).abs() < 1e-3);
    // The text table shows the same figures.
    let (text, _) = run(&["appearance", "silver-925", "--against", "chrome"]);
    assert!(
        text.contains("gloss 20 deg (GU)") && text.contains("dE00 15 deg"),
        "{text}"
    );
}

#[test]
fn extrapolated_cells_and_the_instrument_resolution_are_warned_about() {
    let dir = tempfile::tempdir().unwrap();
    let table = dir.path().join("paint.binary");
    let out = specula()
        .args(["tabulate", "green-paint", "--out"])
        .arg(&table)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    // Every cell marked extrapolated.
    let provenance = Provenance {
        cells: vec![CellOrigin::Extrapolated; CELLS],
    };
    provenance.write(&sidecar_path(&table)).unwrap();
    let table = table.to_string_lossy().to_string();
    let (_, stderr) = run(&["appearance", &table, "--resolution", "1.82"]);
    assert!(
        stderr.contains("gloss_20: 100.0 % of its flux comes from extrapolated cells"),
        "{stderr}"
    );
    assert!(
        stderr.contains(
            "doi: reads the BRDF 0.3 deg from the specular, finer than the instrument's 1.82 deg"
        ),
        "{stderr}"
    );
    assert!(
        !stderr.contains("gloss_60: reads"),
        "60 deg gloss reads 2.2 deg, coarser: {stderr}"
    );
}

#[test]
fn bad_input_is_one_line_or_a_usage_error() {
    specula()
        .args(["appearance", "green-paint", "--resolution", "0"])
        .assert()
        .code(2);
    specula().args(["appearance"]).assert().code(2);
    let out = specula()
        .args(["appearance", "no-such.binary"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(stderr.contains("no-such.binary"));
}

/// Writes a tolerance file into `dir` and returns its path as a string.
fn tolerance_file(dir: &std::path::Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_string_lossy().into_owned()
}

#[test]
fn tolerance_verdicts_pass_exit_0_and_a_failing_batch_exits_3() {
    let dir = tempfile::tempdir().unwrap();
    // silver-925 against itself: every difference is 0, inside any tolerance.
    let tight = tolerance_file(
        dir.path(),
        "tight.toml",
        "[tolerances]\ngloss_20 = 0.5\ngloss_60 = 0.5\nde00_15 = 0.1\nde00_45 = 0.1\n",
    );
    let (stdout, _) = run(&[
        "appearance",
        "silver-925",
        "--against",
        "silver-925",
        "--tolerances",
        &tight,
        "--csv",
    ]);
    let lines: Vec<&str> = stdout.lines().collect();
    assert!(lines[0].ends_with(",verdict"), "{}", lines[0]);
    assert!(lines[1].ends_with(",reference") && lines[2].ends_with(",pass"));

    // A batch of two samples, one of them chrome: one CSV, chrome fails on the figures it
    // misses by, silver passes; the run exits 3.
    let out = specula()
        .args([
            "appearance",
            "silver-925",
            "chrome",
            "--against",
            "silver-925",
            "--tolerances",
            &tight,
            "--csv",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(3), "{out:?}");
    let stdout = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 4, "{stdout}");
    assert!(lines[2].starts_with("silver-925,") && lines[2].ends_with(",pass"));
    assert!(
        lines[3].starts_with("chrome,")
            && lines[3].contains(",\"fail: gloss_20, gloss_60, de00_15, de00_45\""),
        "{}",
        lines[3]
    );
    assert!(String::from_utf8(out.stderr)
        .unwrap()
        .contains("1 of 2 samples outside their tolerances"));

    // The text table has a verdict row.
    let out = specula()
        .args([
            "appearance",
            "chrome",
            "--against",
            "silver-925",
            "--tolerances",
            &tight,
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(3));
    let text = String::from_utf8(out.stdout).unwrap();
    let verdict = text.lines().find(|l| l.starts_with("verdict")).unwrap();
    assert!(verdict.contains("reference") && verdict.contains("fail: gloss_20"));
}

#[test]
fn a_bad_tolerance_file_is_one_line_naming_the_file_and_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let unknown = tolerance_file(dir.path(), "t.toml", "[tolerances]\ngloss_30 = 5.0\n");
    let negative = tolerance_file(dir.path(), "n.toml", "[tolerances]\ngloss_20 = -1\n");
    let broken = tolerance_file(dir.path(), "b.toml", "[tolerances\ngloss_20 = 1\n");
    for (file, words) in [
        (&unknown, "unknown figure `gloss_30`"),
        (&negative, "`gloss_20` must be a number of at least 0"),
        (&broken, "line 1"),
    ] {
        let out = specula()
            .args([
                "appearance",
                "chrome",
                "--against",
                "silver-925",
                "--tolerances",
                file,
            ])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1), "{out:?}");
        let stderr = String::from_utf8(out.stderr).unwrap();
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(
            stderr.contains(file.as_str()) && stderr.contains(words),
            "{stderr}"
        );
    }
    // Tolerances need a reference to be differences to.
    let out = specula()
        .args(["appearance", "chrome", "--tolerances", &unknown])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
}
