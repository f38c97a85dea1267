//! A labelled heatmap PNG of a grid of values: one row per label, one column per x value,
//! false colour (inferno) on a linear or logarithmic scale with a colour bar, cells without a
//! value in blue, and optionally one cell outlined (e.g. the best of the grid).
//! Used for the database analysis of paper 5.1 (families x theta_d columns).

use crate::canvas::Canvas;
use crate::color::{false_colour, UNMEASURED_BLUE};
use crate::error::VisualError;
use crate::font;
use image::RgbImage;
use plotters::prelude::*;
use std::path::Path;

/// What to draw.
#[derive(Debug, Clone)]
pub struct Heatmap {
    /// The title above the map.
    pub title: String,
    /// Caption of the x axis.
    pub x_label: String,
    /// The x value at the centre of each column, increasing and evenly spaced.
    pub x_values: Vec<f64>,
    /// One label per row, drawn top to bottom.
    pub row_labels: Vec<String>,
    /// `values[row][column]`; non-finite values are drawn as "no value".
    pub values: Vec<Vec<f64>>,
    /// Colour by `log10` of the value (values must then be positive to count).
    pub log_scale: bool,
    /// Caption of the colour bar.
    pub value_label: String,
    /// A cell `(row, column)` to outline.
    pub highlight: Option<(usize, usize)>,
}

/// Picture size in pixels.
const WIDTH: u32 = 1200;
const ROW_HEIGHT: u32 = 70;
const MARGINS_HEIGHT: u32 = 150;

impl Heatmap {
    /// The scale's value for a cell: the value or its logarithm; `None` when not drawable.
    fn scaled(&self, v: f64) -> Option<f64> {
        match (v.is_finite(), self.log_scale) {
            (false, _) => None,
            (true, true) if v > 0.0 => Some(v.log10()),
            (true, true) => None,
            (true, false) => Some(v),
        }
    }

    /// The range of the scaled values, widened when flat.
    fn range(&self) -> Option<(f64, f64)> {
        let scaled = self.values.iter().flatten().filter_map(|&v| self.scaled(v));
        let (lo, hi) = scaled.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
        if lo > hi {
            return None;
        }
        Some(if hi > lo {
            (lo, hi)
        } else {
            (lo - 0.5, hi + 0.5)
        })
    }

    fn check(&self) -> Result<(), VisualError> {
        let columns = self.x_values.len();
        if columns == 0 || self.row_labels.is_empty() {
            return Err(VisualError::Data(String::from(
                "a heatmap needs at least one row and one column",
            )));
        }
        if self.values.len() != self.row_labels.len()
            || self.values.iter().any(|r| r.len() != columns)
        {
            return Err(VisualError::Data(String::from(
                "a heatmap needs one value per row label and x value",
            )));
        }
        Ok(())
    }

    /// Draws the heatmap into an RGB image.
    pub fn draw(&self) -> Result<RgbImage, VisualError> {
        self.check()?;
        let height = MARGINS_HEIGHT + ROW_HEIGHT * self.row_labels.len() as u32;
        let mut out = RgbImage::from_pixel(WIDTH, height, image::Rgb([255, 255, 255]));
        font::ensure_registered();
        {
            let root = Canvas::with_buffer(out.as_mut(), (WIDTH, height)).into_drawing_area();
            self.draw_on(&root)
                .map_err(VisualError::draw("the heatmap"))?;
            root.present().map_err(VisualError::draw("the heatmap"))?;
        }
        Ok(out)
    }

    fn draw_on<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, plotters::coord::Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let (lo, hi) = self.range().unwrap_or((0.0, 1.0));
        let t_of = |v: f64| self.scaled(v).map(|s| (s - lo) / (hi - lo));
        let rows = self.row_labels.len();
        let xs = &self.x_values;
        let dx = if xs.len() > 1 {
            (xs[xs.len() - 1] - xs[0]) / (xs.len() - 1) as f64
        } else {
            1.0
        };
        let (x0, x1) = (xs[0] - dx / 2.0, xs[xs.len() - 1] + dx / 2.0);

