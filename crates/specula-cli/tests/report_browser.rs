//! Reports in a real browser: `specula report` on the journal of a small simulated
//! measurement and on the table it wrote, each opened from disk by headless Chromium; every
//! embedded picture decodes (naturalWidth > 0), a screenshot of the page is taken and
//! checked, and the embedded interactive viewer passes its self-test.
//!
//! Needs the Debian package `chromium` (CI installs it in `.ci/install-extras`). Without it the
//! test is skipped with a message, except under CI (`CI` set), where it fails.
//! SPECULA_KEEP_SCREENSHOT=PREFIX keeps the screenshots as PREFIX-NAME.png.

mod chromium;
mod common;

use chromium::{
    attribute, chromium_or_skip, file_url, run_chromium, viewer_self_test, MAX_READY_MS,
};
use common::{measure_small, report};
use std::path::Path;

/// Opens `page` in headless Chromium (profiles under `work`): every picture must decode, a
/// screenshot of the page must be of the requested size and not blank, and the embedded
/// viewer must draw both BRDFs (the table and the truth) without a script error.
fn check_in_chromium(chromium: &Path, page: &Path, work: &Path, uncertainties: usize) {
    let html = std::fs::read_to_string(page).unwrap();
    let pictures = html.matches("<img ").count();

    // A copy of the page with a probe script that records, once everything has loaded, how
    // many pictures decoded; --dump-dom prints the DOM with the record.
    let script = "<script>window.addEventListener('load',()=>{const i=[...document.images];\
        document.body.setAttribute('data-images',i.length);\
        document.body.setAttribute('data-loaded',i.filter(x=>x.complete&&x.naturalWidth>0).length);});</script>";
    let probed = work.join("probed.html");
    std::fs::write(
        &probed,
        html.replace("</body>", &format!("{script}</body>")),
    )
    .unwrap();
    let (dom, _) = run_chromium(
        chromium,
        &work.join("profile-a"),
        &["--dump-dom".into(), VIRTUAL_TIME.into()],
        &file_url(&probed, ""),
    );
    assert_eq!(attribute(&dom, "data-images"), pictures);
    assert_eq!(
        attribute(&dom, "data-loaded"),
        pictures,
        "some pictures of {} did not load",
        page.display()
    );

    // A screenshot of the unmodified page: a picture of the requested size, not blank.
    let shot = work.join("screenshot.png");
    run_chromium(
        chromium,
        &work.join("profile-b"),
        &[
            format!("--screenshot={}", shot.display()),
            "--window-size=1200,1800".into(),
            VIRTUAL_TIME.into(),
        ],
        &file_url(page, ""),
    );
    let image = image::open(&shot)
        .expect("a screenshot was written")
        .into_rgb8();
    assert_eq!(image.dimensions(), (1200, 1800));
    let distinct: std::collections::HashSet<[u8; 3]> = image.pixels().map(|p| p.0).collect();
    assert!(
        distinct.len() > 500,
        "the screenshot of {} looks blank: {} colours",
        page.display(),
        distinct.len()
    );
    let viewer = viewer_self_test(chromium, page, work);
    assert_eq!(viewer.tables, 2, "the table and its truth: {viewer:?}");
    assert!(
        viewer
            .canvases
            .iter()
            .all(|&(_, colours, changed)| colours > 20 && changed),
        "the report's viewer is blank or does not move: {viewer:?}"
    );
    assert_eq!(viewer.readouts, 3, "a readout on each drawing: {viewer:?}");
    assert_eq!(
        viewer.readout_origins, 3,
        "the measured table's cells say where they come from: {viewer:?}"
    );
    assert_eq!(
        viewer.readout_uncertainties, uncertainties,
        "readouts that give the cell's uncertainty: {viewer:?}"
    );
    assert!(
        viewer.ready_ms <= MAX_READY_MS,
        "the report's viewer is interactive after {} ms",
        viewer.ready_ms
    );
    if let Some(keep) = std::env::var_os("SPECULA_KEEP_SCREENSHOT") {
        let name = page.file_stem().unwrap().to_string_lossy();
        std::fs::copy(&shot, format!("{}-{name}.png", keep.to_string_lossy())).unwrap();
    }
}

/// Lets the page's timers and pictures settle before the DOM or the screenshot is taken.
const VIRTUAL_TIME: &str = "--virtual-time-budget=10000";

#[test]
fn session_and_table_reports_open_in_chromium_with_every_picture() {
    let Some(chromium) = chromium_or_skip() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let (session, table) = measure_small(dir.path(), None);
    // Both show the uncertainty `measure` wrote beside the table: the session's report, which
    // reconstructs its table from the journal, reads it beside the session's out path.
    let reports: [(&Path, &[&str], usize, &str, usize); 2] = [
        (
            &session,
            &[],
            8,
            "renders x 2, slices x 3 (measured, truth, difference), relative uncertainty, probe, raw samples",
            3,
        ),
        (
            &table,
            &["--truth", "silver-925"],
            7,
            "renders x 2, slices x 3 (measured, truth, difference), relative uncertainty, probe",
            3,
        ),
    ];
    for (input, extra, expected, what, uncertainties) in reports {
        let name = input.file_stem().unwrap().to_string_lossy();
        let page = dir.path().join(format!("{name}.html"));
        let output = report(input, &page, 96, extra);
        assert!(
            output.status.success(),
            "report of {} failed: {}",
            input.display(),
            String::from_utf8_lossy(&output.stderr)
        );
        let html = std::fs::read_to_string(&page).unwrap();
        assert_eq!(html.matches("<img ").count(), expected, "{what}");
        let work = dir.path().join(format!("{name}-chromium"));
        std::fs::create_dir_all(&work).unwrap();
        check_in_chromium(&chromium, &page, &work, uncertainties);
    }
    // Without the sidecar the session's report says so and shows no map.
    let sidecar = specula_reconstruct::uncertainty::sidecar_path(&table);
    std::fs::remove_file(&sidecar).unwrap();
    let page = dir.path().join("without.html");
    let output = report(&session, &page, 96, &[]);
    assert!(output.status.success(), "{output:?}");
    let html = std::fs::read_to_string(&page).unwrap();
    assert_eq!(html.matches("<img ").count(), 7, "no relative uncertainty");
    assert!(html.contains("none: no"), "the report says there is none");
    assert!(!html.contains("relative uncertainty"));
}
