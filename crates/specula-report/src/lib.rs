//! The report layer: one self-contained HTML page about a measured BRDF (a MERL table) or
//! about a measurement session (its journal), assembled from the library crates: the
//! material, k-hat of its probe (paper 5.2), the coverage, renders on a sphere and a
//! speedshape, the characteristic slice (Fig. 11), the probe against the adaptive samples
//! (Fig. 13), the raw samples (Fig. 15) and, with a truth, the error figures.
//!
//! This crate takes a plain [`ReportRequest`] (no argument parser) and reports long work to
//! a [`Progress`]; `specula report` and `specula demo` are thin callers of [`run_report`]
//! and [`write_session_pictures`], `specula view` of [`view::write_view`] (the interactive
//! viewer, which the report embeds too).

pub mod appearance;
mod appearance_request;
mod database;
mod error;
mod figures;
mod pdf;
mod plot;
mod session;
mod source_info;
mod table;
pub mod view;
mod viewer;

pub use appearance_request::{
    run_appearance, AppearanceInput, AppearanceRequest, AppearanceRow, AppearanceTable,
};
pub use database::DatabaseRequest;
pub use error::ReportError;
pub use plot::{database_heatmap, plot, Adaptive, Figure, PlotRequest, Plotted};
pub use source_info::describe_source;
pub use specula_appearance::Verdict;
use specula_visual::report::Layout;
pub use specula_visual::report::Report;

use std::path::{Path, PathBuf};
use std::time::Instant;

use specula_visual::render::{IMAGE_PX, SAMPLES_PER_PIXEL};
pub use specula_visual::render::{MAX_IMAGE_PX, MAX_SAMPLES_PER_PIXEL};

/// Adaptive samples the paper places along theta_h with the fitted k (section 5.3).
const PLACED_SAMPLES: usize = specula_core::GridSpec::paper().theta_h_samples;

/// Whom a report is for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Audience {
    /// The customer: the sample, the figures and verdicts, the pictures.
    Customer,
    /// The engineer: every section (k-hat, coverage, duration, error figures, slices,
    /// probe).
    #[default]
    Engineering,
}

impl std::str::FromStr for Audience {
    type Err = String;

    /// `customer` or `engineering`.
    fn from_str(text: &str) -> Result<Self, String> {
        match text {
            "customer" => Ok(Audience::Customer),
            "engineering" => Ok(Audience::Engineering),
            _ => Err(format!(
                "unknown audience `{text}` (customer or engineering)"
            )),
        }
    }
}

impl std::fmt::Display for Audience {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Audience::Customer => "customer",
            Audience::Engineering => "engineering",
        })
    }
}

/// Who the sample is and who measured it, for the report's first page.
#[derive(Clone, Debug, Default)]
pub struct SampleInfo {
    /// The sample's identifier.
    pub sample_id: Option<String>,
    /// Who measured it.
    pub operator: Option<String>,
    /// For whom.
    pub customer: Option<String>,
}

/// What to report on and how; the fields are `specula report`'s options.
#[derive(Clone, Debug)]
pub struct ReportRequest {
    /// What to report on: a session journal (.sqlite) or any BRDF source
    /// (`specula_formats::load_brdf`'s: a MERL .binary, RGL .bsdf, material .toml, preset,
    /// fit, ...).
    pub input: PathBuf,
    /// A reference BRDF to compare the figures with (labelled "reference").
    pub against: Option<String>,
    /// A tolerance file: a verdict on the figures' differences to the reference.
    pub tolerances: Option<PathBuf>,
    /// The sample, operator and customer shown on the first page.
    pub sample: SampleInfo,
    /// Whom the report is for.
    pub audience: Audience,
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

impl ReportRequest {
    /// Checks the renders' size and rays per pixel against their ranges (the errors name
    /// the Python arguments `size` and `spp`; the CLI's parsers say the same words after
    /// `--size` and `--spp`).
    pub fn validate(&self) -> Result<(), ReportError> {
        IMAGE_PX.check("size", self.size_px)?;
        SAMPLES_PER_PIXEL.check("spp", self.spp)?;
        Ok(())
    }

