//! `specula appearance`: gloss, haze, DOI and multi-angle colour of BRDFs.

use anyhow::Result;
use specula_appearance::figures::{csv_header, csv_row, text_rows_with};
use specula_appearance::uncertainty::{column_names, expanded_uncertainty};
use specula_appearance::{appearance, Differences, Options, Tolerances, Verdict};
use specula_core::merl::MerlBrdf;
use specula_reconstruct::uncertainty::sidecar_path;
use specula_report::appearance::extrapolated_cells;
use std::path::Path;

/// Gloss, haze, DOI, colour and flop of BRDFs, with verdicts against tolerances.
///
/// The colour is multi-angle colour: one reading per aspecular angle (`L_15`, ...).
///
/// A measured MERL table with its .uncertainty.binary beside it also gets each figure's
/// expanded uncertainty (k = 2, Monte Carlo over the cells' uncertainty): `± U` in the table,
/// `U_<figure>` columns in the CSV.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// BRDFs: presets, material .toml files, MERL .binary, RGL .bsdf, UTIA .bin, samples
    /// .csv, or model:name fits.
    #[arg(required = true)]
    pub brdfs: Vec<String>,
    /// A reference BRDF (e.g. electroplated chrome) to give the differences to.
    #[arg(long)]
    pub against: Option<String>,
    /// Write CSV (one row per BRDF, the reference's first) instead of the text table.
    #[arg(long)]
    pub csv: bool,
    /// Angular resolution of the instrument that measured the BRDFs, degrees: for example the
    /// angular radius of its light source (1.82 deg on the simulated UTIA device). Range: degrees
    /// above 0 and at most 90.
    #[arg(long = "resolution", alias = "resolution-deg", value_parser = crate::range::RESOLUTION_DEG)]
    pub resolution_deg: Option<f64>,
    /// A tolerance file (TOML, [tolerances]: gloss_20 = 5.0, de00_15 = 1.0, ...): a pass/fail
    /// verdict per sample; exit 3 when any fails.
    #[arg(long, requires = "against")]
    pub tolerances: Option<std::path::PathBuf>,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let tolerances = args
        .tolerances
        .as_deref()
        .map(Tolerances::read)
        .transpose()?;
    let mut sources: Vec<String> = args.against.iter().cloned().collect();
    sources.extend(args.brdfs.iter().cloned());
    let mut figures = Vec::with_capacity(sources.len());
    let mut expanded = Vec::with_capacity(sources.len());
    let mut names = Vec::with_capacity(sources.len());
    for spec in &sources {
        let options = Options {
            extrapolated: extrapolated_cells(spec)?,
            resolution_deg: args.resolution_deg,
        };
        let brdf = specula_formats::load_brdf(spec)?;
        names.push(specula_core::shown::excerpt(&brdf.name()));
        let result = appearance(brdf.as_ref(), &options);
        for warning in &result.warnings {
            eprintln!("warning: {spec}: {warning}");
        }
        expanded.push(figures_uncertainty(Path::new(spec), &options)?);
        figures.push(result);
    }
    let differences: Option<Vec<Differences>> = args
        .against
        .as_ref()
        .map(|_| figures.iter().map(|f| f.against(&figures[0])).collect());
    // One verdict per row; the reference (first) is not a sample and shows as such.
    let verdicts: Option<Vec<Verdict>> = tolerances
        .as_ref()
        .zip(differences.as_ref())
        .map(|(t, d)| d.iter().map(|d| t.verdict(d)).collect());
    if args.csv {
        let mut out = csv::Writer::from_writer(crate::output::Stdout);
        let mut header = csv_header(differences.is_some());
        let with_u = expanded.iter().any(Option::is_some);
        if with_u {
            header.extend(column_names(&csv_header(false)[1..]));
        }
        header.extend(verdicts.as_ref().map(|_| "verdict".to_string()));
        out.write_record(header)?;
        let figure_count = csv_header(false).len() - 1;
        for (k, (spec, f)) in sources.iter().zip(&figures).enumerate() {
            let mut row = csv_row(spec, f, differences.as_ref().map(|d| &d[k]));
            if with_u {
                row.extend((0..figure_count).map(|c| {
                    expanded[k]
                        .as_ref()
                        .and_then(|u| u.get(c).copied().flatten())
                        .map_or_else(String::new, |u| format!("{u:.4}"))
                }));
            }
            row.extend(verdicts.as_ref().map(|v| verdict_text(v, k)));
            out.write_record(row)?;
        }
        out.flush()?;
    } else {
        let mut rows = text_rows_with(
            &figures.iter().collect::<Vec<_>>(),
            differences.as_deref(),
            &expanded,
        );
        if let Some(verdicts) = &verdicts {
            rows.push(verdict_row(verdicts));
        }
        out!("{}", text_table(&names, rows));
    }
    verdicts.map_or(Ok(()), |v| crate::verdict::check(&v[1..]))
}

/// The figures' expanded uncertainty of the MERL table at `path` from its uncertainty
/// sidecar, `None` when it is no `.binary` or has none.
fn figures_uncertainty(path: &Path, options: &Options) -> Result<Option<Vec<Option<f64>>>> {
    let sidecar = sidecar_path(path);
    if path.extension().is_none_or(|e| e != "binary") || !sidecar.is_file() {
        return Ok(None);
    }
    let table = MerlBrdf::read(path)?;
    let u = MerlBrdf::read(&sidecar)?;
    Ok(Some(expanded_uncertainty(&table, &u, options)))
}

/// The verdict shown for row `k`: `reference` for the reference (row 0), else the verdict.
fn verdict_text(verdicts: &[Verdict], k: usize) -> String {
    if k == 0 {
        "reference".into()
    } else {
        verdicts[k].to_string()
    }
}

/// The text table's verdict row.
fn verdict_row(verdicts: &[Verdict]) -> Vec<String> {
    std::iter::once("verdict".to_string())
        .chain((0..verdicts.len()).map(|k| verdict_text(verdicts, k)))
        .collect()
}

/// Figure rows under a header of the BRDFs' names, aligned.
fn text_table(sources: &[String], rows: Vec<Vec<String>>) -> String {
    let mut header = vec![String::new()];
    header.extend(sources.iter().cloned());
    let mut table = vec![header];
    table.extend(rows);
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
    for row in &table {
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
