//! `specula appearance`: gloss, haze, DOI and multi-angle colour of BRDFs.

use anyhow::Result;
use specula_report::{run_appearance, AppearanceInput, AppearanceRequest};

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
    let request = AppearanceRequest {
        brdfs: args
            .brdfs
            .iter()
            .map(|spec| AppearanceInput::load(spec))
            .collect::<Result<_, _>>()?,
        against: args
            .against
            .as_deref()
            .map(AppearanceInput::load)
            .transpose()?,
        resolution_deg: args.resolution_deg,
        tolerances: args.tolerances,
    };
    let table = run_appearance(&request)?;
    for warning in table.warnings() {
        eprintln!("warning: {warning}");
    }
    if args.csv {
        let mut out = csv::Writer::from_writer(crate::output::Stdout);
        for record in table.csv_records() {
            out.write_record(record)?;
        }
        out.flush()?;
    } else {
        out!("{}", table.text());
    }
    table
        .sample_verdicts()
        .map_or(Ok(()), |v| crate::verdict::check(&v))
}
