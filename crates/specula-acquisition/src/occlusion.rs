//! Occlusion: does the light or its arm stand in the camera's view of the sample, does the
//! camera or its arm stand in the light's beam, or would the arms collide (paper 4.1: "an
//! occlusion of view of the camera by the arm with the light source may occur, it can be
//! analytically detected").
//!
//! The model (docs/book/src/plan.md): every solid part of an arm is a capsule, a
//! segment thickened by a radius, placed in the lab frame by the axis angles (see
//! [`crate::device::Part`]). The camera's view is a cone from the measured area (radius
//! `sample_radius_m`) to the lens front (`end_radius_m` at `end_distance_m`); the light's beam
//! is a cone from the sample to the light's exit aperture. A position is blocked when a light
//! part enters the view cone, a camera part enters the beam cone, or a light part and a camera
//! part overlap. The turntable does not matter: it turns only the sample, which is small
//! next to the arms, and the axis ranges already keep the arms above the sample stage.
//!
//! The arms stop where the positioning accuracy puts them, not exactly where they were sent.
//! A plan therefore asks [`blockage_within_accuracy`]: every part is thickened by the farthest
//! an error of [`ACCURACY_SIGMAS`] times the device's accuracy on every axis can move it
//! relative to the other arm, so that a position the plan keeps is free wherever within that
//! error the arms stop. [`blockage`] is the exact test at the axes as placed, which the
//! simulator applies where the arms really are.

use crate::device::{Cone, Device, Part};
use crate::kinematics::{AxisPositions, CAMERA_AXIS};
use glam::DVec3;

/// Why a position cannot be used. The indices name parts in `device.light.parts` and
/// `device.camera.parts`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Blockage {
    /// A part of the light (its head or its arm) is in the camera's view of the sample.
    View {
        /// Index of the part in `device.light.parts`.
        light_part: usize,
    },
    /// A part of the camera (lens, body or arm) is in the light's beam.
    Beam {
        /// Index of the part in `device.camera.parts`.
        camera_part: usize,
    },
    /// A light part and a camera part overlap: the arms would collide.
    Collision {
        /// Index of the light part in `device.light.parts`.
        light_part: usize,
        /// Index of the camera part in `device.camera.parts`.
        camera_part: usize,
    },
}

impl Blockage {
    /// A short description naming the parts, e.g. "light head in the camera's view".
    pub fn describe(&self, device: &Device) -> String {
        let light = |i: usize| device.light.parts[i].name.as_str();
        let camera = |i: usize| device.camera.parts[i].name.as_str();
        match *self {
            Blockage::View { light_part } => format!("{} in the camera's view", light(light_part)),
            Blockage::Beam { camera_part } => {
                format!("{} in the light's beam", camera(camera_part))
            }
            Blockage::Collision {
                light_part,
                camera_part,
            } => format!(
                "{} collides with {}",
                light(light_part),
                camera(camera_part)
            ),
        }
    }
}

/// How many times the device's accuracy (one standard deviation per axis) a plan allows the
/// arms to stop away from their command, on every axis at once.
pub const ACCURACY_SIGMAS: f64 = 3.0;

/// The first thing that blocks the measurement at these axis angles, or `None` when the
/// light sees the sample, the camera sees it and the arms are clear of each other: the exact
/// test, for arms placed exactly there.
pub fn blockage(device: &Device, axes: &AxisPositions) -> Option<Blockage> {
    blockage_with_clearance(device, axes, 0.0)
}

/// [`blockage`] for a command: what blocks it, or would block it were every axis to stop
/// [`ACCURACY_SIGMAS`] times the device's accuracy away from it. Plans and checks choose
/// positions with this test, so that a kept position neither drives the arms into each other
/// nor hides the sample when the axes stop off their command.
///
/// A point at distance `r` from the sample moves at most `r * delta` when the camera arm's
/// axis errs by `delta`, and at most `2 r delta` when both of the light arm's axes do; the
/// camera's view cone and the light's beam turn with their arms. Thickening every part by
/// `3 r delta` (its farthest point's `r`) covers each of the three tests: a light part against
/// the camera's parts or its view, a camera part against the beam.
pub fn blockage_within_accuracy(device: &Device, axes: &AxisPositions) -> Option<Blockage> {
    let delta_rad = ACCURACY_SIGMAS * device.accuracy_deg.to_radians();
    blockage_with_clearance(device, axes, 3.0 * delta_rad)
}

