//! Headless Chromium for the browser tests (the Debian package `chromium`; CI installs it in
//! `.ci/install-extras`): finding it, opening a page from disk, reading what the page wrote
//! into its DOM, and the viewer's self-test (`PAGE#selftest`, see
//! `specula_visual::viewer`).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

/// The target: a page with the viewer is drawn and interactive this soon after it starts
/// loading, ms.
pub(crate) const MAX_READY_MS: usize = 2000;

/// The Chromium binary, if installed; without it under CI (`CI` set) the test fails, else
/// it is skipped with a message (`None`).
pub(crate) fn chromium_or_skip() -> Option<PathBuf> {
    let found = ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .find_map(|name| {
            let out = Command::new("which").arg(name).output().ok()?;
            out.status
                .success()
                .then(|| PathBuf::from(String::from_utf8_lossy(&out.stdout).trim().to_string()))
        });
    if found.is_none() {
        assert!(
            std::env::var_os("CI").is_none(),
            "chromium is not installed on CI: .ci/install-extras must install it"
        );
        eprintln!("SKIPPED: chromium is not installed (apt-get install chromium chromium-driver)");
    }
    found
}

/// Runs headless Chromium on `url` (a page from disk, optionally with a `#fragment`) with
/// extra arguments and a fresh profile in `profile`; returns stdout and the wall time.
pub(crate) fn run_chromium(
    chromium: &Path,
    profile: &Path,
    args: &[String],
    url: &str,
) -> (String, Duration) {
    let start = Instant::now();
    let output = Command::new("timeout")
        .arg("120")
        .arg(chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-dev-shm-usage",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            "--hide-scrollbars",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(args)
        .arg(url)
        .output()
        .expect("chromium runs");
    assert!(
        output.status.success(),
        "chromium failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    (
        String::from_utf8_lossy(&output.stdout).into_owned(),
        start.elapsed(),
    )
}

/// The `file://` address of a page, with `fragment` (`#...`) appended.
pub(crate) fn file_url(page: &Path, fragment: &str) -> String {
    format!("file://{}{fragment}", page.display())
}

/// The value of a numeric attribute in a dumped DOM (its first occurrence).
pub(crate) fn attribute(dom: &str, name: &str) -> usize {
    let at = dom
        .find(&format!("{name}=\""))
        .unwrap_or_else(|| panic!("no {name} in the DOM"));
    let rest = &dom[at + name.len() + 2..];
    rest[..rest.find('"').expect("a closing quote")]
        .parse()
        .unwrap_or_else(|_| panic!("{name} is not a number"))
}

/// What the viewer's self-test recorded.
#[derive(Debug)]
pub(crate) struct SelfTest {
    /// BRDFs shown.
    pub(crate) tables: usize,
    /// Milliseconds from navigation start until the viewer was drawn and interactive.
    pub(crate) ready_ms: usize,
    /// Drawings (of the polar plot, the first slice and the first sphere) whose middle gave
    /// a readout of f_r under the pointer ...
    pub(crate) readouts: usize,
    /// ... and of those, readouts naming the cell's origin (measured, interpolated, ...).
    pub(crate) readout_origins: usize,
    /// ... and readouts giving the cell's uncertainty.
    pub(crate) readout_uncertainties: usize,
    /// Per canvas (polar, slice, sphere): distinct colours before the sliders moved, and
    /// whether moving them changed the drawing.
    pub(crate) canvases: Vec<(&'static str, usize, bool)>,
}

/// Opens `page#selftest` in Chromium (profile under `work`) and reads the viewer's record.
pub(crate) fn viewer_self_test(chromium: &Path, page: &Path, work: &Path) -> SelfTest {
    let (dom, _) = run_chromium(
        chromium,
        &work.join("profile-selftest"),
        &["--dump-dom".into()],
        &file_url(page, "#selftest"),
    );
    let at = dom
        .find("id=\"sv-selftest\"")
        .unwrap_or_else(|| panic!("{}: no viewer in the page", page.display()));
    let record = &dom[at..at + dom[at..].find('>').expect("the element closes")];
    assert_eq!(
        attribute(record, "data-errors"),
        0,
        "script errors in {}: {}",
        page.display(),
        &dom[at..at + dom[at..].find("</div>").unwrap_or(0)]
    );
    SelfTest {
        tables: attribute(record, "data-tables"),
        ready_ms: attribute(record, "data-ready-ms"),
        readouts: attribute(record, "data-readouts"),
        readout_origins: attribute(record, "data-readout-origins"),
        readout_uncertainties: attribute(record, "data-readout-uncertainties"),
        canvases: ["polar", "slice", "sphere"]
            .into_iter()
            .map(|name| {
                (
                    name,
                    attribute(record, &format!("data-{name}-colours")),
                    attribute(record, &format!("data-{name}-changed")) == 1,
                )
            })
            .collect(),
    }
}
