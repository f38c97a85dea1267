//! The ranges every reply of a device must respect (`docs/driver-protocol.md`, "What
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
    pub fn check_positions(&self, p: &AxisPositions) -> Result<(), String> {
        for (i, value) in p.as_array().into_iter().enumerate() {
            if !value.is_finite() {
                return Err(format!("{} = {value} is not a finite angle", AXES[i]));
            }
            if let Some(axes) = &self.axes_rad {
                let (low, high) = axes[i];
                if !(low..=high).contains(&value) {
                    return Err(format!(
                        "{} = {} rad is outside the device model's range [{low:.4}, {high:.4}] rad",
                        AXES[i],
                        shown(value)
                    ));
                }
            }
        }
        Ok(())
    }

    /// Checks a `capture` reply to a request for `exposure_s`.
    pub fn check_capture(&self, c: &Capture, exposure_s: f64) -> Result<(), String> {
        if !(c.exposure_s.is_finite()
            && c.exposure_s > 0.0
            && c.exposure_s <= 2.0 * exposure_s
            && c.exposure_s >= 0.5 * exposure_s)
        {
            return Err(format!(
                "exposure_s = {} s, but {} s was asked (within a factor of 2 is accepted)",
                shown(c.exposure_s),
                shown(exposure_s)
            ));
        }
        if !(0.0..=1.0).contains(&c.light_level) {
            return Err(format!(
                "light_level = {} is outside [0, 1]",
                shown(c.light_level)
            ));
        }
        let white = self.white_level.unwrap_or(f64::INFINITY);
        for (i, &mean) in c.mean_raw.iter().enumerate() {
            if !(mean.is_finite() && (0.0..=white).contains(&mean)) {
                return Err(format!(
                    "mean_raw[{i}] = {} is outside [0, {}] (the white level)",
                    shown(mean),
                    shown(white)
                ));
            }
        }
        for (i, &fraction) in c.saturated_fraction.iter().enumerate() {
            if !(0.0..=1.0).contains(&fraction) {
                return Err(format!(
                    "saturated_fraction[{i}] = {} is outside [0, 1]",
                    shown(fraction)
                ));
            }
        }
        if c.pixel_count == 0 {
            return Err("pixel_count = 0: a capture has pixels".into());
        }
        if let Some(pixels) = &c.pixels {
            if pixels.len() != c.pixel_count as usize {
                return Err(format!(
                    "pixels holds {} pixels, pixel_count says {}",
                    pixels.len(),
                    c.pixel_count
                ));
            }
            let bad = pixels
                .iter()
                .flatten()
                .find(|&&v| !(v.is_finite() && (0.0..=white as f32).contains(&v)));
            if let Some(v) = bad {
                return Err(format!(
                    "a pixel value {} is outside [0, {}] (the white level)",
                    shown(f64::from(*v)),
                    shown(white)
                ));
            }
        }
        Ok(())
    }

    /// Checks an `info` reply.
    pub fn check_info(info: &InstrumentInfo) -> Result<(), String> {
        if !(1..=MAX_BIT_DEPTH).contains(&info.bit_depth) {
            return Err(format!(
                "bit_depth = {} is outside [1, {MAX_BIT_DEPTH}]",
                info.bit_depth
            ));
        }
        let largest = 2f64.powi(info.bit_depth as i32);
        if !(info.white_level > 0.0 && info.white_level <= largest) {
            return Err(format!(
                "white_level = {} is outside (0, {largest}] (2 to the bit depth)",
                shown(info.white_level)
            ));
        }
        if info.light_levels.is_empty()
            || info.light_levels.iter().any(|l| !(*l > 0.0 && *l <= 1.0))
        {
            return Err("light_levels must be fractions of full power in (0, 1]".into());
        }
        let (low, high) = info.exposure_range_s;
        if !(low > 0.0 && low <= high && high.is_finite()) {
            return Err(format!(
                "exposure_range_s = [{}, {}] is not a range of positive seconds",
                shown(low),
                shown(high)
            ));
        }
        Ok(())
    }
}