/// The tests of [`blockage`] with every part thickened by `per_metre` times its farthest
/// point's distance from the sample, metres.
fn blockage_with_clearance(
    device: &Device,
    axes: &AxisPositions,
    per_metre: f64,
) -> Option<Blockage> {
    let camera_dir = axes.camera_direction();
    let light_dir = axes.light_direction();
    let light_axis = axes.light_axis();
    let light_parts: Vec<Capsule> = device
        .light
        .parts
        .iter()
        .map(|p| Capsule::place(p, light_dir, light_axis, per_metre))
        .collect();
    let camera_parts: Vec<Capsule> = device
        .camera
        .parts
        .iter()
        .map(|p| Capsule::place(p, camera_dir, CAMERA_AXIS, per_metre))
        .collect();

    if let Some(i) = light_parts
        .iter()
        .position(|c| cone_meets_capsule(&device.camera.view, camera_dir, c))
    {
        return Some(Blockage::View { light_part: i });
    }
    if let Some(i) = camera_parts
        .iter()
        .position(|c| cone_meets_capsule(&device.light.beam, light_dir, c))
    {
        return Some(Blockage::Beam { camera_part: i });
    }
    for (i, l) in light_parts.iter().enumerate() {
        for (j, c) in camera_parts.iter().enumerate() {
            if segment_distance(l.a, l.b, c.a, c.b) < l.radius_m + c.radius_m {
                return Some(Blockage::Collision {
                    light_part: i,
                    camera_part: j,
                });
            }
        }
    }
    None
}

/// A segment `a`-`b` thickened by `radius_m`, in the lab frame, metres.
#[derive(Debug, Clone, Copy)]
struct Capsule {
    a: DVec3,
    b: DVec3,
    radius_m: f64,
}

impl Capsule {
    /// Places an arm part: `[u, v]` goes to `u * pointing + v * arm_axis` (`pointing` and
    /// `arm_axis` are orthogonal unit vectors), its radius thickened by `per_metre` times the
    /// distance of its farthest point from the sample.
    fn place(part: &Part, pointing: DVec3, arm_axis: DVec3, per_metre: f64) -> Self {
        let at = |[u, v]: [f64; 2]| u * pointing + v * arm_axis;
        let reach_m = part.radius_m
            + f64::hypot(part.from_m[0], part.from_m[1])
                .max(f64::hypot(part.to_m[0], part.to_m[1]));
        Self {
            a: at(part.from_m),
            b: at(part.to_m),
            radius_m: part.radius_m + per_metre * reach_m,
        }
    }
}

/// True when the capsule enters the cone that runs from the sample (the origin) along `dir`.
///
/// The cone's radius grows linearly along its axis, `r(s) = r0 + (r1 - r0) s` for the point
/// `s * end_distance * dir`, `s` in `[0, 1]`. The gap `distance(point(s), capsule axis) - r(s)`
/// is convex in `s` (a distance to a convex set along a line, minus a linear function), so a
/// golden-section search finds its minimum; quick bounds settle most cases first.
fn cone_meets_capsule(cone: &Cone, dir: DVec3, capsule: &Capsule) -> bool {
    let end = cone.end_distance_m * dir;
    let (r_min, r_max) = if cone.sample_radius_m < cone.end_radius_m {
        (cone.sample_radius_m, cone.end_radius_m)
    } else {
        (cone.end_radius_m, cone.sample_radius_m)
    };
    let axis_gap = segment_distance(DVec3::ZERO, end, capsule.a, capsule.b) - capsule.radius_m;
    if axis_gap >= r_max {
        return false;
    }
    if axis_gap < r_min {
        return true;
    }
    let gap = |s: f64| {
        let radius = cone.sample_radius_m + (cone.end_radius_m - cone.sample_radius_m) * s;
        point_segment_distance(s * end, capsule.a, capsule.b) - capsule.radius_m - radius
    };
    golden_section_min(gap, 0.0, 1.0) < 0.0
}

/// The minimum of a convex function on `[lo, hi]` (to about 1e-10 of the interval).
fn golden_section_min(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    let mut x1 = hi - ratio * (hi - lo);
    let mut x2 = lo + ratio * (hi - lo);
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..50 {
        if f1 < f2 {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - ratio * (hi - lo);
            f1 = f(x1);
        } else {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + ratio * (hi - lo);
            f2 = f(x2);
        }
    }
    f1.min(f2).min(f(lo)).min(f(hi))
}

/// Distance from point `p` to the segment `a`-`b`.
fn point_segment_distance(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + t * ab)).length()
}

