//! `specula convert`: a BRDF from one measured format into another.

use crate::{progress, range};
use anyhow::Result;
use specula_core::GridSpec;
use specula_formats::convert::{run_convert, ConvertRequest, CsvGrid};
use specula_formats::rgl::RglResolution;
use std::path::PathBuf;

/// Convert a BRDF between MERL, UTIA, RGL and samples CSV files.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The BRDF to convert: a .binary, .bin, .bsdf or .csv file, a preset or a model:name fit.
    pub input: String,
    /// The file to write; .binary (MERL), .bin (UTIA), .bsdf (RGL) or .csv (samples).
    #[arg(value_parser = crate::output::OUTPUT_FILE)]
    pub output: PathBuf,
    /// Azimuth of the half vector (degrees) at which MERL cells and MERL-grid samples are taken.
    /// Range: degrees from -360 to 360.
    #[arg(long = "phi-h", alias = "phi-h-deg", default_value_t = GridSpec::paper().phi_h_deg, allow_negative_numbers = true, value_parser = range::AZIMUTH_DEG)]
    pub phi_h_deg: f64,
    /// Where to sample a continuous source (RGL file, fit, preset) written as CSV: `merl`,
    /// the 1,458,000 MERL bin centres, or `utia`, the 82,944 UTIA nodes.
    #[arg(long, default_value_t = CsvGrid::Merl)]
    pub grid: CsvGrid,
    /// RGL output: incident elevations (slices), evenly spaced in cos(theta_i) from the normal to
    /// 89.9 deg. Range: a whole number from 2 to 90.
    #[arg(long, default_value_t = RglResolution::DEFAULT.elevations, value_parser = range::RGL_ELEVATIONS)]
    pub rgl_elevations: usize,
    /// RGL output: nodes (elevations) of the microfacet distribution and its projected area
    /// (the RGL database uses 128; the visible-normal warp has 64 x 64 nodes). Range: a whole
    /// number from 8 to 512.
    #[arg(long, default_value_t = RglResolution::DEFAULT.ndf_size, value_parser = range::RGL_NDF_SIZE)]
    pub rgl_ndf_size: usize,
    /// RGL output: samples per axis of each elevation's RGB grid (the RGL database uses 32; finer
    /// resolves sharp highlights over a diffuse base better). Range: a whole number from 4 to 256.
    #[arg(long, default_value_t = RglResolution::DEFAULT.sample_size, value_parser = range::RGL_SAMPLE_SIZE)]
    pub rgl_sample_size: usize,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let request = ConvertRequest {
        input: args.input,
        output: args.output.clone(),
        phi_h_deg: args.phi_h_deg,
        csv_grid: args.grid,
        rgl: RglResolution {
            elevations: args.rgl_elevations,
            ndf_size: args.rgl_ndf_size,
            sample_size: args.rgl_sample_size,
        },
    };
    let spinner = progress::spinner("converting");
    let result = run_convert(&request);
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
