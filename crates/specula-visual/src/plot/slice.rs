//! The characteristic slice (paper section 5.1, Fig. 11): f_r over theta_h x theta_d at a fixed
//! phi_d (90 deg, the slice holding "the most descriptive information"), in log false colour.

use super::{
    angle_label, draw, draw_colour_bar, plot_error, unmeasured_colour, LogScale, ThetaHAxis,
    ThetaHCoord, AXIS_DESC_PX, LABEL_PX, THETA_D_DESCRIPTION, TITLE_PX,
};
use crate::error::VisualError;
use crate::font;
use image::RgbImage;
use plotters::prelude::*;
use specula_core::brdf::Brdf;
use specula_core::geometry::HalfDiff;
use specula_core::merl::{theta_h_centre_deg, THETA_D_BINS, THETA_H_BINS};

/// Where the slice is taken and how theta_h is laid out.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SliceOptions {
    /// How theta_h runs along the horizontal axis.
    pub axis: ThetaHAxis,
    /// The fixed phi_d, degrees (the characteristic slice: 90).
    pub phi_d_deg: f64,
    /// The half vector's azimuth, degrees (matters only for anisotropic materials).
    pub phi_h_deg: f64,
}

impl Default for SliceOptions {
    fn default() -> Self {
        Self {
            axis: ThetaHAxis::Merl,
            phi_d_deg: 90.0,
            phi_h_deg: 0.0,
        }
    }
}

/// The slice's values: row `i` (theta_h) by column `j` (theta_d, `j + 0.5` deg), the mean of
/// R, G and B in 1/sr, `None` where not measured. Row `i` is theta_h at MERL's bin centre
/// `(i + 0.5)^2 / 90` deg on the MERL axis, at `i + 0.5` deg on the linear one.
pub fn slice_values(brdf: &dyn Brdf, options: &SliceOptions) -> Vec<Vec<Option<f64>>> {
    (0..THETA_H_BINS)
        .map(|i| {
            let theta_h_deg = match options.axis {
                ThetaHAxis::Merl => theta_h_centre_deg(i),
                ThetaHAxis::Linear => i as f64 + 0.5,
            };
            (0..THETA_D_BINS)
                .map(|j| {
                    let hd = HalfDiff::from_degrees(
                        theta_h_deg,
                        options.phi_h_deg,
                        j as f64 + 0.5,
                        options.phi_d_deg,
                    );
                    brdf.eval_half_diff(hd)
                        .map(|v| v.element_sum() / 3.0)
                        .filter(|v| v.is_finite())
                })
                .collect()
        })
        .collect()
}

/// The slice of `brdf` as a picture (theta_d across, theta_h up, colour bar at the right).
pub fn plot_slice(
    brdf: &dyn Brdf,
    title: &str,
    options: &SliceOptions,
) -> Result<RgbImage, VisualError> {
    let values = slice_values(brdf, options);
    let Some(scale) = LogScale::of(values.iter().flatten().flatten().copied()) else {
        return Err(VisualError::Data(format!(
            "{title}: the slice has no positive value to show"
        )));
    };
    draw_slice(
        &values,
        scale,
        title,
        "f_r, mean of R, G, B [1/sr]",
        options,
    )
}

/// The slices of a measured BRDF and of its truth on one colour scale (the scale of both
/// together), and the slice of their absolute difference |measured - truth| on the same
/// scale, so that the three compare by eye: where the difference is as bright as the truth,
/// the error is 100 %. Cells either leaves unmeasured are unmeasured in the difference.
pub fn plot_slices_against_truth(
    measured: (&dyn Brdf, &str),
    truth: (&dyn Brdf, &str),
    options: &SliceOptions,
) -> Result<[RgbImage; 3], VisualError> {
    let a = slice_values(measured.0, options);
    let b = slice_values(truth.0, options);
    let difference: Vec<Vec<Option<f64>>> = a
        .iter()
        .zip(&b)
        .map(|(ra, rb)| {
            ra.iter()
                .zip(rb)
                .map(|(x, y)| Some((x.as_ref()? - y.as_ref()?).abs()))
                .collect()
        })
        .collect();
    let all = a.iter().chain(&b).flatten().flatten().copied();
    let Some(scale) = LogScale::of(all) else {
        return Err(VisualError::Data(format!(
            "{}: the slices have no positive value to show",
            measured.1
        )));
    };
    let label = "f_r, mean of R, G, B [1/sr]";
    Ok([
        draw_slice(&a, scale, measured.1, label, options)?,
        draw_slice(&b, scale, truth.1, label, options)?,
        draw_slice(
            &difference,
            scale,
            &format!("|{} - {}|", measured.1, truth.1),
            "|difference| of f_r [1/sr]",
            options,
        )?,
    ])
}

/// The relative standard uncertainty (k = 1) of a table on its slice, in per cent: per cell
/// the mean over R, G and B of `uncertainty` (1/sr, a table's `OUT.uncertainty.binary`)
/// over the mean of `table`, `None` where either has no value or the table's is not
/// positive.
pub fn relative_uncertainty_values(
    table: &dyn Brdf,
    uncertainty: &dyn Brdf,
    options: &SliceOptions,
) -> Vec<Vec<Option<f64>>> {
    let values = slice_values(table, options);
    let uncertainties = slice_values(uncertainty, options);
    values
        .iter()
        .zip(&uncertainties)
        .map(|(row, u_row)| {
            row.iter()
                .zip(u_row)
                .map(|(v, u)| {
                    let (v, u) = ((*v)?, (*u)?);
                    (v > 0.0 && u >= 0.0).then(|| 100.0 * u / v)
                })
                .collect()
        })
        .collect()
}

