//! Plots of BRDF data as PNG pictures (plotters, bitmap backend, embedded fonts):
//!
//! - [`slice`]: the characteristic slice theta_h x theta_d at phi_d = 90 deg in log false
//!   colour (paper Fig. 11), on MERL's square-root theta_h axis or a linear one;
//! - [`raw_samples`]: the raw samples of a measurement as a row of characteristic slices, one
//!   per phi_d, unmeasured cells in blue (paper Fig. 15);
//! - [`probe`]: the dense probe column against the adaptive samples, over the full theta_h
//!   range and the 0 to 2 deg detail (paper Fig. 13).

pub mod probe;
pub mod raw_samples;
pub mod slice;

use crate::canvas::Canvas;
use crate::color::false_colour;
use crate::error::{DrawCause, VisualError};
use crate::font;
use image::RgbImage;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use specula_core::merl;

/// Font sizes, pixels.
pub(crate) const TITLE_PX: f64 = 20.0;
pub(crate) const LABEL_PX: f64 = 14.0;
pub(crate) const AXIS_DESC_PX: f64 = 15.0;

/// A plotters error of drawing a plot.
pub(crate) fn plot_error(cause: DrawCause) -> VisualError {
    VisualError::Draw {
        what: "the plot".to_string(),
        cause,
    }
}

/// Draws on a white canvas of `width` x `height` pixels and returns the picture.
pub(crate) fn draw(
    width: u32,
    height: u32,
    paint: impl FnOnce(&DrawingArea<Canvas<'_>, Shift>) -> Result<(), VisualError>,
) -> Result<RgbImage, VisualError> {
    font::ensure_registered();
    let mut buffer = vec![255u8; (width * height * 3) as usize];
    {
        let root = Canvas::with_buffer(&mut buffer, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        paint(&root)?;
        root.present().map_err(plot_error)?;
    }
    RgbImage::from_raw(width, height, buffer).ok_or(VisualError::Buffer)
}

/// How theta_h runs along an axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ThetaHAxis {
    /// MERL's square-root mapping (paper eq. 1): the axis coordinate is `sqrt(90 theta_h)`,
    /// so the first degrees around the specular peak take a third of the axis.
    Merl,
    /// Degrees, evenly.
    Linear,
}

impl std::str::FromStr for ThetaHAxis {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "merl" | "sqrt" => Ok(ThetaHAxis::Merl),
            "linear" => Ok(ThetaHAxis::Linear),
            other => Err(format!(
                "unknown theta_h axis '{other}' (expected merl or linear)"
            )),
        }
    }
}

impl ThetaHAxis {
    /// The axis coordinate in `[0, 90]` of theta_h in degrees.
    pub fn coordinate(self, theta_h_deg: f64) -> f64 {
        match self {
            ThetaHAxis::Merl => merl::theta_h_coordinate(theta_h_deg),
            ThetaHAxis::Linear => theta_h_deg,
        }
    }

    /// theta_h in degrees at an axis coordinate.
    pub fn theta_h_deg(self, coordinate: f64) -> f64 {
        match self {
            ThetaHAxis::Merl => merl::theta_h_deg_at(coordinate),
            ThetaHAxis::Linear => coordinate,
        }
    }

    /// The axis description.
    pub(crate) fn description(self) -> &'static str {
        match self {
            ThetaHAxis::Merl => "θ_h [°] (MERL square-root axis)",
            ThetaHAxis::Linear => "θ_h [°]",
        }
    }

    /// The axis coordinates of its ticks, at round angles: on the square-root axis 0, 1, 2,
    /// 5, 10, 20, 40, 60 and 90 deg, so that the labels read as whole degrees.
    pub(crate) fn ticks(self) -> Vec<f64> {
        let degrees: &[f64] = match self {
            ThetaHAxis::Merl => &[0.0, 1.0, 2.0, 5.0, 10.0, 20.0, 40.0, 60.0, 90.0],
            ThetaHAxis::Linear => &[0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 90.0],
        };
        degrees.iter().map(|&d| self.coordinate(d)).collect()
    }
}

/// A theta_h axis over its coordinates 0 to 90 ([`ThetaHAxis::coordinate`]), ticked at
/// round angles ([`ThetaHAxis::ticks`]) rather than at round coordinates.
pub(crate) struct ThetaHCoord {
    axis: ThetaHAxis,
    coordinates: RangedCoordf64,
}

