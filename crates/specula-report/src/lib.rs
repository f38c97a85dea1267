//! The report layer: one self-contained HTML page about a measured BRDF (a MERL table) or
//! about a measurement session (its journal), assembled from the library crates: the
//! material, k-hat of its probe (paper 5.2), the coverage, renders on a sphere and a
//! speedshape, the characteristic slice (Fig. 11), the probe against the adaptive samples
//! (Fig. 13), the raw samples (Fig. 15) and, with a truth, the error figures.
//!
//! This crate takes a plain [`ReportOptions`] (no argument parser) and reports long work to
//! a [`Progress`]; `specula report` and `specula demo` are thin callers of [`write_report`]
//! and [`write_session_pictures`], `specula view` of [`view::write_view`] (the interactive
//! viewer, which the report embeds too).

pub mod appearance;
mod error;
mod figures;
mod session;
mod table;
pub mod view;

pub use error::ReportError;
pub use specula_visual::report::Report;

use std::path::{Path, PathBuf};
use std::time::Instant;

/// The largest width and height of a render, pixels.
pub const MAX_IMAGE_PX: usize = 8192;

pub use specula_visual::render::MAX_SAMPLES_PER_PIXEL;

/// Adaptive samples the paper places along theta_h with the fitted k (section 5.3).
const PLACED_SAMPLES: usize = specula_core::GridSpec::paper().theta_h_samples;

/// What to report on and how; the fields are `specula report`'s options.
#[derive(Clone, Debug)]
pub struct ReportOptions {
    /// The measured BRDF (a MERL .binary file) or a session journal (.sqlite).
    pub input: PathBuf,
    /// The true BRDF, when known (a simulation): a preset, .toml, .binary or model:name
    /// (as `specula_formats::load_brdf` reads it).
    pub truth: Option<String>,
    /// The raw samples of the measurement (CSV theta_h,phi_h,theta_d,phi_d,r,g,b); with a
    /// .binary input only (a journal holds its samples).
    pub samples: Option<PathBuf>,
    /// With a session journal: the MERL .binary to show instead of reconstructing the
    /// session's samples.
    pub table: Option<PathBuf>,
    /// Width and height of each render, pixels, in 8..=[`MAX_IMAGE_PX`].
    pub size_px: usize,
    /// Camera rays per pixel of the renders, in 1..=[`MAX_SAMPLES_PER_PIXEL`].
    pub spp: usize,
    /// The report's title (default: the input's material name).
    pub title: Option<String>,
}

impl ReportOptions {
    /// Options for `input` with the command's defaults: 320 x 320 renders at 32 rays per
    /// pixel, no truth, samples, table or title.
    pub fn new(input: impl Into<PathBuf>) -> Self {
        ReportOptions {
            input: input.into(),
            truth: None,
            samples: None,
            table: None,
            size_px: 320,
            spp: 32,
            title: None,
        }
    }
}

/// Where the report's long steps show their progress (a terminal bar in the CLI).
pub trait Progress: Sync {
    /// A step starts: `label`, over `total` units when known (else a spinner).
    fn start(&self, label: &str, total: Option<u64>);
    /// `done` units of the current step are done.
    fn set(&self, done: u64);
    /// The current step is finished.
    fn finish(&self);
}

/// No progress shown (tests, and callers without a terminal).
pub struct NoProgress;

impl Progress for NoProgress {
    fn start(&self, _label: &str, _total: Option<u64>) {}
    fn set(&self, _done: u64) {}
    fn finish(&self) {}
}

/// The kind of input, told by the file's extension.
enum Input {
    Table,
    Session,
}

/// Check the options against the input's kind.
fn check(options: &ReportOptions) -> Result<Input, ReportError> {
    let extension = options
        .input
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let input = match extension.as_deref() {
        Some("binary") => Input::Table,
        Some("sqlite") => Input::Session,
        _ => return Err(ReportError::UnknownInput(options.input.clone())),
    };
    // The message below spells the bounds out in words.
    const _: () = assert!(MAX_IMAGE_PX == 8192 && MAX_SAMPLES_PER_PIXEL == 65536);
    if !(8..=MAX_IMAGE_PX).contains(&options.size_px)
        || !(1..=MAX_SAMPLES_PER_PIXEL).contains(&options.spp)
    {
        return Err(ReportError::Options(
            "--size must be a whole number of pixels from 8 to 8192 and --spp one from 1 to 65536",
        ));
    }
    match input {
        Input::Session if options.samples.is_some() => Err(ReportError::Options(
            "--samples-csv is for a .binary input: a session journal holds its own samples",
        )),
        Input::Table if options.table.is_some() => Err(ReportError::Options(
            "--table is for a session journal input: the .binary input is the table",
        )),
        _ => Ok(input),
    }
}

/// The report of `options.input`: of a MERL table or of a session journal, by extension.
pub fn build_report(
    options: &ReportOptions,
    progress: &dyn Progress,
) -> Result<Report, ReportError> {
    let start = Instant::now();
    let mut report = match check(options)? {
        Input::Session => session::report(options, progress)?,
        Input::Table => table::report(options, progress)?,
    };
    report.notes.push(format!(
        "Report made in {:.1} s from {}.",
        start.elapsed().as_secs_f64(),
        options.input.display()
    ));
    Ok(report)
}

