//! `specula view` in a real browser: the page of two MERL-size tables (one with a provenance
//! and an uncertainty sidecar), opened from disk by headless Chromium, runs its self-test
//! (`view.html#selftest`): no script error, every drawing (polar plot, slice, sphere) not
//! blank, each changes when its slider or the light moves, and the pointer on each gives a
//! readout of f_r with the cell's origin and uncertainty; the page is interactive within 2 s,
//! holds no `http` source or link and weighs at most 5 MB.
//!
//! Needs the Debian package `chromium` (CI installs it in `.ci/install-extras`). Without it the
//! test is skipped with a message, except under CI (`CI` set), where it fails.

mod chromium;

use assert_cmd::Command;
use chromium::{chromium_or_skip, viewer_self_test, MAX_READY_MS};
use specula_reconstruct::provenance::{CellOrigin, Provenance};

/// The target: the page of two MERL-size sources weighs at most this, bytes.
const MAX_PAGE_BYTES: usize = 5_000_000;

fn specula(dir: &std::path::Path, args: &[&str]) {
    let output = Command::cargo_bin("specula")
        .unwrap()
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "specula {args:?} failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
}

#[test]
fn the_viewer_page_draws_moves_and_stays_offline_in_chromium() {
    let Some(chromium) = chromium_or_skip() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    specula(
        dir.path(),
        &["tabulate", "silver-925", "--out", "silver.binary"],
    );
    specula(
        dir.path(),
        &["tabulate", "chrome", "--out", "chrome.binary"],
    );
    let cells = (0..specula_core::merl::CELLS)
        .map(|i| match i % 3 {
            0 => CellOrigin::Measured,
            1 => CellOrigin::Interpolated,
            _ => CellOrigin::Extrapolated,
        })
        .collect();
    Provenance { cells }
        .write(&dir.path().join("silver.provenance.npy"))
        .unwrap();
    // An uncertainty sidecar (any MERL table will do for the page).
    std::fs::copy(
        dir.path().join("chrome.binary"),
        dir.path().join("silver.uncertainty.binary"),
    )
    .unwrap();
    specula(
        dir.path(),
        &[
            "view",
            "silver.binary",
            "chrome.binary",
            "--out",
            "view.html",
        ],
    );

    let page = dir.path().join("view.html");
    let html = std::fs::read_to_string(&page).unwrap();
    assert!(
        html.len() <= MAX_PAGE_BYTES,
        "the page weighs {} bytes",
        html.len()
    );
    // No address to fetch: the base64 data may spell "http" by chance, never "http:".
    let lower = html.to_ascii_lowercase();
    assert!(
        !lower.contains("http:") && !lower.contains("https:"),
        "the page names an http address"
    );
    assert_eq!(
        html.matches("\"origins\":\"").count(),
        1,
        "silver's sidecar"
    );

    let result = viewer_self_test(&chromium, &page, dir.path());
    eprintln!("viewer self-test: {result:?}");
    assert_eq!(result.tables, 2);
    for (canvas, colours, changed) in &result.canvases {
        assert!(*colours > 20, "the {canvas} looks blank: {colours} colours");
        assert!(changed, "moving the {canvas}'s control did not change it");
    }
    assert_eq!(
        result.readouts, 3,
        "a readout under the pointer on each drawing"
    );
    assert_eq!(
        result.readout_origins, 3,
        "silver's cells say where they come from"
    );
    assert_eq!(
        result.readout_uncertainties, 3,
        "silver's sidecar gives its uncertainty"
    );
    assert!(
        result.ready_ms <= MAX_READY_MS,
        "interactive after {} ms",
        result.ready_ms
    );
}