/// Shortest distance between the segments `p1`-`q1` and `p2`-`q2` (Ericson, Real-Time
/// Collision Detection, 5.1.9).
fn segment_distance(p1: DVec3, q1: DVec3, p2: DVec3, q2: DVec3) -> f64 {
    const EPS: f64 = 1e-18;
    let d1 = q1 - p1;
    let d2 = q2 - p2;
    let r = p1 - p2;
    let a = d1.length_squared();
    let e = d2.length_squared();
    let f = d2.dot(r);
    let (s, t) = if a <= EPS && e <= EPS {
        (0.0, 0.0)
    } else if a <= EPS {
        (0.0, (f / e).clamp(0.0, 1.0))
    } else {
        let c = d1.dot(r);
        if e <= EPS {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else {
            let b = d1.dot(d2);
            let denom = a * e - b * b;
            let s = if denom > EPS {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let t = (b * s + f) / e;
            if t < 0.0 {
                ((-c / a).clamp(0.0, 1.0), 0.0)
            } else if t > 1.0 {
                (((b - c) / a).clamp(0.0, 1.0), 1.0)
            } else {
                (s, t)
            }
        }
    };
    ((p1 + s * d1) - (p2 + t * d2)).length()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::solutions;
    use proptest::prelude::*;
    use specula_core::HalfDiff;

    fn vec3() -> impl Strategy<Value = DVec3> {
        (-2.0..2.0f64, -2.0..2.0f64, -2.0..2.0f64).prop_map(|(x, y, z)| DVec3::new(x, y, z))
    }

    /// Brute force: the smallest distance over a fine grid of both segments' parameters.
    fn sampled_segment_distance(p1: DVec3, q1: DVec3, p2: DVec3, q2: DVec3) -> f64 {
        let n = 400;
        let mut best = f64::INFINITY;
        for i in 0..=n {
            let a = p1 + (q1 - p1) * (i as f64 / n as f64);
            best = best.min(point_segment_distance(a, p2, q2));
        }
        best
    }

    proptest! {
        #[test]
        fn segment_distance_matches_sampling(p1 in vec3(), q1 in vec3(), p2 in vec3(), q2 in vec3()) {
            let exact = segment_distance(p1, q1, p2, q2);
            let sampled = sampled_segment_distance(p1, q1, p2, q2);
            // Sampling one segment at 1/400 steps overestimates by at most half a step.
            let step = (q1 - p1).length() / 400.0;
            prop_assert!(exact <= sampled + 1e-12, "{exact} > {sampled}");
            prop_assert!(sampled - exact <= step, "{exact} vs {sampled}");
            prop_assert!((exact - segment_distance(q2, p2, q1, p1)).abs() < 1e-9, "symmetric");
        }
    }

    fn position(theta_h: f64, theta_d: f64, phi_d: f64) -> Vec<AxisPositions> {
        let device = Device::utia();
        let (wi, wo) = HalfDiff::from_degrees(theta_h, 45.0, theta_d, phi_d).to_directions();
        solutions(&device, wi, wo)
    }

    #[test]
    fn retro_reflection_is_always_blocked_by_the_light_head() {
        let device = Device::utia();
        for theta in [0.0, 20.0, 60.0] {
            let all = position(theta, 0.0, 0.0);
            assert!(!all.is_empty());
            for axes in &all {
                let b = blockage(&device, axes);
                assert!(
                    matches!(b, Some(Blockage::View { light_part: 0 })),
                    "{theta}: {b:?}"
                );
            }
        }
    }

    /// The light head blocks the view exactly when the camera's line of sight passes within
    /// (head radius + view cone radius there) of the head's front: check the threshold in the
    /// angle between light and camera against the closed form.
    #[test]
    fn head_blocking_threshold_matches_closed_form() {
        let device = Device::utia();
        let head = &device.light.parts[0];
        let view = device.camera.view;
        let front = head.from_m[0];
        let cone_r = view.sample_radius_m
            + (view.end_radius_m - view.sample_radius_m) * front / view.end_distance_m;
        // The line of sight at angle g from the light axis passes the head's front disc edge
        // at distance front * sin g from the axis; the nearest capsule point is the front
        // centre, so blocking ends when front * sin g = head radius + cone radius (to first
        // order in the cone's slope).
        let limit_deg = ((head.radius_m + cone_r) / front).asin().to_degrees();
        for (angle_deg, blocked) in [(limit_deg - 0.3, true), (limit_deg + 0.3, false)] {
            // Camera at 30 deg, light in the same vertical plane, further out by angle_deg.
            let axes = AxisPositions::from_degrees(0.0, 30.0, 0.0, 30.0 + angle_deg);
            let b = blockage(&device, &axes);
            assert_eq!(
                matches!(b, Some(Blockage::View { light_part: 0 })),
                blocked,
                "angle {angle_deg} (limit {limit_deg}): {b:?}"
            );
        }
    }

    /// Every position that the test within the accuracy keeps stays free, by the exact test,
    /// wherever within that error the arm axes stop: the corners of the error box and points
    /// inside it, over a grid that crosses the boundaries of all three kinds of blockage.
    #[test]
    fn a_position_free_within_the_accuracy_is_free_wherever_the_axes_stop() {
        let device = Device::utia();
        let delta = ACCURACY_SIGMAS * device.accuracy_deg.to_radians();
        let offsets = [-1.0, -0.5, 0.0, 0.5, 1.0];
        let (mut kept, mut near_boundary) = (0, 0);
        for theta_h in [0.0, 3.0, 10.0, 25.0, 45.0, 70.0] {
            for theta_d in (0..=30).map(|i| 3.0 * i as f64) {
                for phi_d in (0..=12).map(|i| 15.0 * i as f64) {
                    for axes in position_at(theta_h, theta_d, phi_d) {
                        let exact = blockage(&device, &axes);
                        if blockage_within_accuracy(&device, &axes).is_some() {
                            near_boundary += usize::from(exact.is_none());
                            continue;
                        }
                        kept += 1;
                        let [t, c, az, el] = axes.as_array();
                        for dc in offsets {
                            for da in offsets {
                                for de in offsets {
                                    let moved = AxisPositions::new(
                                        t,
                                        c + dc * delta,
                                        az + da * delta,
                                        el + de * delta,
                                    );
                                    assert_eq!(blockage(&device, &moved), None, "{axes:?}");
                                }
                            }
                        }
                    }
                }
            }
        }
        assert!(kept > 1000, "{kept} kept");
        // The margin is a margin: some positions free as placed are refused, not many.
        assert!(
            (1..kept / 20).contains(&near_boundary),
            "{near_boundary} of {kept}"
        );
    }

    fn position_at(theta_h: f64, theta_d: f64, phi_d: f64) -> Vec<AxisPositions> {
        let device = Device::utia();
        let (wi, wo) = HalfDiff::from_degrees(theta_h, 30.0, theta_d, phi_d).to_directions();
        solutions(&device, wi, wo)
    }

    #[test]
    fn far_apart_is_free() {
        let device = Device::utia();
        // Specular pair at theta_d = 40: light and camera 80 deg apart in the camera's plane,
        // the light arm's pivot sideways.
        let axes = AxisPositions::from_degrees(0.0, 40.0, 180.0, 40.0);
        assert_eq!(blockage(&device, &axes), None);
    }

    #[test]
    fn light_arm_blocks_the_view_from_its_pivot_side() {
        let device = Device::utia();
        // Light at 20 deg towards +x with its elevation axis along +y (azimuth 0): its arm
        // runs from the head towards +y. A camera in the plane of L and +y, between the two,
        // looks through the arm; the mirror pose of the light arm (azimuth 180, elevation
        // -20) puts the arm on the -y side and frees the view.
        let light = AxisPositions::from_degrees(0.0, 0.0, 0.0, 20.0);
        let l = light.light_direction();
        let arm_axis = light.light_axis();
        // A camera direction between L and the arm axis, in their plane.
        let c = (l + 0.8 * arm_axis).normalize();
        // Turn the lab so the camera lies in the camera arm's x-z plane: rotate everything
        // about z. Equivalent: choose the turntable freely; here rotate the light azimuth.
        let cam_azimuth = c.y.atan2(c.x);
        let camera_rad = c.z.acos();
        let axes = AxisPositions::new(0.0, camera_rad, -cam_azimuth, 20f64.to_radians());
        let b = blockage(&device, &axes);
        assert!(
            matches!(b, Some(Blockage::View { light_part: 1 | 2 })),
            "expected the light arm in view: {b:?}"
        );
        let flipped = AxisPositions::new(
            0.0,
            camera_rad,
            -cam_azimuth + std::f64::consts::PI,
            -20f64.to_radians(),
        );
        assert!((flipped.light_direction() - axes.light_direction()).length() < 1e-12);
        assert_eq!(blockage(&device, &flipped), None);
    }

    #[test]
    fn camera_closer_than_light_blocks_the_beam() {
        // A device whose camera sits inside the light's distance: near retro-reflection the
        // lens and body stand in the beam, and the light head no longer blocks the view.
        let mut device = Device::utia();
        device.camera.distance_m = 0.5;
        device.camera.view.end_distance_m = 0.4;
        for part in &mut device.camera.parts[..2] {
            part.from_m[0] -= 1.6;
            part.to_m[0] -= 1.6;
        }
        let axes = AxisPositions::from_degrees(0.0, 30.0, 0.0, 32.0);
        let b = blockage(&device, &axes);
        assert!(
            matches!(b, Some(Blockage::Beam { camera_part: 0 | 1 })),
            "{b:?}"
        );
    }
}
