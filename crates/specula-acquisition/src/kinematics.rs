//! Kinematics of the goniometer: axis angles to the light and camera directions in the sample
//! frame, and back, with every alternative position (paper 4.1: "in most cases, an
//! alternative positioning of the arms exists").
//!
//! Lab frame: z up along the turntable axis (the sample's normal once aligned). The camera arm
//! turns about the lab y axis, so the camera looks from `c = Ry(camera) z =
//! (sin camera, 0, cos camera)`. The light arm turns by its azimuth about z and tilts by its
//! elevation about the horizontal axis `e = Rz(azimuth) y`, so the light sits at
//! `L = Rz(azimuth) Ry(elevation) z`. The turntable turns the sample about z: a sample-frame
//! direction `w` appears in the lab as `Rz(turntable) w`.
//!
//! For a pair `(wi, wo)` there are, within the axis ranges:
//! - two camera sides: turntable `-phi_o` with camera `+theta_o`, or turntable `pi - phi_o`
//!   with camera `-theta_o` (the arm on the other side of the zenith, the sample turned by
//!   pi);
//! - for each, two light arm poses: `(phi_L, +theta_L)` or `(phi_L + pi, -theta_L)` (the arm
//!   tilted over the zenith, its pivot on the other side);
//! - every whole turn of an axis that its range allows.
//!
//! The poses are identical for the measurement but not for the occlusion tests: the arms lie
//! elsewhere.

use crate::device::{Axis, Device};
use glam::DVec3;
use serde::{Deserialize, Serialize};
use specula_core::geometry::{rotate_y, rotate_z};
use std::f64::consts::{PI, TAU};

/// The angles of the four axes, radians.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AxisPositions {
    /// Turntable angle: the sample's x axis is turned by this about the lab z axis.
    pub turntable_rad: f64,
    /// Camera arm angle from the zenith about the lab y axis; negative on the other side.
    pub camera_rad: f64,
    /// Light arm azimuth about the lab z axis.
    pub light_azimuth_rad: f64,
    /// Light arm elevation (angle from the zenith) about its horizontal axis.
    pub light_elevation_rad: f64,
}

/// Names of the axes in the order of [`AxisPositions::as_array`].
pub const AXIS_NAMES: [&str; 4] = ["turntable", "camera", "light_azimuth", "light_elevation"];

impl AxisPositions {
    /// Axis positions from the four angles, radians.
    pub fn new(
        turntable_rad: f64,
        camera_rad: f64,
        light_azimuth_rad: f64,
        light_elevation_rad: f64,
    ) -> Self {
        Self {
            turntable_rad,
            camera_rad,
            light_azimuth_rad,
            light_elevation_rad,
        }
    }

    /// Axis angles given in degrees.
    pub fn from_degrees(
        turntable_deg: f64,
        camera_deg: f64,
        light_azimuth_deg: f64,
        light_elevation_deg: f64,
    ) -> Self {
        Self::new(
            turntable_deg.to_radians(),
            camera_deg.to_radians(),
            light_azimuth_deg.to_radians(),
            light_elevation_deg.to_radians(),
        )
    }

    /// `[turntable, camera, light_azimuth, light_elevation]`, radians.
    pub fn as_array(&self) -> [f64; 4] {
        [
            self.turntable_rad,
            self.camera_rad,
            self.light_azimuth_rad,
            self.light_elevation_rad,
        ]
    }

    /// `[turntable, camera, light_azimuth, light_elevation]`, degrees.
    pub fn to_degrees(&self) -> [f64; 4] {
        self.as_array().map(f64::to_degrees)
    }

    /// The camera's direction in the lab frame.
    pub fn camera_direction(&self) -> DVec3 {
        rotate_y(DVec3::Z, self.camera_rad)
    }

    /// The light's direction in the lab frame.
    pub fn light_direction(&self) -> DVec3 {
        rotate_z(
            rotate_y(DVec3::Z, self.light_elevation_rad),
            self.light_azimuth_rad,
        )
    }

    /// The light arm's elevation axis in the lab frame (horizontal).
    pub fn light_axis(&self) -> DVec3 {
        rotate_z(DVec3::Y, self.light_azimuth_rad)
    }

    /// Forward kinematics: `(wi, wo)`, the light's and the camera's directions in the sample
    /// frame.
    pub fn directions(&self) -> (DVec3, DVec3) {
        let to_sample = |lab: DVec3| rotate_z(lab, -self.turntable_rad);
        (
            to_sample(self.light_direction()),
            to_sample(self.camera_direction()),
        )
    }
}

/// The camera arm's rotation axis in the lab frame.
pub const CAMERA_AXIS: DVec3 = DVec3::Y;

