//! How long a measurement takes: axis moves, settling and the HDR capture at every sample
//! (paper 5.3: "multiple exposures and intensities of light are used, resulting in a
//! measurement time of 15 hours").
//!
//! A step from one position to the next costs
//! - the move: every axis follows a trapezoidal velocity profile (accelerate at `a`, cruise at
//!   `v`, decelerate at `a`; a triangle when the distance is too short to reach `v`); the axes
//!   move at the same time, so the move lasts as long as the slowest axis;
//! - settling: the longest settle time among the axes that moved;
//! - the capture, by the HDR scheme the measurement uses:
//!   - the device's fixed bracket: at each light level, a change of the LED current and one
//!     frame per exposure (exposure plus read-out), then a fixed overhead
//!     ([`crate::capture_bracket::CaptureBracket::duration_s`]);
//!   - predicted exposures ([`crate::hdr::HdrCapturer::choose`]): one frame at the exposure
//!     chosen from the sample's predicted brightness, plus a change of the LED current
//!     whenever the chosen level differs from the sample's before
//!     ([`predicted_capture_times_s`]).
//!
//! Axes that would move less than the device's accuracy do not move.

use crate::capture_bracket::CaptureBracket;
use crate::device::Device;
use crate::hdr::Exposure;
use crate::kinematics::AxisPositions;

/// The capture time of each sample measured with predicted exposures, in execution order,
/// seconds: the chosen exposure plus the read-out of `capture`, plus its light change where
/// the level differs from the sample's before (the first sample sets the light).
pub fn predicted_capture_times_s(exposures: &[Exposure], capture: &CaptureBracket) -> Vec<f64> {
    let mut level: Option<f64> = None;
    exposures
        .iter()
        .map(|e| {
            let change_s = if level == Some(e.light_level) {
                0.0
            } else {
                capture.light_change_s
            };
            level = Some(e.light_level);
            change_s + e.exposure_s + capture.readout_s
        })
        .collect()
}

/// The motion of one axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisMotion {
    /// Top speed, radians per second.
    pub speed_rad_s: f64,
    /// Acceleration and deceleration, radians per second squared.
    pub accel_rad_s2: f64,
    /// Wait after a move, seconds.
    pub settle_s: f64,
}

impl AxisMotion {
    /// Duration of a move over `distance_rad` (sign ignored) with the trapezoidal profile:
    /// `d / v + v / a` when `d >= v^2 / a` (the axis reaches its top speed), else
    /// `2 sqrt(d / a)`.
    pub fn move_time_s(&self, distance_rad: f64) -> f64 {
        let d = distance_rad.abs();
        let (v, a) = (self.speed_rad_s, self.accel_rad_s2);
        if d >= v * v / a {
            d / v + v / a
        } else {
            2.0 * (d / a).sqrt()
        }
    }
}

/// The time of a measurement step: move, settle, capture.
#[derive(Debug, Clone, PartialEq)]
pub struct TimeModel {
    /// Turntable, camera, light azimuth, light elevation (the order of
    /// [`AxisPositions::as_array`]).
    pub axes: [AxisMotion; 4],
    /// Moves shorter than this are not made (the device's accuracy), radians.
    pub deadband_rad: f64,
    /// The capture at every sample, seconds.
    pub capture_s: f64,
    /// Where the device starts.
    pub park: AxisPositions,
}

/// The parts of one step's time, seconds.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StepTime {
    /// Moving the axes (the slowest axis's trapezoidal profile).
    pub move_s: f64,
    /// Settling after the move.
    pub settle_s: f64,
    /// The capture.
    pub capture_s: f64,
}

impl StepTime {
    pub(crate) fn total_s(&self) -> f64 {
        self.move_s + self.settle_s + self.capture_s
    }
}

impl TimeModel {
    /// The device's axis motions, accuracy, fixed HDR bracket and park position.
    pub fn from_device(device: &Device) -> Self {
        let motion = |axis: &crate::device::Axis| AxisMotion {
            speed_rad_s: axis.speed_deg_s.to_radians(),
            accel_rad_s2: axis.accel_deg_s2.to_radians(),
            settle_s: axis.settle_s,
        };
        Self {
            axes: device.axes().map(motion),
            deadband_rad: device.accuracy_deg.to_radians(),
            capture_s: device.capture.duration_s(),
            park: device.park_axes(),
        }
    }

    /// Move plus settle from `from` to `to`, seconds: what ordering can change.
    pub fn transition_s(&self, from: &AxisPositions, to: &AxisPositions) -> f64 {
        let step = self.step(from, to);
        step.move_s + step.settle_s
    }

