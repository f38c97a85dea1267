//! The HTML report in a real browser: headless Chromium opens it from disk, every embedded
//! picture decodes (naturalWidth > 0), and a screenshot of the page is taken and checked.
//!
//! Needs the Debian package `chromium` (CI installs it in `.ci/install-extras`). Without it the
//! test is skipped with a message, except under CI (`CI` set), where it fails.

use glam::DVec3;
use specula_core::materials::presets::preset;
use specula_visual::plot::probe::{interpolate, plot_probe};
use specula_visual::plot::slice::{plot_slice, SliceOptions};
use specula_visual::report::{Figure, KHatSection, MaterialSection, Report};
use specula_visual::{render, Environment, Lighting, RenderSettings, Scene, ShapeKind};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;

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

fn report() -> Report {
    let silver = preset("silver-925").expect("preset");
    let scene = Scene::new(
        ShapeKind::Sphere,
        Lighting::Environment(Arc::new(Environment::studio())),
    );
    let render = render(&silver, &scene, &RenderSettings::square(96, 4), &|_| {});
    let slice = plot_slice(&silver, "silver-925", &SliceOptions::default()).unwrap();
    let probe: Vec<(f64, DVec3)> = (0..90)
        .map(|i| {
            let t = (i as f64).powi(2) / 90.0;
            (
                t,
                DVec3::new(900.0, 800.0, 700.0) * (-2.0 * t).exp() + DVec3::splat(0.05),
            )
        })
        .collect();
    let positions: Vec<f64> = (0..30).map(|i| 90.0 * (i as f64 / 29.0).powi(3)).collect();
    let probe_plot = plot_probe(&probe, &interpolate(&probe, &positions), "probe").unwrap();
    Report {
        title: "Browser check".into(),
        generator: "specula-visual test".into(),
        material: Some(MaterialSection {
            name: "silver-925".into(),
            source: "preset".into(),
            facts: vec![],
        }),
        k_hat: Some(KHatSection {
            family: "exponential".into(),
            k: 4.78,
            fit_error: 0.01,
            probe_samples: 90,
            placed_samples: 30,
        }),
        figures: vec![
            Figure::new("Render", "sphere in the studio", &render.to_display(0.0)).unwrap(),
            Figure::new("Characteristic slice", "phi_d = 90 deg", &slice).unwrap(),
            Figure::new("Probe", "probe against adaptive", &probe_plot).unwrap(),
        ],
        ..Report::default()
    }
}

#[test]
fn report_opens_in_chromium_with_every_picture() {
    let Some(chromium) = chromium() else {
        assert!(
            std::env::var_os("CI").is_none(),
            "chromium is not installed on CI: .ci/install-extras must install it"
        );
        eprintln!("SKIPPED: chromium is not installed (apt-get install chromium chromium-driver)");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let report = report();
    let page = dir.path().join("report.html");
    report.write(&page).unwrap();

    // A copy of the page with a probe script that records, once everything has loaded, how
    // many pictures decoded; --dump-dom prints the DOM with the record.
    let html = std::fs::read_to_string(&page).unwrap();
    let script = "<script>window.addEventListener('load',()=>{const i=[...document.images];\
        document.body.setAttribute('data-images',i.length);\
        document.body.setAttribute('data-loaded',i.filter(x=>x.complete&&x.naturalWidth>0).length);});</script>";
    let probed = dir.path().join("probed.html");
    std::fs::write(
        &probed,
        html.replace("</body>", &format!("{script}</body>")),
    )
    .unwrap();
    let dom = run_chromium(
        &chromium,
        &dir.path().join("profile-a"),
        &["--dump-dom".into()],
        &probed,
    );
    let attribute = |name: &str| -> usize {
        let at = dom
            .find(&format!("{name}=\""))
            .unwrap_or_else(|| panic!("no {name} in the DOM"));
        let rest = &dom[at + name.len() + 2..];
        rest[..rest.find('"').unwrap()].parse().unwrap()
    };
    assert_eq!(attribute("data-images"), report.figures.len());
    assert_eq!(
        attribute("data-loaded"),
        report.figures.len(),
        "some pictures did not load"
    );

    // A screenshot of the unmodified page: a picture of the requested size, not blank.
    let shot = dir.path().join("screenshot.png");
    run_chromium(
        &chromium,
        &dir.path().join("profile-b"),
        &[
            format!("--screenshot={}", shot.display()),
            "--window-size=1200,1800".into(),
        ],
        &page,
    );
    let image = image::open(&shot)
        .expect("a screenshot was written")
        .into_rgb8();
    assert_eq!(image.dimensions(), (1200, 1800));
    let distinct: std::collections::HashSet<[u8; 3]> = image.pixels().map(|p| p.0).collect();
    assert!(
        distinct.len() > 500,
        "the screenshot looks blank: {} colours",
        distinct.len()
    );
    if let Some(keep) = std::env::var_os("SPECULA_KEEP_SCREENSHOT") {
        std::fs::copy(&shot, keep).unwrap();
    }
}
