//! What `specula appearance` and `specula.appearance` ask (the BRDFs, a reference, the
//! instrument's resolution, tolerances), checked in one place ([`AppearanceRequest::validate`]),
//! and the one entry point both call ([`run_appearance`]): the figures, their differences to
//! the reference, their expanded uncertainty where a measured table has one, and the verdicts,
//! in the text and CSV forms the CLI prints.

use crate::appearance::extrapolated_cells;
use crate::error::{OrReport, ReportError};
use specula_appearance::figures::{csv_header, csv_row, text_rows_with};
use specula_appearance::uncertainty::{column_names, expanded_uncertainty};
use specula_appearance::{appearance, Appearance, Differences, Options, Tolerances, Verdict};
use specula_core::merl::MerlBrdf;
use specula_formats::BrdfSource;
use specula_reconstruct::uncertainty::sidecar_path;
use std::path::{Path, PathBuf};

/// One BRDF whose figures are asked for.
#[derive(Clone)]
pub struct AppearanceInput {
    /// The row's label: the source as given (a file, a preset name).
    pub label: String,
    /// The BRDF.
    pub brdf: BrdfSource,
    /// The file it was read from, when it is one: a MERL `.binary` with a provenance sidecar
    /// has its extrapolated cells flagged, one with an uncertainty sidecar its figures'
    /// expanded uncertainty given.
    pub path: Option<PathBuf>,
}

impl AppearanceInput {
    /// The BRDF `spec` names (any source [`specula_formats::load_brdf`] reads), labelled by it.
    pub fn load(spec: &str) -> Result<Self, ReportError> {
        Ok(AppearanceInput {
            label: spec.to_string(),
            brdf: specula_formats::load_brdf(spec).or_report()?,
            path: Some(PathBuf::from(spec)),
        })
    }
}

/// What the figures are asked of.
#[derive(Clone, Default)]
pub struct AppearanceRequest {
    /// The BRDFs, one row each.
    pub brdfs: Vec<AppearanceInput>,
    /// A reference (e.g. electroplated chrome): the first row, and every row's differences
    /// are to it.
    pub against: Option<AppearanceInput>,
    /// Angular resolution of the instrument that measured the BRDFs, degrees, in
    /// [`specula_core::request::RESOLUTION_DEG`]: figures that read finer get a warning.
    pub resolution_deg: Option<f64>,
    /// A tolerance file (TOML): a verdict per row on its differences to the reference.
    pub tolerances: Option<PathBuf>,
}

impl AppearanceRequest {
    /// Checks the resolution's range (the error names `resolution_deg`, the CLI's parser
    /// `--resolution`, with the same words), that there is a BRDF, and that tolerances come
    /// with a reference.
    pub fn validate(&self) -> Result<(), ReportError> {
        self.options().validate()?;
        if self.brdfs.is_empty() {
            return Err(ReportError::Options("give at least one BRDF"));
        }
        if self.tolerances.is_some() && self.against.is_none() {
            return Err(ReportError::Options(
                "tolerances judge the differences to a reference: give against too",
            ));
        }
        Ok(())
    }

    /// The figures' options the request gives (no table's extrapolated cells).
    fn options(&self) -> Options {
        Options {
            extrapolated: None,
            resolution_deg: self.resolution_deg,
        }
    }
}

/// One row of the figures.
#[derive(Debug, Clone)]
pub struct AppearanceRow {
    /// The input's label.
    pub label: String,
    /// The BRDF's own name.
    pub name: String,
    /// Its figures.
    pub figures: Appearance,
    /// Its differences to the reference (zero on the reference's own row).
    pub differences: Option<Differences>,
    /// Each figure's expanded uncertainty (k = 2), when the input is a measured table with
    /// an uncertainty sidecar.
    pub expanded: Option<Vec<Option<f64>>>,
    /// The tolerances' verdict on its differences.
    pub verdict: Option<Verdict>,
}

/// The figures of every input, the reference's first.
#[derive(Debug, Clone)]
pub struct AppearanceTable {
    /// The rows.
    pub rows: Vec<AppearanceRow>,
    /// Whether the first row is the reference.
    pub with_reference: bool,
}

