//! The probe against the adaptive samples (paper section 5.2, Fig. 13): f_r along theta_h at
//! theta_d = 40, phi_d = 90, phi_h = 45 deg from the dense square-root probe (solid lines)
//! and at the adaptive positions (dashed lines with markers), over the full theta_h range and
//! over the 0 to 2 deg around the specular peak. Each channel is drawn in its colour, on a
//! logarithmic f_r axis.

use super::Canvas;
use super::{
    angle_label, draw, log_ticks, plot_error, value_label, ThetaHAxis, AXIS_DESC_PX,
    F_R_DESCRIPTION, LABEL_PX, TITLE_PX,
};
use crate::error::VisualError;
use crate::font;
use image::RgbImage;
use plotters::prelude::*;
use specula_core::brdf::Rgb;
use specula_core::ProbePoint;

/// The theta_h range of the detail panel, degrees.
pub const DETAIL_MAX_DEG: f64 = 2.0;

/// The probe's values at `positions_deg` by linear interpolation in theta_h (clamped to the
/// probe's ends): what a measurement at the adaptive positions would read, when only the
/// probe is known. `probe` must be sorted by theta_h.
pub fn interpolate(probe: &[ProbePoint], positions_deg: &[f64]) -> Vec<ProbePoint> {
    positions_deg
        .iter()
        .map(|&t| {
            let at = probe.partition_point(|p| p.theta_h_deg < t);
            let value = match at {
                0 => probe.first().map_or(Rgb::ZERO, |p| p.value),
                n if n >= probe.len() => probe.last().map_or(Rgb::ZERO, |p| p.value),
                n => {
                    let (p0, p1) = (probe[n - 1], probe[n]);
                    let (t0, t1) = (p0.theta_h_deg, p1.theta_h_deg);
                    let w = if t1 > t0 { (t - t0) / (t1 - t0) } else { 0.0 };
                    p0.value + (p1.value - p0.value) * w
                }
            };
            ProbePoint::new(t, value)
        })
        .collect()
}

fn check_sorted(name: &str, points: &[ProbePoint]) -> Result<(), VisualError> {
    if points.is_empty() {
        return Err(VisualError::Data(format!("the {name} has no values")));
    }
    if points
        .windows(2)
        .any(|w| w[1].theta_h_deg < w[0].theta_h_deg)
    {
        return Err(VisualError::Data(format!(
            "the {name}'s theta_h values must increase"
        )));
    }
    if let Some(p) = points
        .iter()
        .find(|p| !p.theta_h_deg.is_finite() || !p.value.is_finite())
    {
        return Err(VisualError::Data(format!(
            "the {name} has a non-finite entry at theta_h {}: {}",
            p.theta_h_deg, p.value
        )));
    }
    Ok(())
}

/// Both panels in one picture (full range above, detail below).
pub fn plot_probe(
    probe: &[ProbePoint],
    adaptive: &[ProbePoint],
    title: &str,
) -> Result<RgbImage, VisualError> {
    check_sorted("probe", probe)?;
    check_sorted("adaptive sampling", adaptive)?;
    draw(900, 860, |root| {
        let (top, bottom) = root.split_vertically(430);
        let full_max = probe
            .last()
            .map_or(90.0, |p| p.theta_h_deg)
            .max(adaptive.last().map_or(0.0, |p| p.theta_h_deg));
        panel(
            &top,
            &format!(
                "{title}: probe ({} samples) against adaptive ({} samples)",
                probe.len(),
                adaptive.len()
            ),
            probe,
            adaptive,
            full_max.max(DETAIL_MAX_DEG),
        )?;
        panel(
            &bottom,
            "detail: θ_h 0° to 2°",
            probe,
            adaptive,
            DETAIL_MAX_DEG,
        )
    })
}