        let (main, bar) = root.split_horizontally(WIDTH - 170);
        let labels = self.row_labels.clone();
        let mut chart = ChartBuilder::on(&main)
            .caption(&self.title, (font::FAMILY, 22))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(130)
            .build_cartesian_2d(x0..x1, 0f64..rows as f64)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(&self.x_label)
            .label_style((font::FAMILY, 15))
            .axis_desc_style((font::FAMILY, 16))
            .y_labels(rows * 2 + 1)
            .y_label_formatter(&|y: &f64| {
                // Label the centre of each row (row 0 at the top).
                let shifted = y - 0.5;
                let index = shifted.round();
                if (shifted - index).abs() < 1e-6 && index >= 0.0 && (index as usize) < labels.len()
                {
                    labels[rows - 1 - index as usize].clone()
                } else {
                    String::new()
                }
            })
            .draw()?;
        let cell = |row: usize, col: usize| {
            let x = xs[col];
            let y = (rows - 1 - row) as f64;
            [(x - dx / 2.0, y), (x + dx / 2.0, y + 1.0)]
        };
        chart.draw_series(self.values.iter().enumerate().flat_map(|(row, values)| {
            values.iter().enumerate().map(move |(col, &v)| {
                let [r, g, b] = t_of(v).map(false_colour).unwrap_or(UNMEASURED_BLUE);
                Rectangle::new(cell(row, col), RGBColor(r, g, b).filled())
            })
        }))?;
        if let Some((row, col)) = self.highlight.filter(|&(r, c)| r < rows && c < xs.len()) {
            chart.draw_series([Rectangle::new(cell(row, col), WHITE.stroke_width(3))])?;
            chart.draw_series([Rectangle::new(cell(row, col), BLACK.stroke_width(1))])?;
        }

        // The colour bar, in the values' own units.
        let mut bar_chart = ChartBuilder::on(&bar)
            .margin_top(50)
            .margin_bottom(57)
            .margin_right(10)
            .y_label_area_size(95)
            .build_cartesian_2d(0f64..1.0, lo..hi)?;
        let log = self.log_scale;
        bar_chart
            .configure_mesh()
            .disable_mesh()
            .disable_x_axis()
            .y_desc(&self.value_label)
            .label_style((font::FAMILY, 13))
            .axis_desc_style((font::FAMILY, 14))
            .y_label_formatter(&|v: &f64| {
                crate::plot::value_label(if log { 10f64.powf(*v) } else { *v })
            })
            .draw()?;
        let steps = 200;
        bar_chart.draw_series((0..steps).map(|i| {
            let a = lo + (hi - lo) * i as f64 / steps as f64;
            let b = lo + (hi - lo) * (i + 1) as f64 / steps as f64;
            let [r, g, bl] = false_colour((i as f64 + 0.5) / steps as f64);
            Rectangle::new([(0.0, a), (1.0, b)], RGBColor(r, g, bl).filled())
        }))?;
        Ok(())
    }

    /// Draws the heatmap and writes it as PNG; errors name the file.
    pub fn write_png(&self, path: &Path) -> Result<(), VisualError> {
        crate::linear_image::save_png(&self.draw()?, path)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Heatmap {
        Heatmap {
            title: "test".into(),
            x_label: "theta_d (deg)".into(),
            x_values: (0..10).map(f64::from).collect(),
            row_labels: vec!["a".into(), "b".into()],
            values: vec![
                (0..10).map(|i| 10f64.powi(i - 5)).collect(),
                (0..10)
                    .map(|i| if i == 3 { f64::NAN } else { 1.0 })
                    .collect(),
            ],
            log_scale: true,
            value_label: "error".into(),
            highlight: Some((0, 0)),
        }
    }

    fn contains(image: &RgbImage, colour: [u8; 3]) -> bool {
        image.pixels().any(|p| p.0 == colour)
    }

    #[test]
    fn extremes_and_missing_cells_get_their_colours() {
        let image = sample().draw().unwrap();
        assert_eq!(image.width(), WIDTH);
        assert_eq!(image.height(), MARGINS_HEIGHT + 2 * ROW_HEIGHT);
        assert!(contains(&image, false_colour(0.0)));
        assert!(contains(&image, false_colour(1.0)));
        assert!(contains(&image, UNMEASURED_BLUE));
        // The log scale puts 1.0 (10^0 between 10^-5 and 10^4) at 5/9 of the way.
        assert!(contains(&image, false_colour(5.0 / 9.0)));
    }

    #[test]
    fn writes_a_png_and_refuses_ragged_grids() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("h.png");
        sample().write_png(&path).unwrap();
        let back = image::open(&path).unwrap();
        assert_eq!(back.width(), WIDTH);
        let mut ragged = sample();
        ragged.values[1].pop();
        assert!(ragged.draw().is_err());
        let err = sample()
            .write_png(&dir.path().join("no/such/dir.png"))
            .unwrap_err();
        assert!(format!("{err:#}").contains("dir.png"));
    }
}
