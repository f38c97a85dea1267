//! `specula plot`: the paper's figures as PNG pictures (Fig. 11, 13, 15 and the analysis of
//! section 5.1).

use crate::range;
use anyhow::{bail, Context, Result};
use specula_core::sampling::{Family, SamplingFunction};
use specula_core::statistics::Statistic;
use specula_core::GridSpec;
use specula_sampling::adaptive::AdaptiveSamples;
use specula_sampling::analysis::ErrorTable;
use specula_sampling::Probe;
use specula_visual::heatmap::Heatmap;
use specula_visual::plot::probe::{interpolate, plot_probe};
use specula_visual::plot::raw_samples::plot_raw_samples;
use specula_visual::plot::slice::{plot_slice, SliceOptions};
use specula_visual::plot::ThetaHAxis;
use specula_visual::RgbImage;
use std::path::{Path, PathBuf};

/// Draw BRDF data as PNG pictures with labelled axes (degrees, 1/sr): the paper's Fig. 11
/// (slice), Fig. 15 (samples), Fig. 13 (probe) and the analysis of section 5.1 (heatmap).
/// Fonts are embedded; no system font is needed.
///
/// Example: specula plot slice chrome --out chrome-slice.png
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

/// The characteristic slice of a BRDF (paper Fig. 11): f_r (mean of R, G, B) over theta_d
/// across and theta_h up, in log false colour from black (low) to pale yellow (high); blue
/// cells are not measured. On MERL's square-root theta_h axis (default) the first degree
/// around the specular peak takes a tenth of the height; --axis linear shows degrees evenly.
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
    /// Azimuth of the half vector, degrees (matters only for anisotropic materials; 45 is
    /// the paper's choice). Range: degrees from -360 to 360.
    #[arg(long, default_value_t = GridSpec::paper().phi_h_deg, allow_negative_numbers = true, value_parser = range::AZIMUTH_DEG)]
    pub phi_h: f64,
}

/// The raw samples of a measurement (paper Fig. 15): one characteristic slice per measured
/// phi_d, each cell of the plan's grid (every theta_h and theta_d that occurs in the file)
/// coloured by its sample in log false colour, blue where that phi_d has no sample.
///
/// SAMPLES.csv has the header theta_h,phi_h,theta_d,phi_d,r,g,b (degrees, 1/sr), one sample
/// a row; phi_h is not shown (the paper fixes it at 45 deg).
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

/// The probe against the adaptive samples (paper Fig. 13): f_r along theta_h from the dense
/// probe (solid lines) and at the adaptive positions (dashed lines with dots), each channel in
/// its colour, over the full range and over 0 to 2 deg.
///
/// The adaptive positions come from --adaptive (a CSV with a theta_h column, and r,g,b
/// columns if measured there), --positions, or --k with --family and --theta-h-samples; by default
/// k-hat is fitted to the probe (exponential family, 30 samples, as the paper). Where no
/// values are given, the probe is interpolated linearly at the positions.
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
    /// The adaptive theta_h positions in degrees, comma-separated. Range: degrees from 0 to
    /// 90.
    #[arg(long, value_delimiter = ',', conflicts_with = "k", value_parser = range::THETA_H_DEG)]
    pub positions: Option<Vec<f64>>,
    /// k of the sampling function that places the adaptive samples (default: fitted).
    /// Range: a number above 0 and at most 100.
    #[arg(long, value_parser = range::SAMPLING_K)]
    pub k: Option<f64>,
    /// Family of the sampling function: exponential, power or base.
    #[arg(long, default_value = "exponential")]
    pub family: Family,
    /// Number of adaptive theta_h samples. Range: a whole number from 2 to 360.
    #[arg(long, default_value_t = GridSpec::paper().theta_h_samples, value_parser = range::THETA_H_SAMPLES)]
    pub theta_h_samples: usize,
}

