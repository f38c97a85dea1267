//! `specula plot`: the paper's figures as PNG pictures (Fig. 11, 13, 15 and the analysis of
//! section 5.1).

use anyhow::{bail, Context, Result};
use specula_core::sampling::{Family, SamplingFunction};
use specula_core::Rgb;
use specula_sampling::Probe;
use specula_visual::heatmap::Heatmap;
use specula_visual::plot::probe::{interpolate, plot_probe};
use specula_visual::plot::raw_samples::{plot_raw_samples, RawSample};
use specula_visual::plot::slice::{plot_slice, SliceOptions};
use specula_visual::plot::ThetaHAxis;
use specula_visual::RgbImage;
use std::path::{Path, PathBuf};

/// Draw BRDF data as PNG pictures with labelled axes (degrees, 1/sr).
///
///   slice     the characteristic slice theta_h x theta_d at phi_d = 90 deg (Fig. 11)
///   samples   the raw samples of a measurement, one slice per phi_d (Fig. 15)
///   probe     the dense probe against the adaptive samples (Fig. 13)
///   heatmap   the database analysis: fit error by family and theta_d column (section 5.1)
#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    pub plot: Plot,
}

#[derive(clap::Subcommand)]
pub enum Plot {
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
pub struct SliceArgs {
    /// The BRDF: a preset name, a material .toml, a MERL .binary or a model:name fit.
    pub brdf: String,
    /// The PNG to write.
    #[arg(long)]
    pub out: PathBuf,
    /// theta_h axis: merl (square root, MERL's bins) or linear.
    #[arg(long, default_value = "merl")]
    pub axis: ThetaHAxis,
    /// The fixed phi_d, degrees.
    #[arg(long, default_value_t = 90.0)]
    pub phi_d: f64,
    /// Azimuth of the half vector, degrees (matters only for anisotropic materials).
    #[arg(long, default_value_t = 0.0)]
    pub phi_h: f64,
}

/// The raw samples of a measurement (paper Fig. 15): one characteristic slice per measured
/// phi_d, each cell of the plan's grid (every theta_h and theta_d that occurs in the file)
/// coloured by its sample in log false colour, blue where that phi_d has no sample.
///
/// SAMPLES.csv has the header theta_h,phi_h,theta_d,phi_d,r,g,b (degrees, 1/sr), one sample
/// a row; phi_h is not shown (the paper fixes it at 45 deg).
#[derive(clap::Args)]
pub struct SamplesArgs {
    /// The samples CSV file.
    pub samples: PathBuf,
    /// The PNG to write.
    #[arg(long)]
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
/// columns if measured there), --positions, or --k with --family and --samples; by default
/// k-hat is fitted to the probe (exponential family, 30 samples, as the paper). Where no
/// values are given, the probe is interpolated linearly at the positions.
#[derive(clap::Args)]
pub struct ProbeArgs {
    /// The probe CSV file (header theta_h,r,g,b; degrees, 1/sr), e.g. from `specula probe`.
    pub probe: PathBuf,
    /// The PNG to write.
    #[arg(long)]
    pub out: PathBuf,
    /// A CSV of the adaptive samples: a theta_h column (degrees) and optionally r,g,b (1/sr).
    #[arg(long, conflicts_with_all = ["positions", "k"])]
    pub adaptive: Option<PathBuf>,
    /// The adaptive theta_h positions in degrees, comma-separated.
    #[arg(long, value_delimiter = ',', conflicts_with = "k")]
    pub positions: Option<Vec<f64>>,
    /// k of the sampling function that places the adaptive samples (default: fitted).
    #[arg(long)]
    pub k: Option<f64>,
    /// Family of the sampling function: exponential, power or base.
    #[arg(long, default_value = "exponential")]
    pub family: Family,
    /// Number of adaptive samples.
    #[arg(long, default_value_t = 30)]
    pub samples: usize,
}

/// The database analysis as a heatmap: one row per sampling family, one column per theta_d
/// of the column k is fitted on, coloured by the mean (or median) slice error in log false
/// colour, the best cell outlined.
///
/// ANALYSIS.csv is what `specula analyze` writes: family,theta_d,mean_error,median_error,...
#[derive(clap::Args)]
pub struct HeatmapArgs {
    /// The analysis CSV file.
    pub analysis: PathBuf,
    /// The PNG to write.
    #[arg(long)]
    pub out: PathBuf,
    /// Colour by the median error instead of the mean.
    #[arg(long)]
    pub median: bool,
}

pub fn run(args: Args) -> Result<()> {
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
    image
        .save(&out)
        .with_context(|| format!("{}: cannot write the PNG", out.display()))?;
    println!("wrote {}", out.display());
    Ok(())
}

fn slice(args: SliceArgs) -> Result<RgbImage> {
    let brdf = specula_formats::load_brdf(&args.brdf)?;
    let options = SliceOptions {
        axis: args.axis,
        phi_d_deg: args.phi_d,
        phi_h_deg: args.phi_h,
    };
    plot_slice(brdf.as_ref(), &brdf.name(), &options)
}

fn samples(args: SamplesArgs) -> Result<RgbImage> {
    let set = specula_formats::samples_csv::SampleSet::read(&args.samples)?;
    let raw: Vec<RawSample> = set
        .samples()
        .iter()
        .map(|s| RawSample {
            theta_h_deg: s.angles.theta_h.to_degrees(),
            theta_d_deg: s.angles.theta_d.to_degrees(),
            phi_d_deg: s.angles.phi_d.to_degrees(),
            value: s.value,
        })
        .collect();
    plot_raw_samples(&raw, &stem(&args.samples), args.axis)
        .with_context(|| args.samples.display().to_string())
}

fn probe(args: ProbeArgs) -> Result<RgbImage> {
    let probe = Probe::read_csv(&args.probe)?;
    let points: Vec<(f64, Rgb)> = probe
        .theta_h_deg()
        .iter()
        .copied()
        .zip(probe.rgb().iter().copied())
        .collect();
    let adaptive = match (&args.adaptive, &args.positions, args.k) {
        (Some(path), _, _) => read_adaptive(path, &points)?,
        (None, Some(positions), _) => {
            let mut positions = positions.clone();
            if positions
                .iter()
                .any(|p| !p.is_finite() || !(0.0..=90.0).contains(p))
            {
                bail!("--positions: every theta_h must lie in [0, 90] deg");
            }
            positions.sort_by(f64::total_cmp);
            interpolate(&points, &positions)
        }
        (None, None, Some(k)) => {
            let function = SamplingFunction::new(args.family, k)?;
            interpolate(&points, &function.positions_deg(args.samples))
        }
        (None, None, None) => {
            let fit = specula_sampling::fit_k(&probe.column(), args.family, args.samples)?;
            println!("k={} error={:e}", fit.function.k, fit.error);
            interpolate(&points, &fit.function.positions_deg(args.samples))
        }
    };
    plot_probe(&points, &adaptive, &stem(&args.probe))
}

/// The adaptive samples of a CSV: theta_h, and r,g,b when present (else interpolated).
fn read_adaptive(path: &Path, probe: &[(f64, Rgb)]) -> Result<Vec<(f64, Rgb)>> {
    let name = path.display();
    let mut reader =
        csv::Reader::from_path(path).with_context(|| format!("{name}: cannot read"))?;
    let headers = reader
        .headers()
        .with_context(|| format!("{name}: cannot read the header"))?
        .clone();
    let column = |wanted: &str| headers.iter().position(|h| h.trim() == wanted);
    let Some(theta_h) = column("theta_h") else {
        bail!(
            "{name}: no theta_h column (header: {})",
            headers.iter().collect::<Vec<_>>().join(",")
        );
    };
    let rgb = match (column("r"), column("g"), column("b")) {
        (Some(r), Some(g), Some(b)) => Some([r, g, b]),
        _ => None,
    };
    let mut rows = Vec::new();
    for (line, record) in reader.records().enumerate() {
        let record = record.with_context(|| format!("{name}: row {}", line + 2))?;
        let number = |i: usize| -> Result<f64> {
            let text = record.get(i).unwrap_or("").trim();
            text.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .with_context(|| format!("{name}: row {}: '{text}' is not a number", line + 2))
        };
        let t = number(theta_h)?;
        let value = match rgb {
            Some([r, g, b]) => Some(Rgb::new(number(r)?, number(g)?, number(b)?)),
            None => None,
        };
        rows.push((t, value));
    }
    if rows.is_empty() {
        bail!("{name}: no rows");
    }
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    Ok(match rgb {
        Some(_) => rows
            .into_iter()
            .map(|(t, v)| (t, v.unwrap_or_default()))
            .collect(),
        None => interpolate(probe, &rows.iter().map(|r| r.0).collect::<Vec<_>>()),
    })
}

#[derive(serde::Deserialize)]
struct AnalysisRow {
    family: String,
    theta_d: f64,
    mean_error: f64,
    median_error: f64,
}

fn heatmap(args: HeatmapArgs) -> Result<RgbImage> {
    let name = args.analysis.display();
    let mut reader =
        csv::Reader::from_path(&args.analysis).with_context(|| format!("{name}: cannot read"))?;
    let mut families: Vec<String> = Vec::new();
    let mut columns: Vec<f64> = Vec::new();
    let mut cells: Vec<(usize, f64, f64)> = Vec::new();
    for (line, row) in reader.deserialize::<AnalysisRow>().enumerate() {
        let row = row.with_context(|| format!("{name}: row {}", line + 2))?;
        let f = match families.iter().position(|f| *f == row.family) {
            Some(f) => f,
            None => {
                families.push(row.family.clone());
                families.len() - 1
            }
        };
        if !columns.contains(&row.theta_d) {
            columns.push(row.theta_d);
        }
        let value = if args.median {
            row.median_error
        } else {
            row.mean_error
        };
        cells.push((f, row.theta_d, value));
    }
    if cells.is_empty() {
        bail!("{name}: no rows");
    }
    columns.sort_by(f64::total_cmp);
    let mut values = vec![vec![f64::NAN; columns.len()]; families.len()];
    for (f, theta_d, value) in cells {
        let j = columns
            .iter()
            .position(|c| *c == theta_d)
            .unwrap_or_default();
        values[f][j] = value;
    }
    let best = values
        .iter()
        .enumerate()
        .flat_map(|(f, row)| row.iter().enumerate().map(move |(j, v)| (f, j, *v)))
        .filter(|c| c.2.is_finite())
        .min_by(|a, b| a.2.total_cmp(&b.2))
        .map(|(f, j, _)| (f, j));
    let statistic = if args.median { "median" } else { "mean" };
    Heatmap {
        title: format!(
            "{}: {statistic} slice error by family and fitted column",
            stem(&args.analysis)
        ),
        x_label: "theta_d of the column k is fitted on (deg)".into(),
        x_values: columns,
        row_labels: families,
        values,
        log_scale: true,
        value_label: format!("{statistic} abs. error (1/sr)"),
        highlight: best,
    }
    .draw()
}

fn stem(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}