    /// Options for `input` with the command's defaults: 320 x 320 renders at 32 rays per
    /// pixel, the engineering audience, no reference, tolerances, sample facts, truth,
    /// samples, table or title.
    pub fn new(input: impl Into<PathBuf>) -> Self {
        ReportRequest {
            input: input.into(),
            against: None,
            tolerances: None,
            sample: SampleInfo::default(),
            audience: Audience::Engineering,
            truth: None,
            samples: None,
            table: None,
            size_px: 320,
            spp: 32,
            title: None,
        }
    }
}

/// Where the report's long steps show their progress, and the quiet default: core's, as
/// every long library entry reports to.
pub use specula_core::progress::{NoProgress, Progress};

/// The kind of input, told by the file's extension: a session journal, or a BRDF source.
enum Input {
    Source,
    Session,
}

/// Check the options against the input's kind.
fn check(options: &ReportRequest) -> Result<Input, ReportError> {
    let extension = options
        .input
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let input = match extension.as_deref() {
        Some("sqlite") => Input::Session,
        _ => Input::Source,
    };
    options.validate()?;
    match input {
        Input::Session if options.samples.is_some() => Err(ReportError::Options(
            "--samples-csv is for a .binary input: a session journal holds its own samples",
        )),
        Input::Source if options.table.is_some() => Err(ReportError::Options(
            "--table is for a session journal input: a BRDF input is the table",
        )),
        _ if options.tolerances.is_some() && options.against.is_none() => Err(
            ReportError::Options("--tolerances needs --against: a reference to judge against"),
        ),
        _ => Ok(input),
    }
}

/// A report and the verdict on its sample (with tolerances).
#[derive(Debug, Clone)]
pub struct Page {
    /// The report.
    pub report: Report,
    /// The verdict of the tolerances on the sample's figures, when tolerances were given.
    pub verdict: Option<Verdict>,
    /// The appearance figures' warnings (extrapolated or unmeasured cells, angles finer
    /// than the instrument resolves), each naming its BRDF; the page shows them too.
    pub warnings: Vec<String>,
}

/// The report of `options.input`: of a session journal or of a BRDF source, by extension.
pub fn build_report(options: &ReportRequest, progress: &dyn Progress) -> Result<Page, ReportError> {
    let start = Instant::now();
    let mut page = match check(options)? {
        Input::Session => session::report(options, progress)?,
        Input::Source => table::report(options, progress)?,
    };
    page.report.notes.push(format!(
        "Report made in {:.1} s from {}.",
        start.elapsed().as_secs_f64(),
        options.input.display()
    ));
    Ok(page)
}

/// The format of the report's file, told by its extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputFormat {
    /// One self-contained HTML page.
    Html,
    /// A PDF, the HTML page printed by headless Chromium.
    Pdf,
}

impl OutputFormat {
    /// The format of `out` by its extension (`.html`/`.htm` or `.pdf`); any other is refused.
    pub fn of(out: &Path) -> Result<Self, ReportError> {
        let extension = out
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        match extension.as_deref() {
            Some("html" | "htm") => Ok(OutputFormat::Html),
            Some("pdf") => Ok(OutputFormat::Pdf),
            _ => Err(ReportError::OutputFormat(out.to_path_buf())),
        }
    }
}

/// Build the report of `options.input` and write it to `out`: one HTML file (pictures
/// embedded, no other file needed), or a PDF of that page when `out` ends in `.pdf`.
pub fn run_report(
    options: &ReportRequest,
    out: &Path,
    progress: &dyn Progress,
) -> Result<Page, ReportError> {
    let format = OutputFormat::of(out)?;
    let page = build_report(options, progress)?;
    match format {
        OutputFormat::Html => page.report.write(out).map_err(ReportError::from_source)?,
        OutputFormat::Pdf => pdf::print(&page.report.to_html(), out)?,
    }
    Ok(page)
}

/// The first page's facts: the sample, operator and customer given, and the date.
fn header(options: &ReportRequest, date: String) -> Vec<(String, String)> {
    let sample = &options.sample;
    [
        ("sample ID", sample.sample_id.clone()),
        ("operator", sample.operator.clone()),
        ("customer", sample.customer.clone()),
        ("date", Some(date)),
    ]
    .into_iter()
    .filter_map(|(label, value)| Some((label.to_string(), value?)))
    .collect()
}

/// Today's date (UTC), `YYYY-MM-DD`.
fn today() -> String {
    date_of(std::time::SystemTime::now())
}

/// The date (UTC) of a time, `YYYY-MM-DD`.
fn date_of(time: std::time::SystemTime) -> String {
    let mut text = humantime::format_rfc3339_seconds(time).to_string();
    text.truncate(10);
    text
}

/// The page's layout for the options' audience.
fn layout(options: &ReportRequest) -> Layout {
    match options.audience {
        Audience::Customer => Layout::Customer,
        Audience::Engineering => Layout::Engineering,
    }
}

