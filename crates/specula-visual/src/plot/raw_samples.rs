//! The raw samples of a measurement (paper Fig. 15): one characteristic slice theta_h x theta_d
//! per measured phi_d, each cell of the plan's grid coloured by its sample in log false colour,
//! and blue where the plan has a cell but no sample was measured (occlusion, the device's
//! reach), as the paper shows the areas later extrapolated.

use super::{
    angle_label, draw, draw_colour_bar, plot_error, unmeasured_colour, LogScale, ThetaHAxis,
    ThetaHCoord, AXIS_DESC_PX, LABEL_PX, THETA_D_DESCRIPTION, TITLE_PX,
};
use crate::error::VisualError;
use crate::font;
use image::RgbImage;
use plotters::prelude::*;
use specula_core::Sample;
use std::collections::BTreeMap;

/// Per cell `(theta_h index, theta_d index)` of one panel: the sum of values and their count.
type CellSums = BTreeMap<(usize, usize), (f64, usize)>;

/// Most panels (distinct phi_d) one picture shows.
pub const MAX_PANELS: usize = 24;
/// Panels in a row.
const COLUMNS: usize = 4;

/// Positions are grouped to this resolution, degrees.
const RESOLUTION_DEG: f64 = 1e-4;

fn key(deg: f64) -> i64 {
    (deg / RESOLUTION_DEG).round() as i64
}

fn degrees(key: i64) -> f64 {
    key as f64 * RESOLUTION_DEG
}

/// The samples arranged on the plan's grid: the distinct theta_h and theta_d of all samples,
/// and per phi_d (folded into `[0, 180)` by reciprocity) the mean value of each measured cell.
#[derive(Debug, Clone, PartialEq)]
pub struct SampleGrid {
    /// The distinct theta_h of the samples, deg, ascending.
    pub theta_h_deg: Vec<f64>,
    /// The distinct theta_d of the samples, deg, ascending.
    pub theta_d_deg: Vec<f64>,
    /// `(phi_d_deg, cells)`, `cells[i][j]` for theta_h `i`, theta_d `j`: the mean of R, G, B
    /// in 1/sr, `None` where the plan has no sample.
    pub panels: Vec<(f64, Vec<Vec<Option<f64>>>)>,
}

impl SampleGrid {
    /// The samples' grid (phi_h is dropped: an isotropic BRDF); an error when there are none
    /// or one lies outside theta_h, theta_d in `[0, 90]` degrees.
    pub fn new(samples: &[Sample]) -> Result<Self, VisualError> {
        if samples.is_empty() {
            return Err(VisualError::Data(String::from("no samples to plot")));
        }
        if let Some(s) = samples.iter().find(|s| {
            ![s.theta_h_deg(), s.theta_d_deg(), s.phi_d_deg()]
                .iter()
                .all(|v| v.is_finite())
                || !(0.0..=90.0).contains(&s.theta_h_deg())
                || !(0.0..=90.0).contains(&s.theta_d_deg())
        }) {
            return Err(VisualError::Data(format!(
                "a sample lies outside theta_h, theta_d in [0, 90] deg: {} {} {}",
                s.theta_h_deg(),
                s.theta_d_deg(),
                s.phi_d_deg()
            )));
        }
        let mut theta_h: Vec<i64> = samples.iter().map(|s| key(s.theta_h_deg())).collect();
        let mut theta_d: Vec<i64> = samples.iter().map(|s| key(s.theta_d_deg())).collect();
        for v in [&mut theta_h, &mut theta_d] {
            v.sort_unstable();
            v.dedup();
        }
        let mut sums: BTreeMap<i64, CellSums> = BTreeMap::new();
        for s in samples {
            let phi_d = key(s.phi_d_deg().rem_euclid(180.0)) % key(180.0);
            let i = theta_h
                .binary_search(&key(s.theta_h_deg()))
                .unwrap_or_default();
            let j = theta_d
                .binary_search(&key(s.theta_d_deg()))
                .unwrap_or_default();
            let cell = sums
                .entry(phi_d)
                .or_default()
                .entry((i, j))
                .or_insert((0.0, 0));
            cell.0 += s.value.element_sum() / 3.0;
            cell.1 += 1;
        }
        if sums.len() > MAX_PANELS {
            return Err(VisualError::Data(format!(
                "{} distinct phi_d values: the raw-sample plot shows one panel per phi_d, at most {MAX_PANELS}",
                sums.len()
            )));
        }
        let panels = sums
            .into_iter()
            .map(|(phi_d, cells)| {
                let mut grid = vec![vec![None; theta_d.len()]; theta_h.len()];
                for ((i, j), (sum, n)) in cells {
                    grid[i][j] = Some(sum / n as f64);
                }
                (degrees(phi_d), grid)
            })
            .collect();
        Ok(Self {
            theta_h_deg: theta_h.into_iter().map(degrees).collect(),
            theta_d_deg: theta_d.into_iter().map(degrees).collect(),
            panels,
        })
    }

