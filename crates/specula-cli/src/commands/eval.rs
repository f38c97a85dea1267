//! `specula eval`: a BRDF at pairs of directions listed in a CSV file.

use anyhow::Result;
use specula_formats::directions_csv::read_direction_pairs;
use std::io::Write;
use std::path::PathBuf;

/// Evaluate a BRDF at the directions of a CSV file and print f_r as CSV.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The BRDF: a preset name, a material .toml, a MERL .binary, an RGL .bsdf or a
    /// model:name fit.
    pub brdf: String,
    /// CSV of direction pairs theta_i,phi_i,theta_o,phi_o in degrees: (theta_i, phi_i) is the
    /// direction towards the light, (theta_o, phi_o) the direction towards the camera (an RGL
    /// .bsdf gets the camera direction in the file's incident slot).
    #[arg(long)]
    pub dirs: PathBuf,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let brdf = specula_formats::load_brdf(&args.brdf)?;
    let pairs = read_direction_pairs(&args.dirs)?;
    let mut out = std::io::BufWriter::new(crate::output::Stdout);
    writeln!(out, "r,g,b")?;
    for pair in pairs {
        let (wi, wo) = pair.directions();
        match brdf.eval(wi, wo) {
            Some(v) => writeln!(out, "{:e},{:e},{:e}", v.x, v.y, v.z)?,
            None => writeln!(out, "nan,nan,nan")?,
        }
    }
    out.flush()?;
    Ok(())
}