/// The figures, differences, uncertainties and verdicts `request` asks for.
pub fn run_appearance(request: &AppearanceRequest) -> Result<AppearanceTable, ReportError> {
    request.validate()?;
    let tolerances = request
        .tolerances
        .as_deref()
        .map(Tolerances::read)
        .transpose()
        .or_report()?;
    let mut rows = Vec::with_capacity(request.brdfs.len() + 1);
    for input in request.against.iter().chain(&request.brdfs) {
        let options = Options {
            extrapolated: match &input.path {
                Some(path) => extrapolated_cells(&path.to_string_lossy())?,
                None => None,
            },
            resolution_deg: request.resolution_deg,
        };
        rows.push(AppearanceRow {
            label: input.label.clone(),
            name: input.brdf.name(),
            figures: appearance(input.brdf.as_ref(), &options),
            differences: None,
            expanded: match &input.path {
                Some(path) => figures_uncertainty(path, &options)?,
                None => None,
            },
            verdict: None,
        });
    }
    if request.against.is_some() {
        let reference = rows[0].figures.clone();
        for row in &mut rows {
            let differences = row.figures.against(&reference);
            row.verdict = tolerances.as_ref().map(|t| t.verdict(&differences));
            row.differences = Some(differences);
        }
    }
    Ok(AppearanceTable {
        rows,
        with_reference: request.against.is_some(),
    })
}

/// The figures' expanded uncertainty of the MERL table at `path` from its uncertainty
/// sidecar, `None` when it is no `.binary` or has none.
fn figures_uncertainty(
    path: &Path,
    options: &Options,
) -> Result<Option<Vec<Option<f64>>>, ReportError> {
    let sidecar = sidecar_path(path);
    if path.extension().is_none_or(|e| e != "binary") || !sidecar.is_file() {
        return Ok(None);
    }
    let table = MerlBrdf::read(path).or_report()?;
    let u = MerlBrdf::read(&sidecar).or_report()?;
    Ok(Some(expanded_uncertainty(&table, &u, options)))
}

impl AppearanceTable {
    /// The verdicts on the samples (every row but the reference), when tolerances were given.
    pub fn sample_verdicts(&self) -> Option<Vec<Verdict>> {
        self.rows
            .iter()
            .skip(1)
            .map(|r| r.verdict.clone())
            .collect()
    }

    /// Every row's warnings, each naming its input (`spec: warning`).
    pub fn warnings(&self) -> Vec<String> {
        self.rows
            .iter()
            .flat_map(|r| {
                r.figures
                    .warnings
                    .iter()
                    .map(move |w| format!("{}: {w}", r.label))
            })
            .collect()
    }

    /// Whether any row has its figures' uncertainty.
    fn with_uncertainty(&self) -> bool {
        self.rows.iter().any(|r| r.expanded.is_some())
    }

    /// Whether the rows have verdicts.
    fn with_verdicts(&self) -> bool {
        self.rows.iter().any(|r| r.verdict.is_some())
    }

    /// The verdict shown for row `k`: `reference` for the reference, else its verdict.
    fn verdict_text(&self, k: usize) -> String {
        match &self.rows[k].verdict {
            _ if k == 0 => "reference".to_string(),
            Some(verdict) => verdict.to_string(),
            None => String::new(),
        }
    }

    /// The CSV records, the header first: one row per BRDF, the figures (and differences),
    /// then `U_<figure>` where a row has its uncertainty, then the verdict.
    pub fn csv_records(&self) -> Vec<Vec<String>> {
        let mut header = csv_header(self.with_reference);
        let figure_count = csv_header(false).len() - 1;
        if self.with_uncertainty() {
            header.extend(column_names(&csv_header(false)[1..]));
        }
        if self.with_verdicts() {
            header.push("verdict".to_string());
        }
        let mut records = vec![header];
        for (k, r) in self.rows.iter().enumerate() {
            let mut record = csv_row(&r.label, &r.figures, r.differences.as_ref());
            if self.with_uncertainty() {
                record.extend((0..figure_count).map(|c| {
                    r.expanded
                        .as_ref()
                        .and_then(|u| u.get(c).copied().flatten())
                        .map_or_else(String::new, |u| format!("{u:.4}"))
                }));
            }
            if self.with_verdicts() {
                record.push(self.verdict_text(k));
            }
            records.push(record);
        }
        records
    }