/// The report of the session journal `options.input` written as `dir/report.html`, and each
/// of its figures as a PNG file beside it named after the figure's title
/// (`render_sphere.png`, ...); returns the page and the files written, the HTML last.
pub fn write_session_pictures(
    options: &ReportRequest,
    dir: &Path,
    progress: &dyn Progress,
) -> Result<(Page, Vec<PathBuf>), ReportError> {
    check(options)?;
    let page = session::report(options, progress)?;
    let report = &page.report;
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
    let html = dir.join("report.html");
    report.write(&html).map_err(ReportError::from_source)?;
    files.push(html);
    Ok((page, files))
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
        let options = ReportRequest {
            truth: Some("steel".into()),
            samples: Some(samples),
            size_px: 16,
            spp: 1,
            ..ReportRequest::new(binary)
        };
        run_report(&options, &out, &NoProgress).unwrap();
        let html = std::fs::read_to_string(&out).unwrap();
        for text in [
            "BRDF report: steel",
            "k-hat</th><td>",
            "1458000 of 1458000 (100.0 %)",
            "planned cells measured (raw samples)</th><td>3 of 4",
            "Against <b>steel</b>",
            "Render, sphere",
            "Render, speedshape",
            "Characteristic slice of the reference",
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
        let options = |input: &str| ReportRequest {
            size_px: 16,
            spp: 1,
            ..ReportRequest::new(dir.path().join(input))
        };
        let out = dir.path().join("r.html");
        let error =
            |options: ReportRequest| chain(&run_report(&options, &out, &NoProgress).unwrap_err());
        assert!(error(options("missing.sqlite")).contains("missing.sqlite"));
        assert!(error(options("x.csv")).contains("x.csv: no such file, preset or model fit"));
        assert!(error(options("missing.binary")).contains("missing.binary"));
        for refused in ["r.docx", "r", "r.htmlx"] {
            let written = dir.path().join(refused);
            let message = chain(&run_report(&options("steel"), &written, &NoProgress).unwrap_err());
            assert!(
                message.contains(refused) && message.contains("as .html or .pdf"),
                "{message}"
            );
            assert!(!written.exists());
        }
        let tolerances = ReportRequest {
            tolerances: Some(dir.path().join("t.toml")),
            ..options("steel")
        };
        assert!(error(tolerances).contains("--tolerances needs --against"));
        let with_table = ReportRequest {
            table: Some(dir.path().join("t.binary")),
            ..options("m.binary")
        };
        assert!(error(with_table).contains("--table is for a session journal"));
        let small = ReportRequest {
            size_px: 4,
            ..options("steel")
        };
        assert_eq!(
            error(small),
            "size 4: expected a whole number from 8 to 8192"
        );
    }

    /// A customer's report of a material file against a reference: the sample's facts and
    /// the date on the page, the title from the file's `name`, figures labelled "reference"
    /// and the verdict, and none of the engineer's sections or the word "truth".
    #[test]
    fn a_customer_report_shows_the_sample_the_verdict_and_no_truth() {
        let dir = tempfile::tempdir().unwrap();
        let toml = dir.path().join("panel.toml");
        let mut material = specula_core::materials::preset("silver-925").unwrap();
        material.name = "Panel 17 satin silver".into();
        std::fs::write(&toml, material.to_toml_string()).unwrap();
        let tolerances = dir.path().join("t.toml");
        std::fs::write(&tolerances, "[tolerances]\ngloss_20 = 1.0\nde00_15 = 1.0\n").unwrap();
        let out = dir.path().join("r.html");
        let options = ReportRequest {
            against: Some("chrome".into()),
            tolerances: Some(tolerances),
            sample: SampleInfo {
                sample_id: Some("P-17".into()),
                operator: Some("A. Lee".into()),
                customer: Some("Acme Coatings".into()),
            },
            audience: Audience::Customer,
            size_px: 16,
            spp: 1,
            ..ReportRequest::new(&toml)
        };
        let page = run_report(&options, &out, &NoProgress).unwrap();
        let html = std::fs::read_to_string(&out).unwrap();
        for text in [
            "<title>BRDF report: Panel 17 satin silver</title>",
            "<th>sample ID</th><td>P-17</td>",
            "<th>operator</th><td>A. Lee</td>",
            "<th>customer</th><td>Acme Coatings</td>",
            &format!("<th>date</th><td>{}</td>", today()),
            "chrome (reference)",
            "<td>fail: gloss_20, de00_15</td>",
            "Render, sphere",
        ] {
            assert!(html.contains(text), "missing: {text}");
        }
        for absent in ["truth", "k-hat", "Error figures", "Characteristic slice"] {
            assert!(!html.contains(absent), "shows {absent}");
        }
        assert_eq!(page.verdict.unwrap().failing, ["gloss_20", "de00_15"]);
        // The engineer's page of the same sample has its sections, and no "truth" either.
        let engineering = ReportRequest {
            audience: Audience::Engineering,
            ..options
        };
        run_report(&engineering, &out, &NoProgress).unwrap();
        let html = std::fs::read_to_string(&out).unwrap();
        assert!(html.contains("k-hat") && html.contains("P-17"));
        assert!(!html.contains("truth"));
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
