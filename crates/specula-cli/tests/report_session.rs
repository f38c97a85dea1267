//! `specula report SESSION.sqlite`: the report of a measurement session, checked against what
//! the journal and the measured table say when read here independently; an interrupted
//! session still reports; a file that is not a journal gets a one-line error; `specula view`
//! shows the table a session's report shows.

mod common;

use common::{measure_small, report};
use specula_core::compare::compare;
use specula_core::materials::preset;
use specula_core::tabulate::tabulate;
use specula_core::MerlBrdf;
use specula_session::journal::Journal;
use specula_session::workflow::FitRecord;
use specula_session::Stage;
use specula_visual::report::duration_text;
use std::path::Path;
use std::process::Output;

/// Renders this small keep the tests quick.
const SIZE_PX: usize = 16;

/// The report page; the run must have succeeded.
fn page(output: &Output, out: &Path) -> String {
    assert!(
        output.status.success(),
        "report failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    std::fs::read_to_string(out).expect("the report was written")
}

fn assert_contains(html: &str, texts: &[String]) {
    for text in texts {
        assert!(html.contains(text.as_str()), "missing: {text}");
    }
}

/// (measured, planned) samples of a stage, from the journal.
fn counts(journal: &Journal, stage: Stage) -> (usize, usize) {
    (
        journal.samples(stage).unwrap().len(),
        journal.plan(stage).unwrap().len(),
    )
}

/// The device time the journal records for a session without checks, and the time model's
/// estimate of its plans, seconds.
fn device_and_predicted_s(journal: &Journal) -> (f64, f64) {
    let mut device_s = 0.0;
    let mut predicted_s = 0.0;
    for stage in [Stage::Probe, Stage::Main] {
        device_s += journal
            .samples(stage)
            .unwrap()
            .values()
            .map(|s| s.device_s)
            .sum::<f64>();
        predicted_s += journal
            .plan(stage)
            .unwrap()
            .iter()
            .map(|r| r.predicted_s)
            .sum::<f64>();
    }
    (device_s, predicted_s)
}

/// The error row of the report's 75-degree set for a table against silver-925.
fn error_row(table: &MerlBrdf) -> String {
    let truth = preset("silver-925").unwrap();
    let e = compare(table, &tabulate(&truth, 0.0), 75.0);
    format!(
        "<tr><td>light and camera within 75 deg</td><td class=\"num\">{}</td><td class=\"num\">{:.4}</td><td class=\"num\">{:.4}</td>",
        e.cells, e.relative_rmse, e.log_rmse
    )
}

#[test]
fn a_complete_session_reports_k_hat_coverage_duration_errors_and_figures() {
    let dir = tempfile::tempdir().unwrap();
    let (session, table) = measure_small(dir.path(), None);
    let out = dir.path().join("report.html");
    let html = page(&report(&session, &out, SIZE_PX, &[]), &out);

    let journal = Journal::open_read_only(&session).unwrap();
    let fit: FitRecord = journal.meta("fit").unwrap().expect("a fit");
    let (probe_done, probe_planned) = counts(&journal, Stage::Probe);
    let (main_done, main_planned) = counts(&journal, Stage::Main);
    assert_eq!(main_done, main_planned, "the session is complete");
    let (device_s, predicted_s) = device_and_predicted_s(&journal);
    assert!(
        device_s > 120.0 && predicted_s > device_s,
        "{device_s} {predicted_s}"
    );
    let measured = MerlBrdf::read(&table).unwrap();
    assert_contains(
        &html,
        &[
            "Session report: silver-925".into(),
            // The date is the session's start.
            "<th>date</th><td>".into(),
            "<th>measured</th><td>simulated: silver-925</td>".into(),
            format!(
                "k-hat</th><td>{:.3} (exponential sampling function, fit error {:.3e} 1/sr; fitted to a probe of {probe_done} samples, places 8 samples along theta_h)",
                fit.function.k, fit.error
            ),
            format!("probe stage: planned samples measured</th><td>{probe_done} of {probe_planned} (100.0 %)"),
            format!("main stage: planned samples measured</th><td>{main_done} of {main_planned} (100.0 %)"),
            format!("<th>duration</th><td>{}</td>", duration_text(device_s)),
            format!("<th>planned duration</th><td>{}</td>", duration_text(predicted_s)),
            format!("reconstructed from the {main_done} main samples with the lobe method"),
            format!(
                "MERL cells holding a value</th><td>{} of 1458000",
                measured.measured_count()
            ),
            "Against <b>silver-925 (truth)</b>".into(),
            // The reconstruction equals the table `measure` wrote.
            error_row(&measured),
            "Render, sphere".into(),
            "Render, speedshape".into(),
            "Characteristic slice of the truth".into(),
            "Characteristic slice of the difference".into(),
            "on the same colour scale".into(),
            format!("the square-root probe of {probe_done} samples"),
            format!("The {main_done} samples of the main stage"),
            // The checks of the deblurred table, per region and over all samples.
            "Checks of the deblurred table".into(),
            "<th>chi-square per value</th>".into(),
            "<td>all</td>".into(),
        ],
    );
    assert!(!html.contains("incomplete"));
    // Renders on two shapes, three slices (measured, truth, difference), the map of the
    // table's relative uncertainty (measure wrote it beside the table), the probe and the raw
    // samples.
    assert_eq!(html.matches("data:image/png;base64,").count(), 8);

    // The same with the written table given, and another truth.
    let out = dir.path().join("table.html");
    let table_arg = table.display().to_string();
    let html = page(
        &report(
            &session,
            &out,
            SIZE_PX,
            &["--table", &table_arg, "--truth", "chrome"],
        ),
        &out,
    );
    assert_contains(
        &html,
        &[
            format!("<th>table</th><td>{table_arg} (--table)</td>"),
            "Against <b>chrome (truth)</b>".into(),
            "cells measured directly</th><td>".into(),
        ],
    );

    // The viewer of the session shows the table its report shows, with its provenance,
    // beside the truth.
    let out = dir.path().join("view.html");
    let html = page(&view(&[&session, Path::new("silver-925")], &out), &out);
    assert_contains(
        &html,
        &[
            "{\"name\":\"silver-925, measured\",\"values\":".into(),
            "{\"name\":\"silver-925\",\"values\":".into(),
        ],
    );
    assert_eq!(html.matches("\"origins\":\"").count(), 1);
}

/// `specula view SOURCES --out OUT`.
fn view(sources: &[&Path], out: &Path) -> Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_specula"))
        .arg("view")
        .args(sources)
        .arg("--out")
        .arg(out)
        .output()
        .expect("specula runs")
}

