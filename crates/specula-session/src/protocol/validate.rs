//! The ranges every reply of a device must respect (`docs/book/src/driver-protocol.md`, "What
//! Specula checks"). A reply outside them is a device fault: the client asks again on a
//! fresh link and, if the device keeps answering so, fails with an error naming the device,
//! the method and the field. A bad reply never becomes a stored sample.

use specula_acquisition::device::Device;
use specula_acquisition::instrument::{Capture, InstrumentInfo};
use specula_acquisition::kinematics::AxisPositions;
use specula_core::shown::shown;

/// The names of [`AxisPositions`]'s fields, in the order of [`AxisPositions::as_array`].
const AXES: [&str; 4] = [
    "turntable_rad",
    "camera_rad",
    "light_azimuth_rad",
    "light_elevation_rad",
];

/// The largest sensor bit depth accepted.
const MAX_BIT_DEPTH: u32 = 32;

/// How far a read-back position may lie outside the device model's range: the positioning
/// accuracy ten times over, at least 1 degree.
fn margin_rad(device: &Device) -> f64 {
    (10.0 * device.accuracy_deg).max(1.0).to_radians()
}

/// What replies are checked against: the device model's axis ranges (when known) and the
/// white level of the device's `info` (once it has answered).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ReplyRanges {
    /// Lowest and highest read-back angle of each axis, radians, margin included.
    pub axes_rad: Option<[(f64, f64); 4]>,
    /// The sensor's largest raw value.
    pub white_level: Option<f64>,
}

/// What is wrong with a device's reply: the field, its value and the range it must lie in.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReplyProblem {
    /// A position is NaN or infinite.
    #[error("{axis} = {value} is not a finite angle")]
    NotFinite {
        /// The field of [`AxisPositions`].
        axis: &'static str,
        /// The value read back, radians.
        value: f64,
    },
    /// A position lies outside the device model's range of that axis.
    #[error(
        "{axis} = {} rad is outside the device model's range [{low_rad:.4}, {high_rad:.4}] rad",
        shown(*.value_rad)
    )]
    Position {
        /// The field of [`AxisPositions`].
        axis: &'static str,
        /// The value read back, radians.
        value_rad: f64,
        /// The lowest accepted angle, radians.
        low_rad: f64,
        /// The highest accepted angle, radians.
        high_rad: f64,
    },
    /// The exposure is not within a factor of 2 of the one asked for.
    #[error(
        "exposure_s = {} s, but {} s was asked (within a factor of 2 is accepted)",
        shown(*.got_s),
        shown(*.asked_s)
    )]
    Exposure {
        /// The exposure the device reports, seconds.
        got_s: f64,
        /// The exposure asked for, seconds.
        asked_s: f64,
    },
    /// The light level is not a fraction in [0, 1].
    #[error("light_level = {} is outside [0, 1]", shown(*.0))]
    LightLevel(f64),
    /// A channel's mean raw value is outside [0, white level].
    #[error(
        "mean_raw[{channel}] = {} is outside [0, {}] (the white level)",
        shown(*.mean),
        shown(*.white)
    )]
    MeanRaw {
        /// The channel (0 red, 1 green, 2 blue).
        channel: usize,
        /// The mean raw value.
        mean: f64,
        /// The white level (infinite before `info` answered).
        white: f64,
    },
    /// A channel's saturated fraction is not in [0, 1].
    #[error("saturated_fraction[{channel}] = {} is outside [0, 1]", shown(*.fraction))]
    SaturatedFraction {
        /// The channel (0 red, 1 green, 2 blue).
        channel: usize,
        /// The fraction reported.
        fraction: f64,
    },
    /// The capture says it has no pixels.
    #[error("pixel_count = 0: a capture has pixels")]
    NoPixels,
    /// The pixels sent are not as many as `pixel_count` says.
    #[error("pixels holds {sent} pixels, pixel_count says {count}")]
    PixelCount {
        /// The pixels sent.
        sent: usize,
        /// The `pixel_count` field.
        count: u32,
    },
    /// A pixel value is outside [0, white level].
    #[error(
        "a pixel value {} is outside [0, {}] (the white level)",
        shown(f64::from(*.value)),
        shown(*.white)
    )]
    Pixel {
        /// The pixel value.
        value: f32,
        /// The white level (infinite before `info` answered).
        white: f64,
    },
    /// The bit depth is outside [1, 32].
    #[error("bit_depth = {0} is outside [1, {MAX_BIT_DEPTH}]")]
    BitDepth(u32),
    /// The white level is outside (0, 2 to the bit depth].
    #[error("white_level = {} is outside (0, {largest}] (2 to the bit depth)", shown(*.white_level))]
    WhiteLevel {
        /// The white level reported.
        white_level: f64,
        /// 2 to the bit depth.
        largest: f64,
    },
    /// The light levels are missing or not fractions of full power.
    #[error("light_levels must be fractions of full power in (0, 1]")]
    LightLevels,
    /// The exposure range is not a range of positive seconds.
    #[error(
        "exposure_range_s = [{}, {}] is not a range of positive seconds",
        shown(*.low_s),
        shown(*.high_s)
    )]
    ExposureRange {
        /// The shortest exposure, seconds.
        low_s: f64,
        /// The longest exposure, seconds.
        high_s: f64,
    },
}

