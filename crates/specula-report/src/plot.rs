//! The paper's figures of BRDF data as PNG pictures (`specula plot`): the characteristic
//! slice (Fig. 11), the raw samples of a measurement (Fig. 15), the probe against the
//! adaptive samples (Fig. 13) and the database analysis of section 5.1 as a heatmap.

use crate::error::{OrReport, ReportError};
use specula_core::request::{
    sampling_function, AZIMUTH_DEG, PHI_D_DEG, THETA_H_DEG, THETA_H_SAMPLES,
};
use specula_core::sampling::{Family, SamplingFunction};
use specula_core::statistics::Statistic;
use specula_sampling::adaptive::AdaptiveSamples;
use specula_sampling::analysis::{DatabaseSummary, ErrorTable};
use specula_sampling::{KFit, Probe};
use specula_visual::heatmap::Heatmap;
use specula_visual::plot::probe::{interpolate, plot_probe};
use specula_visual::plot::raw_samples::plot_raw_samples;
use specula_visual::plot::slice::{plot_slice, SliceOptions};
use specula_visual::plot::ThetaHAxis;
use specula_visual::RgbImage;
use std::path::{Path, PathBuf};

/// One figure to draw.
#[derive(Clone, Debug)]
pub enum Figure {
    /// The characteristic slice of a BRDF (a source as `specula_formats::load_brdf` reads
    /// it): f_r over theta_d across and theta_h up at one phi_d and phi_h.
    Slice {
        /// The BRDF's source.
        brdf: String,
        /// theta_h's axis.
        axis: ThetaHAxis,
        /// The fixed phi_d, in [`PHI_D_DEG`].
        phi_d_deg: f64,
        /// Azimuth of the half vector, in [`AZIMUTH_DEG`].
        phi_h_deg: f64,
    },
    /// The raw samples of a measurement (a samples CSV), one slice per measured phi_d.
    Samples {
        /// The samples CSV file.
        samples: PathBuf,
        /// theta_h's axis.
        axis: ThetaHAxis,
    },
    /// A probe (CSV `theta_h,r,g,b`) against the adaptive samples.
    Probe {
        /// The probe CSV file.
        probe: PathBuf,
        /// Where the adaptive samples lie.
        adaptive: Adaptive,
        /// Family of the sampling function that places them.
        family: Family,
        /// Number of adaptive samples, in [`THETA_H_SAMPLES`].
        theta_h_samples: usize,
    },
    /// The database analysis (CSV) as a heatmap of the slice error by family and column.
    Heatmap {
        /// The analysis CSV file.
        analysis: PathBuf,
        /// Mean or median error.
        statistic: Statistic,
    },
}

/// Where the adaptive samples of a probe figure lie.
#[derive(Clone, Debug)]
pub enum Adaptive {
    /// Read from a CSV: a theta_h column (degrees) and optionally r,g,b (1/sr).
    File(PathBuf),
    /// These theta_h positions, degrees, each in [`THETA_H_DEG`].
    Positions(Vec<f64>),
    /// Placed by the sampling function with this k ([`sampling_function`]).
    K(f64),
    /// Placed by the sampling function with k fitted to the probe.
    Fitted,
}

/// A figure and the PNG to write it to.
#[derive(Clone, Debug)]
pub struct PlotRequest {
    /// The figure.
    pub figure: Figure,
    /// The PNG to write.
    pub out: PathBuf,
}

/// What drawing a figure found besides the picture: k fitted to the probe, when it was.
#[derive(Clone, Debug, Default)]
pub struct Plotted {
    /// The fit of [`Adaptive::Fitted`].
    pub fitted: Option<KFit>,
}

impl PlotRequest {
    /// Refuses an output that is not `.png` and a value out of its range (named as the
    /// Python arguments are: `phi_d_deg`, `positions`, `k`, ...).
    pub fn validate(&self) -> Result<(), ReportError> {
        let is_png = self
            .out
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        if !is_png {
            return Err(ReportError::PlotFormat(self.out.clone()));
        }
        match &self.figure {
            Figure::Slice {
                phi_d_deg,
                phi_h_deg,
                ..
            } => {
                PHI_D_DEG.check("phi_d_deg", *phi_d_deg)?;
                AZIMUTH_DEG.check("phi_h_deg", *phi_h_deg)?;
            }
            Figure::Probe {
                adaptive,
                family,
                theta_h_samples,
                ..
            } => {
                THETA_H_SAMPLES.check("theta_h_samples", *theta_h_samples)?;
                match adaptive {
                    Adaptive::Positions(positions) => {
                        for &position in positions {
                            THETA_H_DEG.check("positions", position)?;
                        }
                    }
                    Adaptive::K(k) => {
                        sampling_function(*family, *k).or_report()?;
                    }
                    Adaptive::File(_) | Adaptive::Fitted => {}
                }
            }
            Figure::Samples { .. } | Figure::Heatmap { .. } => {}
        }
        Ok(())
    }
}