#[test]
fn an_interrupted_session_reports_what_it_holds() {
    let dir = tempfile::tempdir().unwrap();
    let (session, table) = measure_small(dir.path(), Some((Stage::Main, 20)));
    assert!(!table.exists(), "no table from an interrupted run");
    let journal = Journal::open_read_only(&session).unwrap();
    let (done, planned) = counts(&journal, Stage::Main);
    assert!(done >= 20 && done < planned, "{done} of {planned}");
    let (device_s, predicted_s) = device_and_predicted_s(&journal);
    let out = dir.path().join("report.html");
    let html = page(&report(&session, &out, SIZE_PX, &[]), &out);
    assert_contains(
        &html,
        &[
            format!(
                "This session is incomplete: {done} of {planned} planned samples of the main stage are measured ({:.1} %)",
                100.0 * done as f64 / planned as f64
            ),
            format!("main stage: planned samples measured</th><td>{done} of {planned} ("),
            format!("<th>duration</th><td>{}</td>", duration_text(device_s)),
            format!("<th>planned duration</th><td>{}</td>", duration_text(predicted_s)),
            "k-hat</th><td>".into(),
            "Probe against the adaptive samples".into(),
            format!("The {done} samples of the main stage"),
        ],
    );
}

#[test]
fn a_session_stopped_in_the_probe_reports_without_k_hat() {
    let dir = tempfile::tempdir().unwrap();
    let (session, _) = measure_small(dir.path(), Some((Stage::Probe, 5)));
    let journal = Journal::open_read_only(&session).unwrap();
    let (done, planned) = counts(&journal, Stage::Probe);
    assert!(done >= 5 && done < planned, "{done} of {planned}");
    assert_eq!(counts(&journal, Stage::Main), (0, 0));
    let out = dir.path().join("report.html");
    let html = page(&report(&session, &out, SIZE_PX, &[]), &out);
    assert_contains(
        &html,
        &[
            format!("it stopped in the probe ({done} of {planned} samples measured)"),
            "k-hat</th><td class=\"missing\">not known".into(),
            format!("probe stage: planned samples measured</th><td>{done} of {planned} ("),
            "No table: the main stage has no measured sample yet".into(),
            "No pictures.".into(),
        ],
    );
    // No table, nothing to view: one line naming the journal.
    let output = view(&[&session], &dir.path().join("view.html"));
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains(&format!("{}: No table", session.display())),
        "{stderr}"
    );
}

#[test]
fn files_that_are_not_journals_get_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r.html");
    let fails = |input: &Path, extra: &[&str], needle: &str| {
        let output = report(input, &out, SIZE_PX, extra);
        assert_eq!(output.status.code(), Some(1), "{}", input.display());
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
        assert!(stderr.contains(needle), "{needle}: {stderr}");
    };
    let text = dir.path().join("notes.sqlite");
    std::fs::write(
        &text,
        "these are notes, not a database, and long enough to tell",
    )
    .unwrap();
    fails(&text, &[], "notes.sqlite");
    let empty = dir.path().join("empty.sqlite");
    std::fs::write(&empty, "").unwrap();
    // An empty file is a truncated journal (issue 16, item 8), not a new session.
    fails(&empty, &[], "empty.sqlite: the journal is damaged");
    fails(&dir.path().join("missing.sqlite"), &[], "missing.sqlite");
    fails(
        &empty,
        &["--samples-csv", "raw.csv"],
        "--samples-csv is for a .binary input",
    );
    assert!(!out.exists());
}

/// The figures' warnings (here: flux from cells the small plan's reconstruction
/// extrapolated) come back with the page, for whoever prints the figures elsewhere (`specula
/// demo` prints them under its figure lines), and are the warnings the page shows.
#[test]
fn the_figures_warnings_come_with_the_page_that_shows_them() {
    let dir = tempfile::tempdir().unwrap();
    let (session, table) = measure_small(dir.path(), None);
    let pictures = dir.path().join("pictures");
    std::fs::create_dir(&pictures).unwrap();
    let options = specula_report::ReportRequest {
        truth: Some("silver-925".into()),
        table: Some(table),
        size_px: SIZE_PX,
        spp: 1,
        ..specula_report::ReportRequest::new(&session)
    };
    let (page, files) =
        specula_report::write_session_pictures(&options, &pictures, &specula_report::NoProgress)
            .unwrap();
    let html = std::fs::read_to_string(files.last().unwrap()).unwrap();
    assert!(
        page.warnings
            .iter()
            .any(|w| w.contains("extrapolated cells")),
        "{:?}",
        page.warnings
    );
    for warning in &page.warnings {
        let shown = specula_visual::report::escape(&format!("Warning, {warning}."));
        assert!(html.contains(&shown), "the page lacks {shown}");
    }
}