/// Inverse kinematics: every axis position within the device's ranges that puts the light at
/// `wi` and the camera at `wo` (sample frame, need not be normalised). Empty when none is
/// reachable. The order is fixed: camera on the +x side first, then the other side; within a
/// side, the light arm untilted first.
pub fn solutions(device: &Device, wi: DVec3, wo: DVec3) -> Vec<AxisPositions> {
    let (wi, wo) = (wi.normalize(), wo.normalize());
    let (theta_o, phi_o) = polar_azimuth(wo);
    let mut found = Vec::new();
    for (turntable_base, camera_rad) in [(-phi_o, theta_o), (PI - phi_o, -theta_o)] {
        if !in_range(camera_rad, &device.camera.axis) {
            continue;
        }
        for turntable_rad in turns_in_range(turntable_base, &device.turntable) {
            let light_lab = rotate_z(wi, turntable_rad);
            let (theta_l, phi_l) = polar_azimuth(light_lab);
            for (azimuth_base, elevation_rad) in [(phi_l, theta_l), (phi_l + PI, -theta_l)] {
                if !in_range(elevation_rad, &device.light.elevation) {
                    continue;
                }
                for azimuth_rad in turns_in_range(azimuth_base, &device.light.azimuth) {
                    found.push(AxisPositions::new(
                        turntable_rad,
                        camera_rad,
                        azimuth_rad,
                        elevation_rad,
                    ));
                }
            }
        }
    }
    found
}

/// Polar angle from +z and azimuth of a unit vector, radians; the azimuth of the pole is 0.
fn polar_azimuth(w: DVec3) -> (f64, f64) {
    let horizontal = w.x.hypot(w.y);
    (horizontal.atan2(w.z), w.y.atan2(w.x))
}

const LIMIT_EPS_RAD: f64 = 1e-9;

fn in_range(angle_rad: f64, axis: &Axis) -> bool {
    angle_rad >= axis.min_deg.to_radians() - LIMIT_EPS_RAD
        && angle_rad <= axis.max_deg.to_radians() + LIMIT_EPS_RAD
}

/// `angle + n * 2 pi` for every whole number `n` that lands within the axis range, ascending.
fn turns_in_range(angle_rad: f64, axis: &Axis) -> impl Iterator<Item = f64> {
    let min = axis.min_deg.to_radians() - LIMIT_EPS_RAD;
    let max = axis.max_deg.to_radians() + LIMIT_EPS_RAD;
    let first = ((min - angle_rad) / TAU).ceil() as i64;
    let last = ((max - angle_rad) / TAU).floor() as i64;
    (first..=last)
        .map(move |n| angle_rad + n as f64 * TAU)
        // Snap an angle a hair outside the range onto its limit.
        .map(move |a| a.clamp(min + LIMIT_EPS_RAD, max - LIMIT_EPS_RAD))
}

/// The device's axes as [`AxisPositions`] (here, so that the device description does not
/// depend on the kinematics).
impl Device {
    /// The park position as axis angles.
    pub fn park_axes(&self) -> AxisPositions {
        let p = self.park;
        AxisPositions::from_degrees(
            p.turntable_deg,
            p.camera_deg,
            p.light_azimuth_deg,
            p.light_elevation_deg,
        )
    }