    /// The time of one step: move from `from` to `to`, settle, capture.
    pub fn step(&self, from: &AxisPositions, to: &AxisPositions) -> StepTime {
        let mut step = StepTime {
            capture_s: self.capture_s,
            ..StepTime::default()
        };
        for ((motion, a), b) in self.axes.iter().zip(from.as_array()).zip(to.as_array()) {
            let distance = (b - a).abs();
            if distance > self.deadband_rad {
                step.move_s = step.move_s.max(motion.move_time_s(distance));
                step.settle_s = step.settle_s.max(motion.settle_s);
            }
        }
        step
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn axis() -> AxisMotion {
        AxisMotion {
            speed_rad_s: 2.0,
            accel_rad_s2: 4.0,
            settle_s: 0.5,
        }
    }

    /// The time-optimal profile under both limits is `v(t) = min(a t, v_max, a (T - t))`.
    /// Integrate it numerically for the distance it covers in `T`, and bisect on `T`.
    fn simulated_move_time_s(m: &AxisMotion, distance: f64) -> f64 {
        let covered = |total: f64| {
            let n = 20_000;
            let dt = total / n as f64;
            (0..n)
                .map(|i| {
                    let t = (i as f64 + 0.5) * dt;
                    let v = (m.accel_rad_s2 * t)
                        .min(m.speed_rad_s)
                        .min(m.accel_rad_s2 * (total - t));
                    v * dt
                })
                .sum::<f64>()
        };
        let (mut lo, mut hi) = (0.0, 100.0);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if covered(mid) < distance {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }

    #[test]
    fn trapezoid_matches_integration() {
        let m = axis();
        // v^2 / a = 1 rad: below it a triangle, above a trapezoid.
        for d in [0.05, 0.5, 1.0, 2.5, 6.0] {
            let exact = m.move_time_s(d);
            let sim = simulated_move_time_s(&m, d);
            assert!((exact - sim).abs() < 1e-6, "d {d}: {exact} vs {sim}");
        }
    }

    proptest! {
        #[test]
        fn move_time_is_continuous_and_increasing(d in 0.0..10.0f64, extra in 0.0..1.0f64) {
            let m = axis();
            prop_assert!(m.move_time_s(d) <= m.move_time_s(d + extra) + 1e-12);
            let knee = m.speed_rad_s * m.speed_rad_s / m.accel_rad_s2;
            let below = m.move_time_s(knee * (1.0 - 1e-12));
            prop_assert!((below - m.move_time_s(knee)).abs() < 1e-6);
        }
    }

    #[test]
    fn axes_move_in_parallel_and_settle_by_the_slowest_moved_axis() {
        let device = Device::utia();
        let model = TimeModel::from_device(&device);
        let from = AxisPositions::from_degrees(0.0, 0.0, 0.0, 10.0);
        let to = AxisPositions::from_degrees(90.0, 0.0, 0.0, 20.0);
        let step = model.step(&from, &to);
        let turntable = model.axes[0].move_time_s(90f64.to_radians());
        let light = model.axes[3].move_time_s(10f64.to_radians());
        assert!((step.move_s - turntable.max(light)).abs() < 1e-12);
        let settle = device
            .turntable
            .settle_s
            .max(device.light.elevation.settle_s);
        assert_eq!(step.settle_s, settle);
        assert_eq!(step.capture_s, device.capture.duration_s());
        assert!((model.transition_s(&from, &to) - step.move_s - step.settle_s).abs() < 1e-12);

        // A move below the accuracy is no move: no time, no settling.
        let tiny = AxisPositions::from_degrees(0.01, 0.0, 0.0, 10.0);
        assert_eq!(model.transition_s(&from, &tiny), 0.0);
    }

    #[test]
    fn predicted_captures_pay_a_frame_each_and_a_light_change_only_when_it_changes() {
        let bracket = CaptureBracket {
            exposures_s: vec![1.0],
            light_levels: vec![1.0],
            readout_s: 0.3,
            light_change_s: 0.5,
            overhead_s: 9.0,
        };
        let at = |light_level, exposure_s| Exposure {
            light_level,
            exposure_s,
        };
        let times = predicted_capture_times_s(
            &[at(1.0, 0.01), at(1.0, 0.2), at(0.1, 0.05), at(1.0, 0.01)],
            &bracket,
        );
        let expected = [0.5 + 0.31, 0.5, 0.5 + 0.35, 0.5 + 0.31];
        for (t, e) in times.iter().zip(expected) {
            assert!((t - e).abs() < 1e-12, "{times:?}");
        }
    }

    #[test]
    fn capture_duration_counts_every_frame() {
        let bracket = CaptureBracket {
            exposures_s: vec![0.01, 0.1],
            light_levels: vec![1.0, 0.1, 0.01],
            readout_s: 0.3,
            light_change_s: 0.5,
            overhead_s: 1.0,
        };
        // 3 levels x (0.5 + 0.31 + 0.4) + 1.0
        assert!((bracket.duration_s() - (3.0 * 1.21 + 1.0)).abs() < 1e-12);
    }
}