    /// The text table: one row per figure under a header of the BRDFs' names, aligned, and
    /// the verdicts' row when there are verdicts.
    pub fn text(&self) -> String {
        let figures: Vec<&Appearance> = self.rows.iter().map(|r| &r.figures).collect();
        let differences: Option<Vec<Differences>> =
            self.rows.iter().map(|r| r.differences.clone()).collect();
        let expanded: Vec<_> = self.rows.iter().map(|r| r.expanded.clone()).collect();
        let mut header = vec![String::new()];
        header.extend(
            self.rows
                .iter()
                .map(|r| specula_core::shown::excerpt(&r.name)),
        );
        let mut table = vec![header];
        table.extend(text_rows_with(&figures, differences.as_deref(), &expanded));
        if self.with_verdicts() {
            table.push(
                std::iter::once("verdict".to_string())
                    .chain((0..self.rows.len()).map(|k| self.verdict_text(k)))
                    .collect(),
            );
        }
        aligned(&table)
    }
}

/// `table`'s cells in columns: the first left-aligned, the others right-aligned.
fn aligned(table: &[Vec<String>]) -> String {
    let widths: Vec<usize> = (0..table[0].len())
        .map(|c| {
            table
                .iter()
                .map(|r| r[c].chars().count())
                .max()
                .unwrap_or(0)
        })
        .collect();
    let mut text = String::new();
    for row in table {
        let line: Vec<String> = row
            .iter()
            .zip(&widths)
            .enumerate()
            .map(|(c, (cell, w))| {
                // Padded by hand: a width from `{:w$}` above 65,535 would panic.
                let pad = " ".repeat(w.saturating_sub(cell.chars().count()));
                if c == 0 {
                    format!("{cell}{pad}")
                } else {
                    format!("{pad}{cell}")
                }
            })
            .collect();
        text.push_str(line.join("  ").trim_end());
        text.push('\n');
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chrome() -> AppearanceInput {
        AppearanceInput::load("chrome").unwrap()
    }

    #[test]
    fn a_request_out_of_range_is_refused_with_the_python_arguments_words() {
        let coarse = AppearanceRequest {
            brdfs: vec![chrome()],
            resolution_deg: Some(100.0),
            ..AppearanceRequest::default()
        };
        assert_eq!(
            run_appearance(&coarse).unwrap_err().to_string(),
            "resolution_deg 100: expected degrees above 0 and at most 90"
        );
        let alone = AppearanceRequest {
            brdfs: vec![chrome()],
            tolerances: Some(PathBuf::from("t.toml")),
            ..AppearanceRequest::default()
        };
        assert!(run_appearance(&alone)
            .unwrap_err()
            .to_string()
            .contains("give against too"));
    }

    #[test]
    fn the_reference_leads_and_every_row_has_its_differences() {
        let request = AppearanceRequest {
            brdfs: vec![AppearanceInput::load("green-paint").unwrap()],
            against: Some(chrome()),
            ..AppearanceRequest::default()
        };
        let table = run_appearance(&request).unwrap();
        assert_eq!(table.rows.len(), 2);
        assert_eq!(table.rows[0].label, "chrome");
        let own = table.rows[0].differences.as_ref().unwrap();
        assert!(own.gloss.iter().all(|d| *d == 0.0), "{own:?}");
        let paint = table.rows[1].differences.as_ref().unwrap();
        assert!(
            paint.gloss[0] < 0.0,
            "paint is less glossy than chrome: {paint:?}"
        );
        let records = table.csv_records();
        assert_eq!(records.len(), 3);
        assert!(records[0].iter().any(|c| c.starts_with("d_")));
        assert_eq!(
            table.text().lines().next().map(|l| l.contains("chrome")),
            Some(true)
        );
    }
}