impl ReplyRanges {
    /// The ranges of a device model (its axes, with a margin of its accuracy).
    pub fn for_device(device: &Device) -> Self {
        let margin = margin_rad(device);
        let axes = device.axes().map(|a| {
            (
                a.min_deg.to_radians() - margin,
                a.max_deg.to_radians() + margin,
            )
        });
        Self {
            axes_rad: Some(axes),
            white_level: None,
        }
    }

    /// Checks the positions of a `home` or `move_to` reply.
    pub fn check_positions(&self, p: &AxisPositions) -> Result<(), ReplyProblem> {
        for (i, value) in p.as_array().into_iter().enumerate() {
            if !value.is_finite() {
                return Err(ReplyProblem::NotFinite {
                    axis: AXES[i],
                    value,
                });
            }
            if let Some(axes) = &self.axes_rad {
                let (low_rad, high_rad) = axes[i];
                if !(low_rad..=high_rad).contains(&value) {
                    return Err(ReplyProblem::Position {
                        axis: AXES[i],
                        value_rad: value,
                        low_rad,
                        high_rad,
                    });
                }
            }
        }
        Ok(())
    }

    /// Checks a `capture` reply to a request for `exposure_s`.
    pub fn check_capture(&self, c: &Capture, exposure_s: f64) -> Result<(), ReplyProblem> {
        if !(c.exposure_s.is_finite()
            && c.exposure_s > 0.0
            && c.exposure_s <= 2.0 * exposure_s
            && c.exposure_s >= 0.5 * exposure_s)
        {
            return Err(ReplyProblem::Exposure {
                got_s: c.exposure_s,
                asked_s: exposure_s,
            });
        }
        if !(0.0..=1.0).contains(&c.light_level) {
            return Err(ReplyProblem::LightLevel(c.light_level));
        }
        let white = self.white_level.unwrap_or(f64::INFINITY);
        for (i, &mean) in c.mean_raw.iter().enumerate() {
            if !(mean.is_finite() && (0.0..=white).contains(&mean)) {
                return Err(ReplyProblem::MeanRaw {
                    channel: i,
                    mean,
                    white,
                });
            }
        }
        for (i, &fraction) in c.saturated_fraction.iter().enumerate() {
            if !(0.0..=1.0).contains(&fraction) {
                return Err(ReplyProblem::SaturatedFraction {
                    channel: i,
                    fraction,
                });
            }
        }
        if c.pixel_count == 0 {
            return Err(ReplyProblem::NoPixels);
        }
        if let Some(pixels) = &c.pixels {
            if pixels.len() != c.pixel_count as usize {
                return Err(ReplyProblem::PixelCount {
                    sent: pixels.len(),
                    count: c.pixel_count,
                });
            }
            let bad = pixels
                .iter()
                .flatten()
                .find(|&&v| !(v.is_finite() && (0.0..=white as f32).contains(&v)));
            if let Some(v) = bad {
                return Err(ReplyProblem::Pixel { value: *v, white });
            }
        }
        Ok(())
    }

    /// Checks an `info` reply.
    pub fn check_info(info: &InstrumentInfo) -> Result<(), ReplyProblem> {
        if !(1..=MAX_BIT_DEPTH).contains(&info.bit_depth) {
            return Err(ReplyProblem::BitDepth(info.bit_depth));
        }
        let largest = 2f64.powi(info.bit_depth as i32);
        if !(info.white_level > 0.0 && info.white_level <= largest) {
            return Err(ReplyProblem::WhiteLevel {
                white_level: info.white_level,
                largest,
            });
        }
        if info.light_levels.is_empty()
            || info.light_levels.iter().any(|l| !(*l > 0.0 && *l <= 1.0))
        {
            return Err(ReplyProblem::LightLevels);
        }
        let (low, high) = info.exposure_range_s;
        if !(low > 0.0 && low <= high && high.is_finite()) {
            return Err(ReplyProblem::ExposureRange {
                low_s: low,
                high_s: high,
            });
        }
        Ok(())
    }
}