/// The map of a table's relative standard uncertainty (k = 1, per cent) on its slice
/// ([`relative_uncertainty_values`]), in log false colour beside the table's own slice.
pub fn plot_relative_uncertainty_slice(
    table: &dyn Brdf,
    uncertainty: &dyn Brdf,
    title: &str,
    options: &SliceOptions,
) -> Result<RgbImage, VisualError> {
    let values = relative_uncertainty_values(table, uncertainty, options);
    let Some(scale) = LogScale::of(values.iter().flatten().flatten().copied()) else {
        return Err(VisualError::Data(format!(
            "{title}: the slice has no uncertainty to show"
        )));
    };
    draw_slice(
        &values,
        scale,
        title,
        "relative standard uncertainty (k = 1) [%]",
        options,
    )
}

/// A slice's values drawn on `scale`.
fn draw_slice(
    values: &[Vec<Option<f64>>],
    scale: LogScale,
    title: &str,
    scale_label: &str,
    options: &SliceOptions,
) -> Result<RgbImage, VisualError> {
    draw(760, 600, |root| {
        let (left, right) = root.split_horizontally(630);
        let mut chart = ChartBuilder::on(&left)
            .caption(
                format!("{title}: φ_d = {}°", angle_label(options.phi_d_deg)),
                (font::FAMILY, TITLE_PX),
            )
            .margin(12)
            .x_label_area_size(44)
            .y_label_area_size(56)
            .build_cartesian_2d(0.0..THETA_D_BINS as f64, ThetaHCoord::new(options.axis))
            .map_err(plot_error)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(THETA_D_DESCRIPTION)
            .x_label_formatter(&|d| angle_label(*d))
            .y_desc(options.axis.description())
            .y_label_formatter(&|c| angle_label(options.axis.theta_h_deg(*c)))
            .label_style((font::FAMILY, LABEL_PX))
            .axis_desc_style((font::FAMILY, AXIS_DESC_PX))
            .draw()
            .map_err(plot_error)?;
        chart
            .draw_series(values.iter().enumerate().flat_map(|(i, row)| {
                row.iter().enumerate().map(move |(j, v)| {
                    let colour = v.map_or_else(unmeasured_colour, |v| scale.colour(v));
                    let (x, y) = (j as f64, i as f64);
                    Rectangle::new([(x, y), (x + 1.0, y + 1.0)], colour.filled())
                })
            }))
            .map_err(plot_error)?;
        draw_colour_bar(&right, scale, scale_label)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;
    use specula_core::brdf::Rgb;

    /// Bright where theta_h is small, not measured for theta_d above 80 deg.
    struct Peak;
    impl Brdf for Peak {
        fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
            self.eval_half_diff(HalfDiff::from_directions(wi, wo))
        }
        fn eval_half_diff(&self, hd: HalfDiff) -> Option<Rgb> {
            (hd.theta_d.to_degrees() < 80.0)
                .then(|| Rgb::splat(1e3 * (-hd.theta_h.to_degrees()).exp() + 0.01))
        }
        fn name(&self) -> String {
            "peak".into()
        }
    }

    /// 2 % of [`Peak`] where it has a value.
    struct TwoPerCent;
    impl Brdf for TwoPerCent {
        fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
            self.eval_half_diff(HalfDiff::from_directions(wi, wo))
        }
        fn eval_half_diff(&self, hd: HalfDiff) -> Option<Rgb> {
            Peak.eval_half_diff(hd).map(|v| v * 0.02)
        }
        fn name(&self) -> String {
            "u".into()
        }
    }

    #[test]
    fn the_relative_uncertainty_is_in_per_cent_and_unmeasured_where_the_table_is() {
        let options = SliceOptions::default();
        let values = relative_uncertainty_values(&Peak, &TwoPerCent, &options);
        assert!(
            (values[3][10].unwrap() - 2.0).abs() < 1e-9,
            "{:?}",
            values[3][10]
        );
        assert_eq!(values[3][85], None);
        let picture = plot_relative_uncertainty_slice(&Peak, &TwoPerCent, "u", &options).unwrap();
        assert!(picture.width() > 0);
    }

    #[test]
    fn values_follow_the_axis_and_holes_stay_holes() {
        let merl = slice_values(&Peak, &SliceOptions::default());
        assert_eq!((merl.len(), merl[0].len()), (90, 90));
        let expected = 1e3 * (-theta_h_centre_deg(3)).exp() + 0.01;
        assert!((merl[3][10].unwrap() - expected).abs() < 1e-9 * expected);
        assert_eq!(merl[3][85], None);
        let linear = slice_values(
            &Peak,
            &SliceOptions {
                axis: ThetaHAxis::Linear,
                ..SliceOptions::default()
            },
        );
        assert!((linear[3][10].unwrap() - (1e3 * (-3.5f64).exp() + 0.01)).abs() < 1e-9);
    }

    #[test]
    fn the_picture_shows_the_peak_bright_and_the_holes_blue() {
        let image = plot_slice(&Peak, "peak", &SliceOptions::default()).unwrap();
        assert_eq!(image.dimensions(), (760, 600));
        let blue = image
            .pixels()
            .filter(|p| p.0 == crate::color::UNMEASURED_BLUE)
            .count();
        // theta_d 80 to 90 deg is a ninth of the slice's area of about 550 x 500 pixels.
        assert!(blue > 20_000, "{blue} blue pixels");
        let bright = image
            .pixels()
            .filter(|p| p.0[0] > 240 && p.0[1] > 200 && p.0[2] < 200)
            .count();
        assert!(bright > 500, "{bright} bright pixels");
    }
}