fn panel(
    area: &DrawingArea<Canvas<'_>, plotters::coord::Shift>,
    caption: &str,
    probe: &[ProbePoint],
    adaptive: &[ProbePoint],
    max_deg: f64,
) -> Result<(), VisualError> {
    // The points up to the panel's edge, the lines ending there at the interpolated value.
    let within = |points: &[ProbePoint]| -> Vec<ProbePoint> {
        let end = points.partition_point(|p| p.theta_h_deg <= max_deg);
        let mut kept = points[..end].to_vec();
        if end > 0 && end < points.len() {
            kept.extend(interpolate(points, &[max_deg]));
        }
        kept
    };
    let markers: Vec<ProbePoint> = adaptive
        .iter()
        .copied()
        .filter(|p| p.theta_h_deg <= max_deg)
        .collect();
    let (probe, adaptive) = (within(probe), within(adaptive));
    let positive = probe
        .iter()
        .chain(&adaptive)
        .flat_map(|p| p.value.to_array())
        .filter(|v| *v > 0.0);
    let (lo, hi) = positive.fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if hi <= 0.0 {
        return Err(VisualError::Data(format!(
            "no positive f_r to plot below theta_h = {max_deg} deg"
        )));
    }
    let (lo, hi) = (lo * 0.5, hi * 2.0);
    let mut chart = ChartBuilder::on(area)
        .caption(caption, (font::FAMILY, TITLE_PX - 2.0))
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(70)
        .build_cartesian_2d(
            0.0..max_deg,
            (lo..hi).log_scale().with_key_points(log_ticks(lo, hi)),
        )
        .map_err(plot_error)?;
    chart
        .configure_mesh()
        .x_desc(ThetaHAxis::Linear.description())
        .y_desc(F_R_DESCRIPTION)
        .x_label_formatter(&|t| angle_label(*t))
        .y_label_formatter(&|v| value_label(*v))
        .label_style((font::FAMILY, LABEL_PX))
        .axis_desc_style((font::FAMILY, AXIS_DESC_PX))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()
        .map_err(plot_error)?;
    let channels = [
        ("R", RGBColor(205, 40, 40)),
        ("G", RGBColor(30, 150, 50)),
        ("B", RGBColor(40, 70, 210)),
    ];
    let clamp = |v: f64| v.max(lo);
    for (c, &(name, colour)) in channels.iter().enumerate() {
        chart
            .draw_series(LineSeries::new(
                probe.iter().map(|p| (p.theta_h_deg, clamp(p.value[c]))),
                colour.stroke_width(2),
            ))
            .map_err(plot_error)?
            .label(format!("{name}, probe"))
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
            });
        let points: Vec<(f64, f64)> = adaptive
            .iter()
            .map(|p| (p.theta_h_deg, clamp(p.value[c])))
            .collect();
        chart
            .draw_series(DashedLineSeries::new(
                points.clone(),
                8,
                5,
                colour.mix(0.9).stroke_width(2),
            ))
            .map_err(plot_error)?
            .label(format!("{name}, adaptive"))
            .legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + Circle::new((10, 0), 3, colour.filled())
                    + PathElement::new(vec![(0, 0), (6, 0)], colour.stroke_width(2))
                    + PathElement::new(vec![(14, 0), (20, 0)], colour.stroke_width(2))
            });
        chart
            .draw_series(
                markers
                    .iter()
                    .map(|p| Circle::new((p.theta_h_deg, clamp(p.value[c])), 3, colour.filled())),
            )
            .map_err(plot_error)?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .label_font((font::FAMILY, LABEL_PX))
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(180, 180, 180))
        .draw()
        .map_err(plot_error)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn probe() -> Vec<ProbePoint> {
        (0..90)
            .map(|i| {
                let t = (i as f64).powi(2) / 90.0;
                ProbePoint::new(
                    t,
                    Rgb::new(1e3, 8e2, 6e2) * (-3.0 * t).exp() + Rgb::splat(0.02),
                )
            })
            .collect()
    }

    #[test]
    fn interpolation_hits_the_probe_and_lies_between_neighbours() {
        let p = probe();
        let at = interpolate(
            &p,
            &[
                p[5].theta_h_deg,
                0.5 * (p[5].theta_h_deg + p[6].theta_h_deg),
                200.0,
                -1.0,
            ],
        );
        assert_eq!(at[0].value, p[5].value);
        assert!((at[1].value - 0.5 * (p[5].value + p[6].value)).length() < 1e-9);
        assert_eq!(at[2].value, p[89].value);
        assert_eq!(at[3].value, p[0].value);
    }

    #[test]
    fn the_picture_has_both_panels_and_refuses_bad_input() {
        let p = probe();
        let positions: Vec<f64> = (0..30)
            .map(|i| 90.0 * ((4.78 * i as f64 / 29.0).exp() - 1.0) / (4.78f64.exp() - 1.0))
            .collect();
        let adaptive = interpolate(&p, &positions);
        let image = plot_probe(&p, &adaptive, "test").unwrap();
        assert_eq!(image.dimensions(), (900, 860));
        // The red channel's lines are drawn in both halves.
        let red = |y0: u32, y1: u32| {
            (y0..y1)
                .flat_map(|y| (0..900).map(move |x| (x, y)))
                .filter(|(x, y)| image.get_pixel(*x, *y).0 == [205, 40, 40])
                .count()
        };
        assert!(
            red(0, 430) > 200 && red(430, 860) > 200,
            "{} {}",
            red(0, 430),
            red(430, 860)
        );
        let mut unsorted = p.clone();
        unsorted.swap(3, 4);
        assert!(plot_probe(&unsorted, &adaptive, "x").is_err());
        assert!(plot_probe(&p, &[], "x").is_err());
    }
}
