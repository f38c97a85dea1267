//! `specula appearance`: gloss, haze, DOI and multi-angle colour of BRDFs.

use anyhow::Result;
use specula_appearance::figures::{csv_header, csv_row, text_rows};
use specula_appearance::{appearance, Appearance, Differences, Options};
use specula_report::appearance::extrapolated_cells;

/// Gloss, haze, DOI, multi-angle colour and flop of BRDFs, as the coatings industry reads them.
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
}

pub(crate) fn run(args: Args) -> Result<()> {
    let mut sources: Vec<String> = args.against.iter().cloned().collect();
    sources.extend(args.brdfs.iter().cloned());
    let mut figures = Vec::with_capacity(sources.len());
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
        figures.push(result);
    }
    let differences: Option<Vec<Differences>> = args
        .against
        .as_ref()
        .map(|_| figures.iter().map(|f| f.against(&figures[0])).collect());
    if args.csv {
        let mut out = csv::Writer::from_writer(crate::output::Stdout);
        out.write_record(csv_header(differences.is_some()))?;
        for (k, (spec, f)) in sources.iter().zip(&figures).enumerate() {
            out.write_record(csv_row(spec, f, differences.as_ref().map(|d| &d[k])))?;
        }
        out.flush()?;
    } else {
        out!("{}", text_table(&names, &figures, differences.as_deref()));
    }
    Ok(())
}

/// Figures as rows, BRDFs (by name) as columns, aligned.
fn text_table(
    sources: &[String],
    figures: &[Appearance],
    differences: Option<&[Differences]>,
) -> String {
    let refs: Vec<&Appearance> = figures.iter().collect();
    let rows = text_rows(&refs, differences);
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
