//! `specula appearance`: gloss, haze, DOI and multi-angle colour of BRDFs.

use anyhow::Result;
use specula_appearance::figures::{csv_header, csv_row, text_rows};
use specula_appearance::{appearance, Differences, Options, Tolerances, Verdict};
use specula_report::appearance::extrapolated_cells;

/// The appearance figures the coatings industry reads from a glossmeter and a multi-angle
/// spectrophotometer, computed from the whole BRDF by integrating it over each standard's
/// apertures.
///
///   gloss_20, gloss_60, gloss_85   specular gloss, ISO 2813 / ASTM D523, in GU: the receptor's
///                                  flux relative to polished black glass (n = 1.567) = 100 GU.
///
///   haze                           ASTM E430 narrow-angle haze at 30 deg: 100 R_2 / R_s, the
///                                  reflectance 2 deg off the specular over the specular's.
///
///   doi                            ASTM E430 distinctness of image at 30 deg:
///                                  100 (R_s - R_0.3) / R_s (100 for a perfect mirror).
///
///   haze_20                        haze at 20 deg, ASTM E430 method B / ISO 13803: receptors
///                                  at 18.1 and 21.9 deg, relative to the gloss standard x 100.
///
///   haze_d4039                     ASTM D4039 haze index G60 - G20 (high-gloss nonmetals).
///
///   L_g, a_g, b_g                  CIELAB under D65 at the aspecular angles g = 15, 25, 45, 75,
///                                  110 deg, illumination at 45 deg (ASTM E2194, DIN 6175-2).
///
///   flop_index                     2.69 (L*15 - L*110)^1.11 / L*45^0.86 (X-Rite, DuPont).
///
/// Colour-space assumption: Specula's BRDFs are RGB. The R, G, B channels are taken to be
/// linear sRGB (Rec. 709 primaries, D65 white point, IEC 61966-2-1); the reflectance factor
/// pi f_r converts to XYZ by the sRGB matrix and to CIELAB with the D65 white. No spectral
/// integration: an instrument's D65 readings of a real pigment would differ.
///
/// With --against REF every figure is followed by its difference to REF, and colour by
/// CIEDE2000 per angle. With --tolerances T.toml too, each sample gets a verdict (`pass`, or
/// `fail:` and the figures outside their tolerances): a `verdict` column in the CSV, a
/// `verdict` row in the table; the command exits 3 when any sample fails, 0 when all pass.
/// T.toml holds one table, [tolerances], of the largest allowed |difference| per figure,
/// keyed by the difference columns' names without `d_` (gloss_20 = 5.0, de00_15 = 1.0). Warnings (on standard error) say where a figure rests on cells of a
/// measured table that were extrapolated (from OUT.provenance.npy beside a .binary) or not
/// measured, and, with --resolution-deg, where it reads the BRDF at a finer angle than the
/// instrument resolved.
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
    /// Angular resolution of the instrument that measured the BRDFs, degrees: for example
    /// the angular radius of its light source (1.82 deg on the simulated UTIA device). Figures
    /// that read the BRDF at a finer angle get a warning. Range: degrees above 0 and at most
    /// 90.
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
    // One verdict per row; the reference (first) is not a sample and shows as such.
    let verdicts: Option<Vec<Verdict>> = tolerances
        .as_ref()
        .zip(differences.as_ref())
        .map(|(t, d)| d.iter().map(|d| t.verdict(d)).collect());
    if args.csv {
        let mut out = csv::Writer::from_writer(crate::output::Stdout);
        let mut header = csv_header(differences.is_some());
        header.extend(verdicts.as_ref().map(|_| "verdict".to_string()));
        out.write_record(header)?;
        for (k, (spec, f)) in sources.iter().zip(&figures).enumerate() {
            let mut row = csv_row(spec, f, differences.as_ref().map(|d| &d[k]));
            row.extend(verdicts.as_ref().map(|v| verdict_text(v, k)));
            out.write_record(row)?;
        }
        out.flush()?;
    } else {
        let mut rows = text_rows(&figures.iter().collect::<Vec<_>>(), differences.as_deref());
        if let Some(verdicts) = &verdicts {
            rows.push(verdict_row(verdicts));
        }
        out!("{}", text_table(&names, rows));
    }
    verdicts.map_or(Ok(()), |v| crate::verdict::check(&v[1..]))
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