impl ThetaHCoord {
    pub(crate) fn new(axis: ThetaHAxis) -> Self {
        Self {
            axis,
            coordinates: (0.0..90.0).into(),
        }
    }
}

impl Ranged for ThetaHCoord {
    type FormatOption = plotters::coord::ranged1d::DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        self.coordinates.map(value, limit)
    }

    fn key_points<Hint: plotters::coord::ranged1d::KeyPointHint>(&self, _hint: Hint) -> Vec<f64> {
        self.axis.ticks()
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.coordinates.range()
    }
}

/// The axis description of theta_d.
pub(crate) const THETA_D_DESCRIPTION: &str = "θ_d [°]";
/// The axis description of f_r.
pub(crate) const F_R_DESCRIPTION: &str = "f_r [1/sr]";

/// Ticks of a logarithmic axis from `lo` to `hi` (both above 0): every power of ten over more
/// than four decades (every second or third over more than ten), 1, 2 and 5 times them over
/// two to four, and every whole multiple 1 to 9 below that, so that even a panel spanning
/// less than a decade has several labelled ticks.
pub(crate) fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let decades = (hi / lo).log10();
    let mantissas: &[f64] = if decades > 4.0 {
        &[1.0]
    } else if decades > 1.5 {
        &[1.0, 2.0, 5.0]
    } else {
        &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]
    };
    let every = (decades / 10.0).ceil().max(1.0) as i32;
    let (first, last) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    (first..=last)
        .filter(|e| e.rem_euclid(every) == 0)
        .flat_map(|e| mantissas.iter().map(move |m| m * 10f64.powi(e)))
        .filter(|v| (lo..=hi).contains(v))
        .collect()
}

/// A tick label for a value: as people write it (`100`, `0.002`, `1e-7`).
pub(crate) fn value_label(value: f64) -> String {
    // Ticks are round numbers; the rounding keeps 3 * 10^-3 from showing as 0.0030000000004.
    specula_core::shown::shown(specula_core::shown::plain(value).parse().unwrap_or(value))
}

/// A tick label for an angle: no decimals for whole degrees, one otherwise.
pub(crate) fn angle_label(deg: f64) -> String {
    let rounded = (deg * 10.0).round() / 10.0;
    if (rounded - rounded.round()).abs() < 1e-9 {
        format!("{}", rounded.round() as i64)
    } else {
        format!("{rounded:.1}")
    }
}

/// A logarithmic colour scale over `[10^min_log10, 10^max_log10]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LogScale {
    /// `log10` of the scale's smallest value.
    pub min_log10: f64,
    /// `log10` of the scale's largest value.
    pub max_log10: f64,
}

/// Most decades a colour scale spans below its maximum.
const MAX_DECADES: f64 = 8.0;

impl LogScale {
    /// The scale of some values: from the 1st percentile of the positive ones (at most
    /// 8 decades below the largest) to the largest. `None` when none is positive.
    pub fn of(values: impl Iterator<Item = f64>) -> Option<Self> {
        let mut positive: Vec<f64> = values.filter(|v| v.is_finite() && *v > 0.0).collect();
        if positive.is_empty() {
            return None;
        }
        positive.sort_by(f64::total_cmp);
        let max = positive[positive.len() - 1].log10();
        let low = positive[positive.len() / 100]
            .log10()
            .max(max - MAX_DECADES);
        let min = if max - low < 1e-6 { max - 1.0 } else { low };
        Some(Self {
            min_log10: min,
            max_log10: max,
        })
    }

    /// The false colour of a value (values at or below the minimum are black).
    pub fn colour(&self, value: f64) -> RGBColor {
        let t = if value > 0.0 {
            (value.log10() - self.min_log10) / (self.max_log10 - self.min_log10)
        } else {
            0.0
        };
        let [r, g, b] = false_colour(t);
        RGBColor(r, g, b)
    }
}

/// The blue of cells that were not measured.
pub(crate) fn unmeasured_colour() -> RGBColor {
    let [r, g, b] = crate::color::UNMEASURED_BLUE;
    RGBColor(r, g, b)
}

