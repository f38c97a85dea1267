//! The measurement report: one self-contained HTML file (styles inline, pictures embedded as
//! base64 PNG data) that opens in any browser, offline, and can be mailed as it is.
//!
//! A [`Report`] is a set of optional sections; whoever builds it fills what it knows: a MERL
//! file gives the material, its coverage of the grid and k-hat of its probe, a known truth
//! adds the error figures, a measurement session adds the plan's coverage and the duration.
//! Sections left empty say so in the page instead of disappearing, so that a reader sees
//! what was not known.

use crate::error::VisualError;
use base64::Engine;
use image::RgbImage;
use std::fmt::Write;
use std::path::Path;

/// What the material is.
#[derive(Debug, Clone, Default)]
pub struct MaterialSection {
    /// The material's name.
    pub name: String,
    /// Where it was read from (a path, a preset name).
    pub source: String,
    /// Further facts as (label, value) rows, e.g. the peak value and where it lies.
    pub facts: Vec<(String, String)>,
}

/// k-hat of the adaptive theta_h sampling (paper 5.2).
#[derive(Debug, Clone)]
pub struct KHatSection {
    /// The sampling function's family (the paper's is exponential).
    pub family: String,
    /// k-hat, the fitted k of the sampling function (paper eq. 3).
    pub k: f64,
    /// The fit error at k-hat, 1/sr.
    pub fit_error: f64,
    /// Samples of the probe it was fitted to.
    pub probe_samples: usize,
    /// Samples the fitted function places along theta_h.
    pub placed_samples: usize,
}

/// How much of what was planned or of the MERL grid was measured.
#[derive(Debug, Clone)]
pub struct CoverageSection {
    /// (what, count, of how many) rows, e.g. ("measured MERL cells", 812_345, 1_458_000).
    pub rows: Vec<(String, usize, usize)>,
}

/// How long the measurement took.
#[derive(Debug, Clone)]
pub struct DurationSection {
    /// The time the measurement took, seconds: the device's time (for a session on the
    /// simulator, its simulated clock), not the wall-clock time of the computer.
    pub measured_s: Option<f64>,
    /// The plan's estimate, seconds.
    pub estimated_s: Option<f64>,
}

/// Error figures against a known truth.
#[derive(Debug, Clone)]
pub struct ErrorSection {
    /// The truth compared against.
    pub truth: String,
    /// The error figures, one row per set of cells.
    pub rows: Vec<ErrorRow>,
}

/// One line of error figures (see `specula compare --help` for their definitions).
#[derive(Debug, Clone)]
pub struct ErrorRow {
    /// Which cells, e.g. "all" or "light and camera within 75 deg".
    pub set: String,
    /// Number of cells in the set.
    pub cells: usize,
    /// Cosine-weighted relative RMSE (`specula_core::compare`).
    pub relative_rmse: f64,
    /// RMSE of `ln(1 + f cos theta_i)` (`specula_core::compare`).
    pub log_rmse: f64,
    /// The paper's figure: mean |a - b| on the characteristic slice, 1/sr.
    pub slice_mae: f64,
}

/// A titled table of figures computed elsewhere (e.g. the appearance figures of
/// `specula-appearance`), with notes below it.
#[derive(Debug, Clone, Default)]
pub struct TableSection {
    /// The table's title.
    pub title: String,
    /// Column headings.
    pub header: Vec<String>,
    /// The rows, one cell per column.
    pub rows: Vec<Vec<String>>,
    /// Paragraphs under the table (definitions, warnings).
    pub notes: Vec<String>,
}

/// A picture with its title and caption.
#[derive(Debug, Clone)]
pub struct Figure {
    /// The figure's title.
    pub title: String,
    /// The caption below the figure.
    pub caption: String,
    /// PNG file bytes.
    pub png: Vec<u8>,
}

impl Figure {
    /// A figure of an image (encoded as PNG).
    pub fn new(
        title: impl Into<String>,
        caption: impl Into<String>,
        image: &RgbImage,
    ) -> Result<Self, VisualError> {
        Ok(Self {
            title: title.into(),
            caption: caption.into(),
            png: png_bytes(image)?,
        })
    }
}

/// Whom the page is for, which decides the sections it shows.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Layout {
    /// Every section; those not known say so.
    #[default]
    Engineering,
    /// The header, the material, the tables and the pictures: no measurement or error
    /// sections.
    Customer,
}

