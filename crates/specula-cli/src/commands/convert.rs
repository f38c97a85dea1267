//! `specula convert`: a BRDF from one measured format into another.

use crate::{progress, range};
use anyhow::Result;
use specula_core::GridSpec;
use specula_formats::convert::{convert, ConvertOptions, CsvGrid};
use specula_formats::rgl::RglResolution;
use std::path::PathBuf;

/// Convert a BRDF between MERL (.binary), UTIA (.bin), RGL (.bsdf) and a samples CSV (.csv),
/// resampling where the grids differ.
///
/// IN is any BRDF source: a measured file (recognised by its magic bytes or extension), a
/// preset, a material .toml or a fit such as nbrdf:gold-metallic-paint or lafortune:NAME. The
/// format of OUT is given by its extension. Same-format conversions copy. Otherwise the source
/// is evaluated at the target's nodes with its own interpolation: MERL bin centres
/// (theta_h = (i + 0.5)^2 / 90, theta_d = j + 0.5, phi_d = k + 0.5 deg), the UTIA nodes
/// (elevations 0..75 deg by 15, azimuths by 7.5), or sample rows. Cells the source has not
/// measured stay "not measured": negative in MERL, -1 in UTIA, no row in a CSV; a CSV source
/// is binned into MERL cells (the mean of each cell's samples). The samples CSV has the header
/// theta_h,phi_h,theta_d,phi_d,r,g,b (degrees, f_r in 1/sr).
///
/// A .bsdf output is the isotropic RGB tensor file of the RGL material database (Dupuy & Jakob
/// 2018) that Mitsuba 3 and pbrt-v4 render with their `measured` BSDF: the microfacet
/// distribution from the source's retro-reflection (power iteration), its visible-normal warp
/// per incident elevation, and the source sampled on the warped grid. Nodes the source has not
/// measured hold the nearest measured node's value and have their `valid` bit cleared.
#[derive(clap::Args)]
#[command(after_help = "Examples:
  specula convert paper_white_rgb.bsdf paper_white.binary
  specula convert gold.binary gold.bin
  specula convert samples.csv binned.binary
  specula convert measured.binary measured.bsdf
  specula convert green-paint paint.bsdf --rgl-sample-size 128
  specula convert nbrdf:chrome chrome.csv --grid utia")]
pub(crate) struct Args {
    /// The BRDF to convert: a .binary, .bin, .bsdf or .csv file, a preset or a model:name fit.
    pub input: String,
    /// The file to write; .binary (MERL), .bin (UTIA), .bsdf (RGL) or .csv (samples).
    #[arg(value_parser = crate::output::OUTPUT_FILE)]
    pub output: PathBuf,
    /// Azimuth of the half vector (degrees) at which MERL cells and MERL-grid samples are
    /// taken. Range: degrees from -360 to 360.
    ///
    /// Matters only for anisotropic sources (UTIA files); 45 is the paper's choice (section
    /// 4.3), away from the scratch directions.
    #[arg(long = "phi-h", alias = "phi-h-deg", default_value_t = GridSpec::paper().phi_h_deg, allow_negative_numbers = true, value_parser = range::AZIMUTH_DEG)]
    pub phi_h_deg: f64,
    /// Where to sample a continuous source (RGL file, fit, preset) written as CSV: `merl`,
    /// the 1,458,000 MERL bin centres, or `utia`, the 82,944 UTIA nodes.
    #[arg(long, default_value_t = CsvGrid::Merl)]
    pub grid: CsvGrid,
    /// RGL output: incident elevations (slices), evenly spaced in cos(theta_i) from the
    /// normal to 89.9 deg. Each adds ndf-size^2 + 4 sample-size^2 floats to the file. Range: a
    /// whole number from 2 to 90.
    #[arg(long, default_value_t = RglResolution::DEFAULT.elevations, value_parser = range::RGL_ELEVATIONS)]
    pub rgl_elevations: usize,
    /// RGL output: nodes per axis of the microfacet distribution and of the visible-normal
    /// warp (the RGL database uses 128). Range: a whole number from 8 to 512.
    #[arg(long, default_value_t = RglResolution::DEFAULT.ndf_size, value_parser = range::RGL_NDF_SIZE)]
    pub rgl_ndf_size: usize,
    /// RGL output: samples per axis of each elevation's RGB grid (the RGL database uses 32;
    /// finer resolves sharp highlights over a diffuse base better). Range: a whole number from
    /// 4 to 256.
    #[arg(long, default_value_t = RglResolution::DEFAULT.sample_size, value_parser = range::RGL_SAMPLE_SIZE)]
    pub rgl_sample_size: usize,
}

/// Sample placement for continuous sources written as CSV.
pub(crate) fn run(args: Args) -> Result<()> {
    let options = ConvertOptions {
        phi_h_rad: args.phi_h_deg.to_radians(),
        csv_grid: args.grid,
        rgl: RglResolution {
            elevations: args.rgl_elevations,
            ndf_size: args.rgl_ndf_size,
            sample_size: args.rgl_sample_size,
        },
    };
    let spinner = progress::spinner("converting");
    let result = convert(&args.input, &args.output, &options);
    spinner.finish_and_clear();
    let done = result?;
    let holes = if done.not_measured > 0 {
        format!(", {} not measured", done.not_measured)
    } else {
        String::new()
    };
    outln!(
        "{}: {} ({}), {} measured{holes}",
        args.output.display(),
        done.target.label(),
        done.method,
        done.measured
    );
    Ok(())
}
