//! `specula eval`: a BRDF at pairs of directions listed in a CSV file.

use anyhow::Result;
use specula_formats::directions_csv::read_direction_pairs;
use std::io::Write;
use std::path::PathBuf;

/// Evaluate a BRDF at the directions of a CSV file and print f_r as CSV on stdout.
///
/// DIRS.csv has the header theta_i,phi_i,theta_o,phi_o (degrees; theta from 0 to 180, phi
/// from -360 to 360): (theta_i, phi_i) is the direction towards the light, (theta_o, phi_o)
/// the direction towards the camera, so a row asks for f_r(light, camera). Every row is read
/// and checked before anything is printed. The output has the header r,g,b (1/sr), one row
/// per input row: `nan` where a MERL cell is not measured, 0 where a direction is at or
/// below the horizon. A MERL file is looked up in its nearest bin, as MERL's reference
/// reader does. An RGL .bsdf file is read as Mitsuba 3 renders it: the camera direction in
/// the file's incident slot and the light in its outgoing one.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The BRDF: a preset name, a material .toml, a MERL .binary, an RGL .bsdf or a
    /// model:name fit.
    pub brdf: String,
    /// CSV file of direction pairs with header theta_i,phi_i,theta_o,phi_o (degrees).
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