/// The whole report; every section is optional.
#[derive(Debug, Clone, Default)]
pub struct Report {
    /// The report's title.
    pub title: String,
    /// Who made it, e.g. "specula 0.1.0".
    pub generator: String,
    /// Whom the page is for.
    pub layout: Layout,
    /// Facts shown under the title (sample ID, operator, customer, date), in order.
    pub header: Vec<(String, String)>,
    /// What the material is.
    pub material: Option<MaterialSection>,
    /// k-hat of the adaptive theta_h sampling (paper 5.2).
    pub k_hat: Option<KHatSection>,
    /// How much was measured.
    pub coverage: Option<CoverageSection>,
    /// How long the measurement took.
    pub duration: Option<DurationSection>,
    /// Error figures against a known truth.
    pub errors: Option<ErrorSection>,
    /// Further tables, each its own section after the error figures.
    pub tables: Vec<TableSection>,
    /// The pictures, in order.
    pub figures: Vec<Figure>,
    /// Free remarks, one paragraph each.
    pub notes: Vec<String>,
}

/// The PNG file bytes of an image.
pub fn png_bytes(image: &RgbImage) -> Result<Vec<u8>, VisualError> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    image
        .write_to(&mut bytes, image::ImageFormat::Png)
        .map_err(|cause| VisualError::Encode { cause })?;
    Ok(bytes.into_inner())
}

/// Text made safe inside HTML elements and attribute values.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// Seconds as hours and minutes (or seconds when short), as the page writes durations.
pub fn duration_text(seconds: f64) -> String {
    if seconds < 120.0 {
        format!("{seconds:.1} s")
    } else {
        let minutes = (seconds / 60.0).round() as u64;
        format!("{} h {:02} min", minutes / 60, minutes % 60)
    }
}

const STYLE: &str = "body{font-family:system-ui,-apple-system,'Segoe UI',sans-serif;margin:0;color:#1d1d1f;background:#f5f5f7}\
main{max-width:1100px;margin:0 auto;padding:24px}\
h1{font-size:1.7em;margin:0 0 4px}h2{font-size:1.2em;margin:28px 0 8px;border-bottom:1px solid #d2d2d7;padding-bottom:4px}\
.sub{color:#6e6e73;margin:0 0 16px}\
table{border-collapse:collapse;background:#fff;margin:4px 0}td,th{padding:5px 12px;border:1px solid #e5e5ea;text-align:left}\
th{background:#fafafa;font-weight:600}td.num{text-align:right;font-variant-numeric:tabular-nums}\
.missing{color:#8e8e93;font-style:italic}\
figure{background:#fff;border:1px solid #e5e5ea;border-radius:6px;padding:12px;margin:16px 0}\
figure img{max-width:100%;height:auto;display:block;margin:0 auto}figcaption{color:#3a3a3c;margin-top:8px}\
figcaption b{color:#1d1d1f}";

impl Report {
    /// The complete HTML page.
    pub fn to_html(&self) -> String {
        let mut html = String::new();
        let title = escape(&self.title);
        let _ = write!(
            html,
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
             <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
             <meta name=\"generator\" content=\"{}\">\n<title>{title}</title>\n<style>{STYLE}</style>\n\
             </head>\n<body>\n<main>\n<h1>{title}</h1>\n<p class=\"sub\">Made by {}</p>\n",
            escape(&self.generator),
            escape(&self.generator)
        );
        if !self.header.is_empty() {
            html.push_str("<table>\n");
            for (label, value) in &self.header {
                row(&mut html, label, value);
            }
            html.push_str("</table>\n");
        }
        self.material_html(&mut html);
        if self.layout == Layout::Engineering {
            self.measurement_html(&mut html);
            self.errors_html(&mut html);
        }
        for table in &self.tables {
            table_html(&mut html, table);
        }
        self.figures_html(&mut html);
        if !self.notes.is_empty() {
            html.push_str("<h2>Notes</h2>\n");
            for note in &self.notes {
                let _ = writeln!(html, "<p>{}</p>", escape(note));
            }
        }
        html.push_str("</main>\n</body>\n</html>\n");
        html
    }

    /// Writes the page.
    pub fn write(&self, path: &Path) -> Result<(), VisualError> {
        specula_core::atomic_file::write_bytes(path, self.to_html().as_bytes()).map_err(|cause| {
            VisualError::Write {
                path: path.to_path_buf(),
                what: "the report",
                cause,
            }
        })
    }

