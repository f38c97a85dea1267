//! `specula eval`: a BRDF at pairs of directions listed in a CSV file.

use anyhow::{Context, Result};
use specula_core::Spherical;
use std::io::Write;
use std::path::PathBuf;

/// Evaluate a BRDF at the directions of a CSV file and print f_r as CSV on stdout.
///
/// DIRS.csv has the header theta_i,phi_i,theta_o,phi_o (degrees; theta from 0 to 180, phi
/// from -360 to 360). Every row is read and checked before anything is printed. The output has the header
/// r,g,b (1/sr), one row per input row: `nan` where a MERL cell is not measured, 0 where a
/// direction is at or below the horizon. A MERL file is looked up in its nearest bin, as
/// MERL's reference reader does.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The BRDF: a preset name, a material .toml, a MERL .binary or a model:name fit.
    pub brdf: String,
    /// CSV file of direction pairs with header theta_i,phi_i,theta_o,phi_o (degrees).
    #[arg(long)]
    pub dirs: PathBuf,
}

#[derive(serde::Deserialize)]
struct DirectionPair {
    theta_i: f64,
    phi_i: f64,
    theta_o: f64,
    phi_o: f64,
}

impl DirectionPair {
    /// Refuses an angle outside its range (theta from 0 to 180 deg, phi from -360 to 360
    /// deg), naming the column.
    fn check(&self) -> std::result::Result<(), String> {
        for (column, value, range) in [
            ("theta_i", self.theta_i, THETA),
            ("phi_i", self.phi_i, PHI),
            ("theta_o", self.theta_o, THETA),
            ("phi_o", self.phi_o, PHI),
        ] {
            if !range.contains(value) {
                return Err(format!("{column} {value}: expected {}", range.words()));
            }
        }
        Ok(())
    }
}

/// A direction's polar angle from the normal (above 90: below the horizon, where f_r is 0).
const THETA: crate::range::Real = crate::range::Real::from_to(0.0, 180.0, "degrees");
/// A direction's azimuth.
const PHI: crate::range::Real = crate::range::AZIMUTH_DEG;

pub(crate) fn run(args: Args) -> Result<()> {
    let brdf = specula_formats::load_brdf(&args.brdf)?;
    let name = args.dirs.display().to_string();
    let mut reader =
        csv::Reader::from_path(&args.dirs).with_context(|| format!("{name}: cannot open"))?;
    let mut pairs = Vec::new();
    for (row, record) in reader.deserialize::<DirectionPair>().enumerate() {
        let line = row + 2;
        let pair = record.with_context(|| {
            format!("{name}: row {line}: expected numbers under theta_i,phi_i,theta_o,phi_o")
        })?;
        pair.check()
            .map_err(|problem| anyhow::anyhow!("{name}: row {line}: {problem}"))?;
        pairs.push(pair);
    }
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    writeln!(out, "r,g,b")?;
    for pair in pairs {
        let wi = Spherical::from_degrees(pair.theta_i, pair.phi_i).to_vector();
        let wo = Spherical::from_degrees(pair.theta_o, pair.phi_o).to_vector();
        match brdf.eval(wi, wo) {
            Some(v) => writeln!(out, "{:e},{:e},{:e}", v.x, v.y, v.z)?,
            None => writeln!(out, "nan,nan,nan")?,
        }
    }
    out.flush()?;
    Ok(())
}