/// Draws a vertical colour bar for `scale` with power-of-ten ticks and a description.
pub(crate) fn draw_colour_bar(
    area: &DrawingArea<Canvas<'_>, Shift>,
    scale: LogScale,
    description: &str,
) -> Result<(), VisualError> {
    let mut chart = ChartBuilder::on(area)
        .margin_top(40)
        .margin_bottom(50)
        .margin_right(8)
        .y_label_area_size(58)
        .build_cartesian_2d(0.0..1.0, scale.min_log10..scale.max_log10)
        .map_err(plot_error)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_desc(description)
        .y_label_formatter(&|v| value_label(10f64.powi(v.round() as i32)))
        .y_labels(((scale.max_log10 - scale.min_log10).ceil() as usize + 1).min(10))
        .label_style((font::FAMILY, LABEL_PX))
        .axis_desc_style((font::FAMILY, AXIS_DESC_PX))
        .draw()
        .map_err(plot_error)?;
    let steps = 128;
    let span = scale.max_log10 - scale.min_log10;
    chart
        .draw_series((0..steps).map(|i| {
            let y0 = scale.min_log10 + span * i as f64 / steps as f64;
            let y1 = scale.min_log10 + span * (i + 1) as f64 / steps as f64;
            let mid = 10f64.powf(0.5 * (y0 + y1));
            Rectangle::new([(0.0, y0), (1.0, y1)], scale.colour(mid).filled())
        }))
        .map_err(plot_error)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merl_axis_round_trips_and_puts_one_degree_at_a_tenth() {
        let axis = ThetaHAxis::Merl;
        for d in [0.0, 0.3, 1.0, 40.0, 90.0] {
            assert!((axis.theta_h_deg(axis.coordinate(d)) - d).abs() < 1e-12);
        }
        // MERL's bin i covers coordinates [i, i + 1): theta_h = 1 deg is at sqrt(90) = 9.49.
        assert!((axis.coordinate(1.0) - 90f64.sqrt()).abs() < 1e-12);
        assert_eq!(angle_label(0.5), "0.5");
        assert_eq!(angle_label(20.0), "20");
        assert!("linear".parse::<ThetaHAxis>().is_ok() && "log".parse::<ThetaHAxis>().is_err());
    }

    #[test]
    fn theta_h_ticks_read_as_round_degrees() {
        for axis in [ThetaHAxis::Merl, ThetaHAxis::Linear] {
            let labels: Vec<String> = axis
                .ticks()
                .into_iter()
                .map(|c| angle_label(axis.theta_h_deg(c)))
                .collect();
            assert!(labels.iter().all(|l| !l.contains('.')), "{labels:?}");
            assert_eq!(labels.last().map(String::as_str), Some("90"));
        }
    }

    #[test]
    fn log_ticks_label_even_a_narrow_panel() {
        // The probe's 0 to 2 deg panel of silver-925: about 40 to 170 1/sr.
        let narrow = log_ticks(40.0, 170.0);
        assert!(narrow.len() >= 3, "{narrow:?}");
        assert_eq!(narrow.first(), Some(&40.0));
        let wide = log_ticks(1e-3, 200.0);
        assert_eq!(
            wide.iter().map(|&v| value_label(v)).collect::<Vec<_>>(),
            ["0.001", "0.01", "0.1", "1", "10", "100"]
        );
        let ratio = |t: &[f64]| t.windows(2).all(|w| w[1] > w[0]);
        assert!(ratio(&narrow) && ratio(&wide));
        assert!(log_ticks(1e-12, 1e6).len() <= 10);
        assert_eq!(value_label(3.0 * 10f64.powi(-3)), "0.003");
    }

    #[test]
    fn log_scale_spans_the_data_and_colours_monotonically() {
        let values = (0..1000).map(|i| 10f64.powf(-3.0 + 7.0 * i as f64 / 999.0));
        let scale = LogScale::of(values).unwrap();
        assert!((scale.max_log10 - 4.0).abs() < 1e-9);
        assert!(
            scale.min_log10 > -3.0 && scale.min_log10 < -2.8,
            "{scale:?}"
        );
        let brightness = |c: RGBColor| c.0 as u32 + c.1 as u32 + c.2 as u32;
        assert!(brightness(scale.colour(1e4)) > brightness(scale.colour(1.0)));
        assert!(brightness(scale.colour(1.0)) > brightness(scale.colour(1e-3)));
        assert!(LogScale::of([0.0, -1.0].into_iter()).is_none());
        let flat = LogScale::of([2.0, 2.0].into_iter()).unwrap();
        assert!(flat.max_log10 > flat.min_log10);
    }
}