    fn material_html(&self, html: &mut String) {
        html.push_str("<h2>Material</h2>\n");
        match &self.material {
            Some(m) => {
                html.push_str("<table>\n");
                row(html, "name", &m.name);
                row(html, "source", &m.source);
                for (label, value) in &m.facts {
                    row(html, label, value);
                }
                html.push_str("</table>\n");
            }
            None => missing(html, "No material description."),
        }
    }

    fn measurement_html(&self, html: &mut String) {
        html.push_str("<h2>Measurement</h2>\n<table>\n");
        match &self.k_hat {
            Some(k) => {
                row(
                    html,
                    "k-hat",
                    &format!(
                        "{:.3} ({} sampling function, fit error {:.3e} 1/sr; fitted to a probe of {} samples, places {} samples along theta_h)",
                        k.k, k.family, k.fit_error, k.probe_samples, k.placed_samples
                    ),
                );
            }
            None => missing_row(html, "k-hat", "not known"),
        }
        match &self.coverage {
            Some(c) => {
                for (what, count, total) in &c.rows {
                    let percent = if *total > 0 {
                        100.0 * *count as f64 / *total as f64
                    } else {
                        0.0
                    };
                    row(html, what, &format!("{count} of {total} ({percent:.1} %)"));
                }
            }
            None => missing_row(html, "coverage", "not known"),
        }
        match &self.duration {
            Some(d) => {
                let text =
                    |s: Option<f64>| s.map_or_else(|| "not recorded".to_string(), duration_text);
                row(html, "duration", &text(d.measured_s));
                row(html, "planned duration", &text(d.estimated_s));
            }
            None => missing_row(
                html,
                "duration",
                "not recorded (a session journal holds it)",
            ),
        }
        html.push_str("</table>\n");
    }

    fn errors_html(&self, html: &mut String) {
        html.push_str("<h2>Error figures</h2>\n");
        let Some(errors) = &self.errors else {
            missing(
                html,
                "No error figures: no known BRDF to compare the table with, or no table.",
            );
            return;
        };
        let _ = writeln!(
            html,
            "<p>Against <b>{}</b>. relative RMSE: cosine-weighted, of the reflected radiance; \
             log RMSE: of ln(1 + f cos theta_i); slice MAE: mean |a - b| on the characteristic \
             slice phi_d = 90 deg (the paper's figure).</p>",
            escape(&errors.truth)
        );
        html.push_str(
            "<table>\n<tr><th>cells</th><th>count</th><th>relative RMSE</th><th>log RMSE</th><th>slice MAE (1/sr)</th></tr>\n",
        );
        for e in &errors.rows {
            let _ = writeln!(
                html,
                "<tr><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{:.4}</td><td class=\"num\">{:.4}</td><td class=\"num\">{:.4e}</td></tr>",
                escape(&e.set),
                e.cells,
                e.relative_rmse,
                e.log_rmse,
                e.slice_mae
            );
        }
        html.push_str("</table>\n");
    }

    fn figures_html(&self, html: &mut String) {
        html.push_str("<h2>Pictures</h2>\n");
        if self.figures.is_empty() {
            missing(html, "No pictures.");
        }
        let engine = base64::engine::general_purpose::STANDARD;
        for figure in &self.figures {
            let _ = writeln!(
                html,
                "<figure>\n<img alt=\"{}\" src=\"data:image/png;base64,{}\">\n<figcaption><b>{}.</b> {}</figcaption>\n</figure>",
                escape(&figure.title),
                engine.encode(&figure.png),
                escape(&figure.title),
                escape(&figure.caption)
            );
        }
    }
}

fn table_html(html: &mut String, table: &TableSection) {
    let _ = writeln!(html, "<h2>{}</h2>\n<table>", escape(&table.title));
    let cells = |tag: &str, cells: &[String]| {
        cells
            .iter()
            .map(|c| format!("<{tag}>{}</{tag}>", escape(c)))
            .collect::<String>()
    };
    let _ = writeln!(html, "<tr>{}</tr>", cells("th", &table.header));
    for r in &table.rows {
        let _ = writeln!(html, "<tr>{}</tr>", cells("td", r));
    }
    html.push_str("</table>\n");
    for note in &table.notes {
        let _ = writeln!(html, "<p>{}</p>", escape(note));
    }
}