/// Build the report of `options.input` and write it to `out` as one HTML file (pictures
/// embedded, no other file needed).
pub fn write_report(
    options: &ReportOptions,
    out: &Path,
    progress: &dyn Progress,
) -> Result<Report, ReportError> {
    let report = build_report(options, progress)?;
    report.write(out).map_err(ReportError::from_source)?;
    Ok(report)
}

/// The report of the session journal `options.input` written as `dir/report.html`, and each
/// of its figures as a PNG file beside it named after the figure's title
/// (`render_sphere.png`, ...); returns the report and the files written, the page last.
pub fn write_session_pictures(
    options: &ReportOptions,
    dir: &Path,
    progress: &dyn Progress,
) -> Result<(Report, Vec<PathBuf>), ReportError> {
    check(options)?;
    let report = session::report(options, progress)?;
    let mut files = Vec::new();
    for figure in &report.figures {
        let path = dir.join(format!("{}.png", file_stem_of(&figure.title)));
        specula_core::atomic_file::write_bytes(&path, &figure.png).map_err(|source| {
            ReportError::Write {
                path: path.clone(),
                source,
            }
        })?;
        files.push(path);
    }
    let page = dir.join("report.html");
    report.write(&page).map_err(ReportError::from_source)?;
    files.push(page);
    Ok((report, files))
}

/// A figure's title as a file name: lower case, words joined by `_`.
fn file_stem_of(title: &str) -> String {
    title
        .split(|c: char| !c.is_ascii_alphanumeric())
        .filter(|word| !word.is_empty())
        .map(str::to_ascii_lowercase)
        .collect::<Vec<_>>()
        .join("_")
}

/// Who made the report.
fn generator() -> String {
    format!("specula {}", env!("CARGO_PKG_VERSION"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::tabulate::tabulate;

    /// The error and its causes, as the CLI prints them.
    fn chain(error: &dyn std::error::Error) -> String {
        let mut text = error.to_string();
        let mut cause = error.source();
        while let Some(e) = cause {
            text.push_str(&format!(": {e}"));
            cause = e.source();
        }
        text
    }

    #[test]
    fn a_report_of_a_binary_has_every_section() {
        let dir = tempfile::tempdir().unwrap();
        let binary = dir.path().join("steel.binary");
        let truth = specula_formats::load_brdf("steel").unwrap();
        tabulate(truth.as_ref(), 0.0).write(&binary).unwrap();
        let samples = dir.path().join("raw.csv");
        std::fs::write(
            &samples,
            "theta_h,phi_h,theta_d,phi_d,r,g,b\n0.1,45,10,0,5,5,5\n2,45,10,0,1,1,1\n0.1,45,40,0,4,4,4\n",
        )
        .unwrap();
        let out = dir.path().join("report.html");
        let options = ReportOptions {
            truth: Some("steel".into()),
            samples: Some(samples),
            size_px: 16,
            spp: 1,
            ..ReportOptions::new(binary)
        };
        write_report(&options, &out, &NoProgress).unwrap();
        let html = std::fs::read_to_string(&out).unwrap();
        for text in [
            "BRDF report: steel",
            "k-hat</th><td>",
            "1458000 of 1458000 (100.0 %)",
            "planned cells measured (raw samples)</th><td>3 of 4",
            "Against <b>steel</b>",
            "Render, sphere",
            "Render, speedshape",
            "Characteristic slice of the truth",
            "Characteristic slice of the difference",
            "Probe against the adaptive samples",
            "Raw samples",
        ] {
            assert!(html.contains(text), "missing: {text}");
        }
        // A table against itself: no error.
        assert!(html.contains("<td class=\"num\">0.0000</td>"));
        assert_eq!(html.matches("data:image/png;base64,").count(), 7);
    }

    #[test]
    fn other_inputs_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let options = |input: &str| ReportOptions {
            size_px: 16,
            spp: 1,
            ..ReportOptions::new(dir.path().join(input))
        };
        let out = dir.path().join("r.html");
        let error =
            |options: ReportOptions| chain(&write_report(&options, &out, &NoProgress).unwrap_err());
        assert!(error(options("missing.sqlite")).contains("missing.sqlite"));
        assert!(
            error(options("x.csv")).contains("x.csv: expected a MERL .binary file or a session")
        );
        assert!(error(options("missing.binary")).contains("missing.binary"));
        let with_table = ReportOptions {
            table: Some(dir.path().join("t.binary")),
            ..options("m.binary")
        };
        assert!(error(with_table).contains("--table is for a session journal"));
    }

    #[test]
    fn figure_titles_become_file_names() {
        assert_eq!(file_stem_of("Render, sphere"), "render_sphere");
        assert_eq!(
            file_stem_of("Probe against the adaptive samples"),
            "probe_against_the_adaptive_samples"
        );
    }
}
