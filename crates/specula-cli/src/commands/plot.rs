//! `specula plot`: the paper's figures as PNG pictures (Fig. 11, 13, 15 and the analysis of
//! section 5.1).

use crate::output::plain;
use crate::range;
use anyhow::Result;
use specula_core::sampling::Family;
use specula_core::statistics::Statistic;
use specula_core::GridSpec;
use specula_report::{plot, Adaptive, Figure, PlotRequest};
use specula_visual::plot::ThetaHAxis;
use std::path::PathBuf;

/// Draw the paper's figures of BRDF data as PNG pictures.
#[derive(clap::Args)]
pub(crate) struct Args {
    #[command(subcommand)]
    pub plot: Plot,
}

#[derive(clap::Subcommand)]
pub(crate) enum Plot {
    Slice(SliceArgs),
    Samples(SamplesArgs),
    Probe(ProbeArgs),
    Heatmap(HeatmapArgs),
}

/// The characteristic slice of a BRDF (paper Fig. 11): f_r (mean of R, G, B) over theta_d across
/// and theta_h up, in log false colour from black (low) to pale yellow (high); blue cells are not
/// measured.
#[derive(clap::Args)]
pub(crate) struct SliceArgs {
    /// The BRDF: a preset name, a material .toml, a MERL .binary or a model:name fit.
    pub brdf: String,
    /// The PNG to write.
    #[arg(long, value_parser = crate::output::OUTPUT_FILE)]
    pub out: PathBuf,
    /// theta_h axis: merl (square root, MERL's bins) or linear.
    #[arg(long, default_value = "merl")]
    pub axis: ThetaHAxis,
    /// The fixed phi_d, degrees (90: the characteristic slice). Range: degrees from 0 to 180.
    #[arg(long, default_value_t = 90.0, value_parser = range::PHI_D_DEG)]
    pub phi_d: f64,
    /// Azimuth of the half vector, degrees (matters only for anisotropic materials; 45 is the
    /// paper's choice). Range: degrees from -360 to 360.
    #[arg(long, default_value_t = GridSpec::paper().phi_h_deg, allow_negative_numbers = true, value_parser = range::AZIMUTH_DEG)]
    pub phi_h: f64,
}

/// The raw samples of a measurement (paper Fig. 15): one characteristic slice per measured phi_d,
/// each cell of the plan's grid (every theta_h and theta_d that occurs in the file) coloured by its
/// sample in log false colour, blue where that phi_d has no sample.
#[derive(clap::Args)]
pub(crate) struct SamplesArgs {
    /// The samples CSV file.
    pub samples: PathBuf,
    /// The PNG to write.
    #[arg(long, value_parser = crate::output::OUTPUT_FILE)]
    pub out: PathBuf,
    /// theta_h axis: merl (square root) or linear.
    #[arg(long, default_value = "merl")]
    pub axis: ThetaHAxis,
}

/// The probe against the adaptive samples (paper Fig. 13): f_r along theta_h from the dense probe
/// (solid lines) and at the adaptive positions (dashed lines with dots), each channel in its
/// colour, over the full range and over 0 to 2 deg.
#[derive(clap::Args)]
pub(crate) struct ProbeArgs {
    /// The probe CSV file (header theta_h,r,g,b; degrees, 1/sr), e.g. from `specula probe`.
    pub probe: PathBuf,
    /// The PNG to write.
    #[arg(long, value_parser = crate::output::OUTPUT_FILE)]
    pub out: PathBuf,
    /// A CSV of the adaptive samples: a theta_h column (degrees) and optionally r,g,b (1/sr).
    #[arg(long, conflicts_with_all = ["positions", "k"])]
    pub adaptive: Option<PathBuf>,
    /// The adaptive theta_h positions in degrees, comma-separated. Range: degrees from 0 to 90.
    #[arg(long, value_delimiter = ',', conflicts_with = "k", value_parser = range::THETA_H_DEG)]
    pub positions: Option<Vec<f64>>,
    /// k of the sampling function that places the adaptive samples (default: fitted). Range: a
    /// number above 0 and at most 100.
    #[arg(long, value_parser = range::SAMPLING_K)]
    pub k: Option<f64>,
    /// Family of the sampling function: exponential, power or base.
    #[arg(long, default_value = "exponential")]
    pub family: Family,
    /// Number of adaptive theta_h samples. Range: a whole number from 2 to 360.
    #[arg(long, default_value_t = GridSpec::paper().theta_h_samples, value_parser = range::THETA_H_SAMPLES)]
    pub theta_h_samples: usize,
}

/// The database analysis as a heatmap: one row per sampling family, one column per theta_d of the
/// column k is fitted on, coloured by the mean (or median) slice error in log false colour, the
/// best cell outlined.
#[derive(clap::Args)]
pub(crate) struct HeatmapArgs {
    /// The analysis CSV file.
    pub analysis: PathBuf,
    /// The PNG to write.
    #[arg(long, value_parser = crate::output::OUTPUT_FILE)]
    pub out: PathBuf,
    /// Colour by the median error instead of the mean.
    #[arg(long)]
    pub median: bool,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let request = match args.plot {
        Plot::Slice(a) => PlotRequest {
            figure: Figure::Slice {
                brdf: a.brdf,
                axis: a.axis,
                phi_d_deg: a.phi_d,
                phi_h_deg: a.phi_h,
            },
            out: a.out,
        },
        Plot::Samples(a) => PlotRequest {
            figure: Figure::Samples {
                samples: a.samples,
                axis: a.axis,
            },
            out: a.out,
        },
        Plot::Probe(a) => PlotRequest {
            figure: Figure::Probe {
                probe: a.probe,
                adaptive: match (a.adaptive, a.positions, a.k) {
                    (Some(path), _, _) => Adaptive::File(path),
                    (None, Some(positions), _) => Adaptive::Positions(positions),
                    (None, None, Some(k)) => Adaptive::K(k),
                    (None, None, None) => Adaptive::Fitted,
                },
                family: a.family,
                theta_h_samples: a.theta_h_samples,
            },
            out: a.out,
        },
        Plot::Heatmap(a) => PlotRequest {
            figure: Figure::Heatmap {
                analysis: a.analysis,
                statistic: if a.median {
                    Statistic::Median
                } else {
                    Statistic::Mean
                },
            },
            out: a.out,
        },
    };
    let plotted = plot(&request)?;
    if let Some(fit) = plotted.fitted {
        outln!("k={} error={}", plain(fit.function.k), plain(fit.error));
    }
    outln!("wrote {}", request.out.display());
    Ok(())
}