    /// True when every axis angle lies within its range (to within a nano-radian, so that a
    /// grid point exactly at a limit counts as reachable).
    pub fn within_limits(&self, axes: &AxisPositions) -> bool {
        const EPS_RAD: f64 = 1e-9;
        self.axes()
            .iter()
            .zip(axes.as_array())
            .all(|(axis, angle_rad)| {
                angle_rad >= axis.min_deg.to_radians() - EPS_RAD
                    && angle_rad <= axis.max_deg.to_radians() + EPS_RAD
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use specula_core::geometry::Spherical;
    use specula_core::HalfDiff;

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-9
    }

    fn same_axes(a: &AxisPositions, b: &AxisPositions) -> bool {
        a.as_array()
            .iter()
            .zip(b.as_array())
            .all(|(x, y)| (x - y).abs() < 1e-9)
    }

    #[test]
    fn mirror_configuration() {
        // Camera 30 deg towards +x, light 30 deg towards -x: the specular (mirror) pair.
        let axes = AxisPositions::from_degrees(0.0, 30.0, 180.0, 30.0);
        let (wi, wo) = axes.directions();
        assert!(close(wo, Spherical::from_degrees(30.0, 0.0).to_vector()));
        assert!(close(wi, Spherical::from_degrees(30.0, 180.0).to_vector()));
        let hd = HalfDiff::from_directions(wi, wo);
        assert!(hd.theta_h.abs() < 1e-9);
        assert!((hd.theta_d.to_degrees() - 30.0).abs() < 1e-9);
    }

    #[test]
    fn turntable_turns_the_sample_not_the_arms() {
        // Turning the turntable by +90 deg makes the camera, fixed in the lab on +x, see the
        // sample from its -y side.
        let axes = AxisPositions::from_degrees(90.0, 40.0, 0.0, 0.0);
        let (_, wo) = axes.directions();
        assert!(close(wo, Spherical::from_degrees(40.0, 270.0).to_vector()));
    }

    #[test]
    fn four_alternatives_for_a_general_pair() {
        let device = Device::utia();
        let wi = Spherical::from_degrees(50.0, 200.0).to_vector();
        let wo = Spherical::from_degrees(35.0, 10.0).to_vector();
        let all = solutions(&device, wi, wo);
        assert_eq!(all.len(), 4, "{all:?}");
        assert!(all[0].camera_rad > 0.0 && all[2].camera_rad < 0.0);
        assert!(all[0].light_elevation_rad > 0.0 && all[1].light_elevation_rad < 0.0);
        for axes in &all {
            let (a, b) = axes.directions();
            assert!(close(a, wi) && close(b, wo));
        }
    }

    #[test]
    fn out_of_range_pairs_have_no_solution() {
        let device = Device::utia();
        let high = Spherical::from_degrees(80.0, 0.0).to_vector();
        let low = Spherical::from_degrees(20.0, 90.0).to_vector();
        assert!(
            solutions(&device, high, low).is_empty(),
            "light beyond 75 deg"
        );
        assert!(
            solutions(&device, low, high).is_empty(),
            "camera beyond 75 deg"
        );
        let below = Spherical::from_degrees(100.0, 0.0).to_vector();
        assert!(
            solutions(&device, low, below).is_empty(),
            "camera below the surface"
        );
    }

    #[test]
    fn whole_turns_are_alternatives_where_the_range_allows() {
        let mut device = Device::utia();
        device.turntable.min_deg = -270.0;
        device.turntable.max_deg = 270.0;
        let wi = Spherical::from_degrees(30.0, 100.0).to_vector();
        let wo = Spherical::from_degrees(30.0, 30.0).to_vector();
        let all = solutions(&device, wi, wo);
        // Turntable -30 (and +330, out of range), 150 (and -210): two turns for the second
        // side, one for the first: three turntable angles, two light poses each.
        assert_eq!(all.len(), 6, "{all:?}");
        for axes in &all {
            assert!(device.within_limits(axes));
            let (a, b) = axes.directions();
            assert!(close(a, wi) && close(b, wo));
        }
    }

    fn axes_in_range() -> impl Strategy<Value = AxisPositions> {
        (
            -179.9..179.9f64,
            -75.0..75.0f64,
            -179.9..179.9f64,
            -75.0..75.0f64,
        )
            .prop_map(|(t, c, a, e)| AxisPositions::from_degrees(t, c, a, e))
    }

    proptest! {
        #[test]
        fn axes_round_trip(axes in axes_in_range()) {
            // At the zenith an azimuth is arbitrary; keep away from it.
            prop_assume!(axes.camera_rad.abs() > 1e-3 && axes.light_elevation_rad.abs() > 1e-3);
            let device = Device::utia();
            let (wi, wo) = axes.directions();
            let all = solutions(&device, wi, wo);
            prop_assert!(all.iter().any(|s| same_axes(s, &axes)), "{axes:?} not in {all:?}");
            prop_assert_eq!(all.len(), 4);
        }

        #[test]
        fn every_solution_reproduces_the_directions(
            ti in 0.0..75.0f64, pi_ in 0.0..360.0f64, to in 0.0..75.0f64, po in 0.0..360.0f64,
        ) {
            let device = Device::utia();
            let wi = Spherical::from_degrees(ti, pi_).to_vector();
            let wo = Spherical::from_degrees(to, po).to_vector();
            let all = solutions(&device, wi, wo);
            prop_assert!(!all.is_empty());
            for axes in &all {
                prop_assert!(device.within_limits(axes));
                let (a, b) = axes.directions();
                prop_assert!(close(a, wi) && close(b, wo), "{axes:?}: {a} {b} vs {wi} {wo}");
            }
        }
    }

    #[test]
    fn limits_are_inclusive() {
        let d = Device::utia();
        let at_limit = AxisPositions::from_degrees(0.0, 75.0, 0.0, -75.0);
        assert!(d.within_limits(&at_limit));
        let beyond = AxisPositions::from_degrees(0.0, 75.01, 0.0, 0.0);
        assert!(!d.within_limits(&beyond));
    }
}