/// The database analysis as a heatmap: one row per sampling family, one column per theta_d
/// of the column k is fitted on, coloured by the mean (or median) slice error in log false
/// colour, the best cell outlined.
///
/// ANALYSIS.csv is what `specula analyze` writes: family,theta_d,mean_error,median_error,...
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
    let (out, image) = match args.plot {
        Plot::Slice(a) => (a.out.clone(), slice(a)?),
        Plot::Samples(a) => (a.out.clone(), samples(a)?),
        Plot::Probe(a) => (a.out.clone(), probe(a)?),
        Plot::Heatmap(a) => (a.out.clone(), heatmap(a)?),
    };
    if !out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
    {
        bail!("{}: plots are written as .png", out.display());
    }
    specula_visual::linear_image::save_png(&image, &out)?;
    outln!("wrote {}", out.display());
    Ok(())
}

fn slice(args: SliceArgs) -> Result<RgbImage> {
    let brdf = specula_formats::load_brdf(&args.brdf)?;
    let options = SliceOptions {
        axis: args.axis,
        phi_d_deg: args.phi_d,
        phi_h_deg: args.phi_h,
    };
    Ok(plot_slice(brdf.as_ref(), &brdf.name(), &options)?)
}

fn samples(args: SamplesArgs) -> Result<RgbImage> {
    let set = specula_formats::samples_csv::SampleSet::read(&args.samples)?;
    plot_raw_samples(set.samples(), &stem(&args.samples), args.axis)
        .with_context(|| args.samples.display().to_string())
}

fn probe(args: ProbeArgs) -> Result<RgbImage> {
    let probe = Probe::read_csv(&args.probe)?;
    let points = probe.points();
    let adaptive = match (&args.adaptive, &args.positions, args.k) {
        (Some(path), _, _) => match AdaptiveSamples::read_csv(path)? {
            AdaptiveSamples::Measured(samples) => samples,
            AdaptiveSamples::Positions(positions) => interpolate(&points, &positions),
        },
        (None, Some(positions), _) => {
            let mut positions = positions.clone();
            positions.sort_by(f64::total_cmp);
            interpolate(&points, &positions)
        }
        (None, None, Some(k)) => {
            let function = SamplingFunction::new(args.family, k)?;
            interpolate(&points, &function.positions_deg(args.theta_h_samples))
        }
        (None, None, None) => {
            let fit = specula_sampling::fit_k(&probe.column(), args.family, args.theta_h_samples)?;
            outln!(
                "k={} error={}",
                crate::output::plain(fit.function.k),
                crate::output::plain(fit.error)
            );
            interpolate(&points, &fit.function.positions_deg(args.theta_h_samples))
        }
    };
    Ok(plot_probe(&points, &adaptive, &stem(&args.probe))?)
}

fn heatmap(args: HeatmapArgs) -> Result<RgbImage> {
    let statistic = if args.median {
        Statistic::Median
    } else {
        Statistic::Mean
    };
    let table = ErrorTable::read_csv(&args.analysis, statistic)?;
    let best = table.best();
    let statistic = statistic.name();
    Ok(Heatmap {
        title: format!(
            "{}: {statistic} slice error by family and fitted column",
            stem(&args.analysis)
        ),
        x_label: "theta_d of the column k is fitted on (deg)".into(),
        x_values: table.theta_d_deg,
        row_labels: table.families,
        values: table.values,
        log_scale: true,
        value_label: format!("{statistic} abs. error (1/sr)"),
        highlight: best,
    }
    .draw()?)
}