fn row(html: &mut String, label: &str, value: &str) {
    let _ = writeln!(
        html,
        "<tr><th>{}</th><td>{}</td></tr>",
        escape(label),
        escape(value)
    );
}

fn missing_row(html: &mut String, label: &str, value: &str) {
    let _ = writeln!(
        html,
        "<tr><th>{}</th><td class=\"missing\">{}</td></tr>",
        escape(label),
        escape(value)
    );
}

fn missing(html: &mut String, text: &str) {
    let _ = writeln!(html, "<p class=\"missing\">{}</p>", escape(text));
}

#[cfg(test)]
mod tests {
    use super::*;

    fn figure() -> Figure {
        Figure::new(
            "slice <1>",
            "a & b",
            &RgbImage::from_pixel(3, 2, image::Rgb([10, 200, 30])),
        )
        .unwrap()
    }

    #[test]
    fn every_section_is_rendered_and_text_is_escaped() {
        let report = Report {
            title: "silver <925>".into(),
            generator: "specula test".into(),
            material: Some(MaterialSection {
                name: "silver".into(),
                source: "a\"b.binary".into(),
                facts: vec![("peak".into(), "1e4 1/sr".into())],
            }),
            k_hat: Some(KHatSection {
                family: "exponential".into(),
                k: 4.78,
                fit_error: 0.012,
                probe_samples: 90,
                placed_samples: 30,
            }),
            coverage: Some(CoverageSection {
                rows: vec![("measured cells".into(), 4073, 6300)],
            }),
            duration: Some(DurationSection {
                measured_s: Some(15.0 * 3600.0),
                estimated_s: None,
            }),
            errors: Some(ErrorSection {
                truth: "silver-925".into(),
                rows: vec![ErrorRow {
                    set: "all".into(),
                    cells: 100,
                    relative_rmse: 0.05,
                    log_rmse: 0.01,
                    slice_mae: 0.3,
                }],
            }),
            tables: vec![TableSection {
                title: "Appearance".into(),
                header: vec!["figure".into(), "a<b".into()],
                rows: vec![vec!["gloss 20 deg (GU)".into(), "95.25".into()]],
                notes: vec!["n & m".into()],
            }],
            figures: vec![figure()],
            notes: vec!["x < y".into()],
            ..Report::default()
        };
        let html = report.to_html();
        assert!(html.contains("<h2>Appearance</h2>"));
        assert!(html.contains("<th>a&lt;b</th>") && html.contains("<td>95.25</td>"));
        assert!(html.contains("n &amp; m"));
        assert!(html.contains("<title>silver &lt;925&gt;</title>"));
        assert!(html.contains("a&quot;b.binary"));
        assert!(html.contains("4.780 (exponential"));
        assert!(html.contains("4073 of 6300 (64.7 %)"));
        assert!(html.contains("15 h 00 min"));
        assert!(html.contains("0.0500"));
        assert!(html.contains("x &lt; y"));
        // The picture is embedded: its bytes decode back from the data URL.
        let start = html.find("base64,").unwrap() + 7;
        let end = start + html[start..].find('"').unwrap();
        let bytes = base64::engine::general_purpose::STANDARD
            .decode(&html[start..end])
            .unwrap();
        assert_eq!(
            image::load_from_memory(&bytes)
                .unwrap()
                .into_rgb8()
                .get_pixel(2, 1)
                .0,
            [10, 200, 30]
        );
        assert!(!html.contains("src=\"http") && !html.contains("<link"));
    }

    #[test]
    fn a_customer_page_has_its_header_and_no_measurement_or_error_sections() {
        let report = Report {
            layout: Layout::Customer,
            header: vec![("sample ID".into(), "P<17>".into())],
            ..Report::default()
        };
        let html = report.to_html();
        assert!(html.contains("<th>sample ID</th><td>P&lt;17&gt;</td>"));
        for absent in ["Measurement", "k-hat", "Error figures"] {
            assert!(!html.contains(absent), "{absent}");
        }
        assert!(html.contains("No pictures."));
    }

    #[test]
    fn missing_sections_say_so() {
        let html = Report::default().to_html();
        for text in [
            "No material description.",
            "k-hat</th><td class=\"missing\">not known",
            "No error figures",
            "No pictures.",
        ] {
            assert!(html.contains(text), "{text}");
        }
        assert_eq!(duration_text(30.0), "30.0 s");
        assert_eq!(duration_text(5400.0), "1 h 30 min");
    }
}
