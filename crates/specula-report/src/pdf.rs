//! The report as a PDF: the HTML page printed by headless Chromium, the engine the page is
//! checked in, so that the PDF shows the same figures and pictures as the page.

use crate::error::ReportError;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Names under which Chromium is installed.
const CHROMIUM_NAMES: [&str; 3] = ["chromium", "chromium-browser", "google-chrome"];

/// The first Chromium on `PATH`.
fn chromium() -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .flat_map(|dir| CHROMIUM_NAMES.map(|name| dir.join(name)))
        .find(|candidate| candidate.is_file())
}

/// Prints `html` to the PDF file `out` with headless Chromium (written whole or not at all).
pub(crate) fn print(html: &str, out: &Path) -> Result<(), ReportError> {
    let chromium = chromium().ok_or_else(|| ReportError::NoChromium(out.to_path_buf()))?;
    let failed = |problem: String| ReportError::Pdf {
        path: out.to_path_buf(),
        problem,
    };
    let work = tempfile::tempdir().map_err(|e| failed(format!("no scratch folder: {e}")))?;
    let page = work.path().join("report.html");
    let printed = work.path().join("report.pdf");
    std::fs::write(&page, html).map_err(|e| failed(format!("cannot write the page: {e}")))?;
    let output = Command::new(&chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-dev-shm-usage",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            "--no-pdf-header-footer",
            "--virtual-time-budget=10000",
        ])
        .arg(format!(
            "--user-data-dir={}",
            work.path().join("profile").display()
        ))
        .arg(format!("--print-to-pdf={}", printed.display()))
        .arg(format!("file://{}", page.display()))
        .output()
        .map_err(|e| failed(format!("{} did not run: {e}", chromium.display())))?;
    let pdf = std::fs::read(&printed).unwrap_or_default();
    if !output.status.success() || !pdf.starts_with(b"%PDF") {
        let stderr = String::from_utf8_lossy(&output.stderr);
        let last = stderr.lines().rev().find(|l| !l.trim().is_empty());
        return Err(failed(format!(
            "{} printed no PDF ({}){}",
            chromium.display(),
            output.status,
            last.map(|l| format!(": {}", l.trim())).unwrap_or_default()
        )));
    }
    specula_core::atomic_file::write_bytes(out, &pdf).map_err(|source| ReportError::Write {
        path: out.to_path_buf(),
        source,
    })
}