fn stem(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(path: &Path, text: &str) {
        std::fs::write(path, text).unwrap();
    }

    fn probe_csv(dir: &Path) -> PathBuf {
        let path = dir.join("probe.csv");
        let mut text = String::from("theta_h,r,g,b\n");
        for i in 0..90 {
            let t = (i * i) as f64 / 90.0;
            let v = 500.0 * (-2.0 * t).exp() + 0.01;
            text.push_str(&format!("{t},{v},{},{}\n", 0.9 * v, 0.8 * v));
        }
        write(&path, &text);
        path
    }

    fn run_to(plot: Plot) -> Result<(u32, u32)> {
        let out = match &plot {
            Plot::Slice(a) => a.out.clone(),
            Plot::Samples(a) => a.out.clone(),
            Plot::Probe(a) => a.out.clone(),
            Plot::Heatmap(a) => a.out.clone(),
        };
        run(Args { plot })?;
        Ok(image::image_dimensions(&out)?)
    }

    fn probe_args(probe: PathBuf, out: PathBuf) -> ProbeArgs {
        ProbeArgs {
            probe,
            out,
            adaptive: None,
            positions: None,
            k: None,
            family: Family::Exponential,
            theta_h_samples: 30,
        }
    }

    #[test]
    fn every_plot_is_drawn() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let slice = SliceArgs {
            brdf: "chrome".into(),
            out: d.join("slice.png"),
            axis: ThetaHAxis::Linear,
            phi_d: 90.0,
            phi_h: 0.0,
        };
        assert!(run_to(Plot::Slice(slice)).unwrap().0 > 500);

        let samples = d.join("samples.csv");
        let mut text = String::from("theta_h,phi_h,theta_d,phi_d,r,g,b\n");
        for phi_d in [0, 45, 90] {
            for i in 0..10 {
                for j in 0..10 {
                    if phi_d == 90 && j > 7 {
                        continue;
                    }
                    text.push_str(&format!("{},45,{},{phi_d},1,2,3\n", (i * i) as f64, 9 * j));
                }
            }
        }
        write(&samples, &text);
        let args = SamplesArgs {
            samples,
            out: d.join("samples.png"),
            axis: ThetaHAxis::Merl,
        };
        assert!(run_to(Plot::Samples(args)).unwrap().0 > 800);

        let probe = probe_csv(d);
        assert!(run_to(Plot::Probe(probe_args(probe.clone(), d.join("p1.png")))).is_ok());
        let with_k = ProbeArgs {
            k: Some(4.78),
            ..probe_args(probe.clone(), d.join("p2.png"))
        };
        assert!(run_to(Plot::Probe(with_k)).is_ok());
        let adaptive = d.join("adaptive.csv");
        write(&adaptive, "theta_h\n0\n0.5\n3\n20\n90\n");
        let measured = ProbeArgs {
            adaptive: Some(adaptive),
            ..probe_args(probe, d.join("p3.png"))
        };
        assert_eq!(run_to(Plot::Probe(measured)).unwrap(), (900, 860));

        let analysis = d.join("analysis.csv");
        let mut text = String::from("family,theta_d,mean_error,median_error,materials\n");
        for family in ["power", "exponential", "base"] {
            for j in 0..90 {
                text.push_str(&format!("{family},{j},{},{},5\n", 1.0 + j as f64, 2.0));
            }
        }
        write(&analysis, &text);
        let heatmap = HeatmapArgs {
            analysis,
            out: d.join("heatmap.png"),
            median: false,
        };
        assert!(run_to(Plot::Heatmap(heatmap)).is_ok());
    }

    #[test]
    fn bad_inputs_name_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let missing = d.join("missing.csv");
        let err = run_to(Plot::Probe(probe_args(missing, d.join("x.png")))).unwrap_err();
        assert!(format!("{err:#}").contains("missing.csv"), "{err:#}");
        let adaptive = d.join("adaptive.csv");
        write(&adaptive, "position\n1\n");
        let args = ProbeArgs {
            adaptive: Some(adaptive),
            ..probe_args(probe_csv(d), d.join("x.png"))
        };
        let err = run_to(Plot::Probe(args)).unwrap_err();
        assert!(format!("{err:#}").contains("no theta_h column"), "{err:#}");
        let slice = SliceArgs {
            brdf: "chrome".into(),
            out: d.join("slice.jpg"),
            axis: ThetaHAxis::Merl,
            phi_d: 90.0,
            phi_h: 0.0,
        };
        assert!(format!("{:#}", run_to(Plot::Slice(slice)).unwrap_err()).contains(".png"));
    }
}