/// Draws the figure `request` asks for and writes it as PNG.
pub fn plot(request: &PlotRequest) -> Result<Plotted, ReportError> {
    request.validate()?;
    let mut plotted = Plotted::default();
    let image = match &request.figure {
        Figure::Slice {
            brdf,
            axis,
            phi_d_deg,
            phi_h_deg,
        } => {
            let brdf = specula_formats::load_brdf(brdf).or_report()?;
            let options = SliceOptions {
                axis: *axis,
                phi_d_deg: *phi_d_deg,
                phi_h_deg: *phi_h_deg,
            };
            plot_slice(brdf.as_ref(), &brdf.name(), &options).or_report()?
        }
        Figure::Samples { samples, axis } => {
            let set = specula_formats::samples_csv::SampleSet::read(samples).or_report()?;
            plot_raw_samples(set.samples(), &stem(samples), *axis)
                .map_err(|e| ReportError::within(&samples.display().to_string())(e.into()))?
        }
        Figure::Probe {
            probe,
            adaptive,
            family,
            theta_h_samples,
        } => {
            let (image, fitted) = probe_figure(probe, adaptive, *family, *theta_h_samples)?;
            plotted.fitted = fitted;
            image
        }
        Figure::Heatmap {
            analysis,
            statistic,
        } => heatmap(analysis, *statistic)?,
    };
    specula_visual::linear_image::save_png(&image, &request.out).or_report()?;
    Ok(plotted)
}

/// The probe against the adaptive samples, and k when it was fitted.
fn probe_figure(
    path: &Path,
    adaptive: &Adaptive,
    family: Family,
    theta_h_samples: usize,
) -> Result<(RgbImage, Option<KFit>), ReportError> {
    let probe = Probe::read_csv(path).or_report()?;
    let points = probe.points();
    let mut fitted = None;
    let samples = match adaptive {
        Adaptive::File(file) => match AdaptiveSamples::read_csv(file).or_report()? {
            AdaptiveSamples::Measured(samples) => samples,
            AdaptiveSamples::Positions(positions) => interpolate(&points, &positions),
        },
        Adaptive::Positions(positions) => {
            let mut positions = positions.clone();
            positions.sort_by(f64::total_cmp);
            interpolate(&points, &positions)
        }
        Adaptive::K(k) => {
            let function = SamplingFunction::new(family, *k).or_report()?;
            interpolate(&points, &function.positions_deg(theta_h_samples))
        }
        Adaptive::Fitted => {
            let fit =
                specula_sampling::fit_k(&probe.column(), family, theta_h_samples).or_report()?;
            let positions = fit.function.positions_deg(theta_h_samples);
            fitted = Some(fit);
            interpolate(&points, &positions)
        }
    };
    let image = plot_probe(&points, &samples, &stem(path)).or_report()?;
    Ok((image, fitted))
}

/// The analysis as a heatmap, the best cell outlined.
fn heatmap(path: &Path, statistic: Statistic) -> Result<RgbImage, ReportError> {
    let table = ErrorTable::read_csv(path, statistic).or_report()?;
    let best = table.best();
    let statistic = statistic.name();
    Heatmap {
        title: format!(
            "{}: {statistic} slice error by family and fitted column",
            stem(path)
        ),
        x_label: "theta_d of the column k is fitted on (deg)".into(),
        x_values: table.theta_d_deg,
        row_labels: table.families,
        values: table.values,
        log_scale: true,
        value_label: format!("{statistic} abs. error (1/sr)"),
        highlight: best,
    }
    .draw()
    .or_report()
}

