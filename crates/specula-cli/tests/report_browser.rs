//! Reports in a real browser: `specula report` on the journal of a small simulated
//! measurement and on the table it wrote, each opened from disk by headless Chromium; every
//! embedded picture decodes (naturalWidth > 0), and a screenshot of the page is taken and
//! checked.
//!
//! Needs the Debian package `chromium` (CI installs it in `.ci/install-extras`). Without it the
//! test is skipped with a message, except under CI (`CI` set), where it fails.
//! SPECULA_KEEP_SCREENSHOT=PREFIX keeps the screenshots as PREFIX-NAME.png.

mod common;

use common::{measure_small, report};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The Chromium binary, if installed.
fn chromium() -> Option<PathBuf> {
    ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .find_map(|name| {
            let out = Command::new("which").arg(name).output().ok()?;
            out.status
                .success()
                .then(|| PathBuf::from(String::from_utf8_lossy(&out.stdout).trim().to_string()))
        })
}

/// Runs headless Chromium on `page` with extra arguments; returns stdout.
fn run_chromium(chromium: &Path, profile: &Path, args: &[String], page: &Path) -> String {
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
            "--virtual-time-budget=10000",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(args)
        .arg(format!("file://{}", page.display()))
        .output()
        .expect("chromium runs");
    assert!(
        output.status.success(),
        "chromium failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// The value of a numeric attribute in a dumped DOM.
fn attribute(dom: &str, name: &str) -> usize {
    let at = dom
        .find(&format!("{name}=\""))
        .unwrap_or_else(|| panic!("no {name} in the DOM"));
    let rest = &dom[at + name.len() + 2..];
    rest[..rest.find('"').expect("a closing quote")]
        .parse()
        .expect("a number")
}

/// Opens `page` in headless Chromium twice (profiles under `work`): every picture must
/// decode, and a screenshot of the page must be of the requested size and not blank.
fn check_in_chromium(chromium: &Path, page: &Path, work: &Path) {
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
    let dom = run_chromium(
        chromium,
        &work.join("profile-a"),
        &["--dump-dom".into()],
        &probed,
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
        ],
        page,
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
    if let Some(keep) = std::env::var_os("SPECULA_KEEP_SCREENSHOT") {
        let name = page.file_stem().unwrap().to_string_lossy();
        std::fs::copy(&shot, format!("{}-{name}.png", keep.to_string_lossy())).unwrap();
    }
}

#[test]
fn session_and_table_reports_open_in_chromium_with_every_picture() {
    let Some(chromium) = chromium() else {
        assert!(
            std::env::var_os("CI").is_none(),
            "chromium is not installed on CI: .ci/install-extras must install it"
        );
        eprintln!("SKIPPED: chromium is not installed (apt-get install chromium chromium-driver)");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let (session, table) = measure_small(dir.path(), None);
    let reports: [(&Path, &[&str], usize, &str); 2] = [
        (
            &session,
            &[],
            7,
            "renders x 2, slices x 3 (measured, truth, difference), probe, raw samples",
        ),
        (
            &table,
            &["--truth", "silver-925"],
            6,
            "renders x 2, slices x 3 (measured, truth, difference), probe",
        ),
    ];
    for (input, extra, expected, what) in reports {
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
        check_in_chromium(&chromium, &page, &work);
    }
}
