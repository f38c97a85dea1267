//! `specula report` as a PDF for a customer: a measured RGL file against chrome, printed by
//! headless Chromium, read back with `pdftotext` (poppler-utils): the sample ID and the
//! operator are on it and the word "truth" is not; any extension but .html or .pdf is
//! refused.
//!
//! Needs `chromium` and `pdftotext` (CI installs both in `.ci/install-extras`) and the RGL
//! files in `../shared/data/measured/rgl_bsdf`; without them the test is skipped with a
//! message, except under CI (`CI` set), where missing programs fail it.

use assert_cmd::Command;
use std::path::{Path, PathBuf};

/// The program `name` on PATH.
fn installed(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|dir| dir.join(name))
        .find(|p| p.is_file())
}

/// A measured RGL file of the shared data, when present.
fn rgl_file() -> Option<PathBuf> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/data/measured/rgl_bsdf/paper_white_rgb.bsdf");
    path.is_file().then_some(path)
}

#[test]
fn a_pdf_report_of_a_bsdf_shows_the_sample_and_never_truth() {
    let tools = (installed("chromium"), installed("pdftotext"));
    let (Some(_), Some(pdftotext)) = tools else {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI must have chromium and pdftotext (.ci/install-extras)"
        );
        eprintln!("skipping: chromium or pdftotext is not installed");
        return;
    };
    let Some(bsdf) = rgl_file() else {
        eprintln!("skipping: ../shared/data/measured/rgl_bsdf is absent");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let pdf = dir.path().join("r.pdf");
    let out = Command::cargo_bin("specula")
        .unwrap()
        .arg("report")
        .arg(&bsdf)
        .args([
            "--against",
            "chrome",
            "--sample-id",
            "QC-2026-0417",
            "--operator",
            "Dana Whitfield",
            "--size",
            "32",
            "--spp",
            "1",
            "--out",
        ])
        .arg(&pdf)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let bytes = std::fs::read(&pdf).unwrap();
    assert!(bytes.starts_with(b"%PDF"), "not a PDF");
    let text = std::process::Command::new(pdftotext)
        .arg(&pdf)
        .arg("-")
        .output()
        .unwrap();
    assert!(text.status.success());
    let text = String::from_utf8_lossy(&text.stdout);
    for shown in [
        "QC-2026-0417",
        "Dana Whitfield",
        "chrome (reference)",
        "gloss 20",
    ] {
        assert!(text.contains(shown), "the PDF lacks {shown}:\n{text}");
    }
    assert!(!text.to_lowercase().contains("truth"), "{text}");

    let docx = dir.path().join("r.docx");
    let out = Command::cargo_bin("specula")
        .unwrap()
        .arg("report")
        .arg(&bsdf)
        .arg("--out")
        .arg(&docx)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1), "{out:?}");
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(
        stderr.contains("r.docx") && stderr.contains(".html or .pdf"),
        "{stderr}"
    );
    assert!(!docx.exists());
}