/// The database analysis of paper 5.1 (`specula analyze`) as a heatmap: one row per
/// sampling family, one column per theta_d of the column k is fitted on, coloured by the
/// mean slice error over `materials` materials in log false colour, the best cell outlined.
pub fn database_heatmap(
    summary: &DatabaseSummary,
    materials: usize,
    theta_h_samples: usize,
) -> Heatmap {
    let best = summary.best().and_then(|best| {
        let row = Family::ALL.iter().position(|f| *f == best.family)?;
        Some((row, best.theta_d_deg))
    });
    Heatmap {
        title: format!("Mean slice error over {materials} materials: k fitted on column theta_d, {theta_h_samples} samples"),
        x_label: "theta_d of the column k is fitted on (deg)".into(),
        x_values: (0..summary.mean[0].len()).map(|j| j as f64).collect(),
        row_labels: Family::ALL.iter().map(|f| f.name().to_string()).collect(),
        values: summary.mean.to_vec(),
        log_scale: true,
        value_label: "mean abs. error (1/sr)".into(),
        highlight: best,
    }
}

/// The file's name without its extension, as a figure's title.
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

    fn run_to(figure: Figure, out: PathBuf) -> Result<(u32, u32), ReportError> {
        plot(&PlotRequest {
            figure,
            out: out.clone(),
        })?;
        Ok(image::image_dimensions(&out).unwrap())
    }

    fn probe_figure(probe: PathBuf, adaptive: Adaptive) -> Figure {
        Figure::Probe {
            probe,
            adaptive,
            family: Family::Exponential,
            theta_h_samples: 30,
        }
    }

    fn slice() -> Figure {
        Figure::Slice {
            brdf: "chrome".into(),
            axis: ThetaHAxis::Linear,
            phi_d_deg: 90.0,
            phi_h_deg: 0.0,
        }
    }

    #[test]
    fn every_plot_is_drawn() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        assert!(run_to(slice(), d.join("slice.png")).unwrap().0 > 500);

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
        let figure = Figure::Samples {
            samples,
            axis: ThetaHAxis::Merl,
        };
        assert!(run_to(figure, d.join("samples.png")).unwrap().0 > 800);

        let probe = probe_csv(d);
        let fitted = PlotRequest {
            figure: probe_figure(probe.clone(), Adaptive::Fitted),
            out: d.join("p1.png"),
        };
        let k = plot(&fitted).unwrap().fitted.unwrap().function.k;
        assert!(k > 0.0 && k <= 100.0, "{k}");
        assert!(run_to(
            probe_figure(probe.clone(), Adaptive::K(4.78)),
            d.join("p2.png")
        )
        .is_ok());
        let adaptive = d.join("adaptive.csv");
        write(&adaptive, "theta_h\n0\n0.5\n3\n20\n90\n");
        let measured = probe_figure(probe, Adaptive::File(adaptive));
        assert_eq!(run_to(measured, d.join("p3.png")).unwrap(), (900, 860));

        let analysis = d.join("analysis.csv");
        let mut text = String::from("family,theta_d,mean_error,median_error,materials\n");
        for family in ["power", "exponential", "base"] {
            for j in 0..90 {
                text.push_str(&format!("{family},{j},{},{},5\n", 1.0 + j as f64, 2.0));
            }
        }
        write(&analysis, &text);
        let figure = Figure::Heatmap {
            analysis,
            statistic: Statistic::Mean,
        };
        assert!(run_to(figure, d.join("heatmap.png")).is_ok());
    }

    #[test]
    fn bad_inputs_name_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let missing = probe_figure(d.join("missing.csv"), Adaptive::Fitted);
        let err = run_to(missing, d.join("x.png")).unwrap_err();
        assert!(err.to_string().contains("missing.csv"), "{err}");
        let adaptive = d.join("adaptive.csv");
        write(&adaptive, "position\n1\n");
        let no_column = probe_figure(probe_csv(d), Adaptive::File(adaptive));
        let err = run_to(no_column, d.join("x.png")).unwrap_err();
        assert!(err.to_string().contains("no theta_h column"), "{err}");
        let err = run_to(slice(), d.join("slice.jpg")).unwrap_err();
        assert!(err.to_string().contains(".png"), "{err}");
        let far = probe_figure(probe_csv(d), Adaptive::Positions(vec![1.0, 91.0]));
        let err = run_to(far, d.join("x.png")).unwrap_err();
        assert_eq!(
            err.to_string(),
            "positions 91: expected degrees from 0 to 90"
        );
    }
}