    /// Cells with a sample, and all cells of the plan's grid over every panel.
    pub fn coverage(&self) -> (usize, usize) {
        let measured = self
            .panels
            .iter()
            .flat_map(|(_, g)| g.iter().flatten())
            .filter(|v| v.is_some())
            .count();
        (
            measured,
            self.panels.len() * self.theta_h_deg.len() * self.theta_d_deg.len(),
        )
    }
}

/// The cell edges around sorted positions: midpoints between neighbours, the outer edges half
/// a spacing out (within `[lo, hi]`); one position gets a cell of 1 either side.
fn edges(positions: &[f64], lo: f64, hi: f64) -> Vec<f64> {
    let n = positions.len();
    let mut e = Vec::with_capacity(n + 1);
    if n == 1 {
        return vec![(positions[0] - 1.0).max(lo), (positions[0] + 1.0).min(hi)];
    }
    e.push((positions[0] - 0.5 * (positions[1] - positions[0])).max(lo));
    for w in positions.windows(2) {
        e.push(0.5 * (w[0] + w[1]));
    }
    e.push((positions[n - 1] + 0.5 * (positions[n - 1] - positions[n - 2])).min(hi));
    e
}

/// The raw samples as one picture: a panel per phi_d, a shared colour bar.
pub fn plot_raw_samples(
    samples: &[Sample],
    title: &str,
    axis: ThetaHAxis,
) -> Result<RgbImage, VisualError> {
    let grid = SampleGrid::new(samples)?;
    let Some(scale) = LogScale::of(
        grid.panels
            .iter()
            .flat_map(|(_, g)| g.iter().flatten().flatten().copied()),
    ) else {
        return Err(VisualError::Data(format!(
            "{title}: no positive sample value to show"
        )));
    };
    let h_coordinates: Vec<f64> = grid
        .theta_h_deg
        .iter()
        .map(|d| axis.coordinate(*d))
        .collect();
    let h_edges = edges(&h_coordinates, 0.0, 90.0);
    let d_edges = edges(&grid.theta_d_deg, 0.0, 90.0);
    let columns = grid.panels.len().min(COLUMNS);
    let rows = grid.panels.len().div_ceil(COLUMNS);
    let (panel_w, panel_h, bar_w, title_h) = (300u32, 300u32, 120u32, 40u32);
    let width = columns as u32 * panel_w + bar_w;
    let height = rows as u32 * panel_h + title_h;
    let (measured, cells) = grid.coverage();
    draw(width, height, |root| {
        let (top, body) = root.split_vertically(title_h);
        top.titled(
            &format!("{title}: {measured} of {cells} planned cells measured (blue: not measured)"),
            (font::FAMILY, TITLE_PX),
        )
        .map_err(plot_error)?;
        let (panels_area, bar) = body.split_horizontally(columns as u32 * panel_w);
        let areas = panels_area.split_evenly((rows, columns));
        for ((phi_d, cells), area) in grid.panels.iter().zip(&areas) {
            let mut chart = ChartBuilder::on(area)
                .caption(
                    format!("φ_d = {}°", angle_label(*phi_d)),
                    (font::FAMILY, LABEL_PX + 2.0),
                )
                .margin(6)
                .x_label_area_size(38)
                .y_label_area_size(44)
                .build_cartesian_2d(0.0..90.0, ThetaHCoord::new(axis))
                .map_err(plot_error)?;
            chart
                .configure_mesh()
                .disable_mesh()
                .x_desc(THETA_D_DESCRIPTION)
                .x_label_formatter(&|d| angle_label(*d))
                .y_desc(axis.description())
                .x_labels(4)
                .y_label_formatter(&|c| angle_label(axis.theta_h_deg(*c)))
                .label_style((font::FAMILY, LABEL_PX - 2.0))
                .axis_desc_style((font::FAMILY, AXIS_DESC_PX - 2.0))
                .draw()
                .map_err(plot_error)?;
            chart
                .draw_series(cells.iter().enumerate().flat_map(|(i, row)| {
                    let (y0, y1) = (h_edges[i], h_edges[i + 1]);
                    let d_edges = &d_edges;
                    row.iter().enumerate().map(move |(j, v)| {
                        let colour = v.map_or_else(unmeasured_colour, |v| scale.colour(v));
                        Rectangle::new([(d_edges[j], y0), (d_edges[j + 1], y1)], colour.filled())
                    })
                }))
                .map_err(plot_error)?;
        }
        draw_colour_bar(&bar, scale, "f_r, mean of R, G, B [1/sr]")
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::{HalfDiff, Rgb};

    fn plan(phi_d: f64, skip_high_theta_d: bool) -> Vec<Sample> {
        let mut out = Vec::new();
        for i in 0..30 {
            let theta_h = 90.0 * ((4.78 * i as f64 / 29.0).exp() - 1.0) / (4.78f64.exp() - 1.0);
            for j in 0..30 {
                let theta_d = 3.0 * j as f64;
                if skip_high_theta_d && theta_d > 70.0 {
                    continue;
                }
                out.push(Sample::new(
                    HalfDiff::from_degrees(theta_h, 0.0, theta_d, phi_d),
                    Rgb::splat(100.0 * (-theta_h).exp() + 0.01),
                ));
            }
        }
        out
    }

    #[test]
    fn grid_groups_by_phi_d_and_marks_missing_cells() {
        let mut samples = plan(0.0, false);
        samples.extend(plan(90.0, true));
        // phi_d 270 is phi_d 90 by reciprocity.
        samples.extend(plan(270.0, true).into_iter().take(3));
        let grid = SampleGrid::new(&samples).unwrap();
        assert_eq!(grid.theta_h_deg.len(), 30);
        assert_eq!(grid.theta_d_deg.len(), 30);
        assert_eq!(grid.panels.len(), 2);
        assert_eq!(grid.panels[1].0, 90.0);
        assert_eq!(grid.coverage(), (900 + 30 * 24, 1800));
        assert_eq!(grid.panels[1].1[0][29], None);
        assert!(grid.panels[0].1[0][29].is_some());
    }

    #[test]
    fn edges_split_between_positions() {
        assert_eq!(edges(&[0.0, 2.0, 6.0], 0.0, 90.0), vec![0.0, 1.0, 4.0, 8.0]);
        assert_eq!(edges(&[45.0], 0.0, 90.0), vec![44.0, 46.0]);
    }

    #[test]
    fn picture_has_a_panel_per_phi_d_and_blue_for_the_unmeasured() {
        let mut samples = plan(0.0, false);
        samples.extend(plan(45.0, true));
        let image = plot_raw_samples(&samples, "test", ThetaHAxis::Merl).unwrap();
        assert_eq!(image.dimensions(), (2 * 300 + 120, 300 + 40));
        let blue = image
            .pixels()
            .filter(|p| p.0 == crate::color::UNMEASURED_BLUE)
            .count();
        assert!(blue > 1000, "{blue}");
        let bad = [Sample::new(
            HalfDiff::from_degrees(95.0, 0.0, 1.0, 0.0),
            Rgb::ONE,
        )];
        assert!(plot_raw_samples(&bad, "bad", ThetaHAxis::Merl).is_err());
    }
}
