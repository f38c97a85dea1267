//! Directions in the sample frame and Rusinkiewicz's half-difference angles.
//!
//! The frame has z along the surface normal (paper section 3, docs/book/src/design.md). A direction points
//! away from the surface, towards the light (`wi`) or the camera (`wo`).
//!
//! Half-difference coordinates (Rusinkiewicz 1998, paper Fig. 3-b):
//! `h = normalize(wi + wo)`, `(theta_h, phi_h)` are the spherical angles of `h`, and
//! `d = Ry(-theta_h) Rz(-phi_h) wi` is the incident direction seen from a frame in which `h`
//! is the pole; `(theta_d, phi_d)` are its angles. The inverse turns `d` back with
//! `Rz(phi_h) Ry(theta_h)` and mirrors it about `h` to get `wo`.
//!
//! All angles here are radians; degrees only appear at the program's edges.

use glam::DVec3;
use std::f64::consts::{PI, TAU};

/// A unit direction given by its polar angle from the normal and its azimuth, in radians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spherical {
    /// Angle from the surface normal, radians, in `[0, pi]`.
    pub theta_rad: f64,
    /// Azimuth about the normal from the x axis, radians, in `[0, 2 pi)`.
    pub phi_rad: f64,
}

impl Spherical {
    /// A direction from its polar angle and azimuth, radians.
    pub fn new(theta_rad: f64, phi_rad: f64) -> Self {
        Self { theta_rad, phi_rad }
    }

    /// Spherical angles given in degrees.
    pub fn from_degrees(theta_deg: f64, phi_deg: f64) -> Self {
        Self::new(theta_deg.to_radians(), phi_deg.to_radians())
    }

    /// The unit vector `(sin t cos p, sin t sin p, cos t)`.
    pub fn to_vector(self) -> DVec3 {
        let (sin_t, cos_t) = self.theta_rad.sin_cos();
        let (sin_p, cos_p) = self.phi_rad.sin_cos();
        DVec3::new(sin_t * cos_p, sin_t * sin_p, cos_t)
    }

    /// The angles of a vector (normalised first); the azimuth of the pole is 0.
    pub fn from_vector(v: DVec3) -> Self {
        let v = v.normalize();
        Self {
            theta_rad: v.z.clamp(-1.0, 1.0).acos(),
            phi_rad: wrap_two_pi(v.y.atan2(v.x)),
        }
    }
}

/// Wraps an angle into `[0, 2 pi)`.
pub fn wrap_two_pi(angle_rad: f64) -> f64 {
    let wrapped = angle_rad.rem_euclid(TAU);
    // rem_euclid can round up to exactly TAU for tiny negative inputs.
    if wrapped >= TAU {
        0.0
    } else {
        wrapped
    }
}

/// Rusinkiewicz's half-difference angles of a pair of directions, radians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HalfDiff {
    /// Angle of the half vector from the normal, `[0, pi/2]` for directions above the surface.
    pub theta_h: f64,
    /// Azimuth of the half vector, `[0, 2 pi)`.
    pub phi_h: f64,
    /// Angle between the half vector and `wi`, `[0, pi/2]`.
    pub theta_d: f64,
    /// Azimuth of `wi` about the half vector, `[0, 2 pi)`.
    pub phi_d: f64,
}

/// The elevation from the normal (degrees) within which light and camera lie in the region
/// people use: a goniometer's reach and the views a renderer mostly sees. Cells beyond it,
/// with the light or the camera nearer the horizon, are grazing: the surface is seen
/// edge-on there and a small error of angle changes f_r most.
pub const USED_ELEVATION_DEG: f64 = 75.0;

/// The cosine of the larger elevation of light and camera of `hd` (the smaller of their z;
/// the elevations do not depend on phi_h).
fn lowest_cos(hd: HalfDiff) -> f64 {
    let (wi, wo) = hd.to_directions();
    wi.z.min(wo.z)
}

/// The larger elevation of light and camera of `hd`, degrees from the normal.
pub fn elevation_deg(hd: HalfDiff) -> f64 {
    lowest_cos(hd).clamp(-1.0, 1.0).acos().to_degrees()
}

/// Light and camera of `hd` both within `max_elevation_deg` of the normal.
pub fn within_elevation(hd: HalfDiff, max_elevation_deg: f64) -> bool {
    lowest_cos(hd) >= max_elevation_deg.to_radians().cos() - 1e-12
}

impl HalfDiff {
    /// A configuration from its four angles, radians (Rusinkiewicz 1998, as MERL indexes).
    pub fn new(theta_h: f64, phi_h: f64, theta_d: f64, phi_d: f64) -> Self {
        Self {
            theta_h,
            phi_h,
            theta_d,
            phi_d,
        }
    }

    /// Half-difference angles given in degrees.
    pub fn from_degrees(
        theta_h_deg: f64,
        phi_h_deg: f64,
        theta_d_deg: f64,
        phi_d_deg: f64,
    ) -> Self {
        Self::new(
            theta_h_deg.to_radians(),
            phi_h_deg.to_radians(),
            theta_d_deg.to_radians(),
            phi_d_deg.to_radians(),
        )
    }

    /// The half-difference angles of the pair `(wi, wo)`.
    ///
    /// When `wi = -wo` (both on the horizon, opposite) the half vector is undefined; the
    /// normal is used, which gives `theta_h = 0` and `theta_d = pi/2`.
    pub fn from_directions(wi: DVec3, wo: DVec3) -> Self {
        let wi = wi.normalize();
        let wo = wo.normalize();
        let sum = wi + wo;
        let h = if sum.length_squared() > 1e-24 {
            sum.normalize()
        } else {
            DVec3::Z
        };
        let half = Spherical::from_vector(h);
        let d = rotate_y(rotate_z(wi, -half.phi_rad), -half.theta_rad);
        let diff = Spherical::from_vector(d);
        Self {
            theta_h: half.theta_rad,
            phi_h: half.phi_rad,
            theta_d: diff.theta_rad,
            phi_d: diff.phi_rad,
        }
    }

    /// The pair `(wi, wo)` of unit vectors with these half-difference angles.
    pub fn to_directions(self) -> (DVec3, DVec3) {
        let d = Spherical::new(self.theta_d, self.phi_d).to_vector();
        let wi = rotate_z(rotate_y(d, self.theta_h), self.phi_h);
        let h = Spherical::new(self.theta_h, self.phi_h).to_vector();
        let wo = 2.0 * wi.dot(h) * h - wi;
        (wi, wo)
    }

    /// The same configuration with the roles of light and camera swapped (reciprocity):
    /// the half vector stays, `phi_d` moves by pi.
    pub fn swapped(self) -> Self {
        Self {
            phi_d: wrap_two_pi(self.phi_d + PI),
            ..self
        }
    }
}

/// Rotation of `v` about the z axis by `angle_rad` (right-handed).
pub fn rotate_z(v: DVec3, angle_rad: f64) -> DVec3 {
    let (s, c) = angle_rad.sin_cos();
    DVec3::new(c * v.x - s * v.y, s * v.x + c * v.y, v.z)
}

/// Rotation of `v` about the y axis by `angle_rad` (right-handed).
pub fn rotate_y(v: DVec3, angle_rad: f64) -> DVec3 {
    let (s, c) = angle_rad.sin_cos();
    DVec3::new(c * v.x + s * v.z, v.y, -s * v.x + c * v.z)
}

/// True when a direction lies strictly above the surface.
pub fn is_above_surface(w: DVec3) -> bool {
    w.z > 0.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::f64::consts::FRAC_PI_2;

    fn upper_direction() -> impl Strategy<Value = DVec3> {
        (0.0..FRAC_PI_2, 0.0..TAU).prop_map(|(t, p)| Spherical::new(t, p).to_vector())
    }

    fn angle_diff(a: f64, b: f64) -> f64 {
        let d = (a - b).rem_euclid(TAU);
        d.min(TAU - d)
    }

    proptest! {
        #[test]
        fn directions_round_trip(wi in upper_direction(), wo in upper_direction()) {
            prop_assume!((wi + wo).length() > 1e-6);
            let (wi2, wo2) = HalfDiff::from_directions(wi, wo).to_directions();
            prop_assert!((wi - wi2).length() < 1e-9, "wi {wi} -> {wi2}");
            prop_assert!((wo - wo2).length() < 1e-9, "wo {wo} -> {wo2}");
        }

        #[test]
        fn half_diff_round_trip(th in 1e-4..1.5f64, ph in 0.0..TAU, td in 1e-4..1.5f64, pd in 0.0..TAU) {
            let hd = HalfDiff::new(th, ph, td, pd);
            let (wi, wo) = hd.to_directions();
            let back = HalfDiff::from_directions(wi, wo);
            prop_assert!((back.theta_h - th).abs() < 1e-9);
            prop_assert!((back.theta_d - td).abs() < 1e-9);
            prop_assert!(angle_diff(back.phi_h, ph) < 1e-9);
            prop_assert!(angle_diff(back.phi_d, pd) < 1e-9);
        }

        #[test]
        fn swapping_directions_moves_phi_d_by_pi(wi in upper_direction(), wo in upper_direction()) {
            prop_assume!((wi + wo).length() > 1e-6);
            let a = HalfDiff::from_directions(wi, wo);
            let b = HalfDiff::from_directions(wo, wi);
            prop_assert!((a.theta_h - b.theta_h).abs() < 1e-9);
            prop_assert!((a.theta_d - b.theta_d).abs() < 1e-9);
            prop_assert!(angle_diff(a.phi_h, b.phi_h) < 1e-9 || a.theta_h < 1e-7);
            prop_assert!(angle_diff(b.phi_d, a.swapped().phi_d) < 1e-7 || a.theta_d < 1e-7);
        }

        #[test]
        fn rotating_about_normal_changes_only_phi_h(wi in upper_direction(), wo in upper_direction(), turn in 0.0..TAU) {
            prop_assume!((wi + wo).length() > 1e-6);
            let a = HalfDiff::from_directions(wi, wo);
            let b = HalfDiff::from_directions(rotate_z(wi, turn), rotate_z(wo, turn));
            prop_assert!((a.theta_h - b.theta_h).abs() < 1e-9);
            prop_assert!((a.theta_d - b.theta_d).abs() < 1e-9);
            prop_assert!(angle_diff(a.phi_d, b.phi_d) < 1e-7 || a.theta_d < 1e-7);
            prop_assert!(angle_diff(b.phi_h, a.phi_h + turn) < 1e-7 || a.theta_h < 1e-7);
        }
    }

    #[test]
    fn special_configurations_are_finite() {
        let cases = [
            (DVec3::Z, DVec3::Z), // theta_h = 0, theta_d = 0
            (
                Spherical::from_degrees(30.0, 0.0).to_vector(),
                Spherical::from_degrees(30.0, 180.0).to_vector(),
            ), // mirror
            (
                Spherical::from_degrees(90.0, 0.0).to_vector(),
                Spherical::from_degrees(90.0, 180.0).to_vector(),
            ), // opposite at horizon
            (
                Spherical::from_degrees(90.0, 10.0).to_vector(),
                Spherical::from_degrees(90.0, 10.0).to_vector(),
            ), // retro at horizon
            (Spherical::from_degrees(90.0, 0.0).to_vector(), DVec3::Z),
        ];
        for (wi, wo) in cases {
            let hd = HalfDiff::from_directions(wi, wo);
            for v in [hd.theta_h, hd.phi_h, hd.theta_d, hd.phi_d] {
                assert!(v.is_finite(), "{wi} {wo} -> {hd:?}");
            }
            let (a, b) = hd.to_directions();
            assert!(a.is_finite() && b.is_finite());
        }
        let mirror = HalfDiff::from_directions(cases[1].0, cases[1].1);
        assert!(mirror.theta_h.abs() < 1e-12);
        assert!((mirror.theta_d - 30f64.to_radians()).abs() < 1e-12);
    }

    #[test]
    fn known_configuration() {
        // Light at 40 deg in the x-z plane, camera mirrored: theta_h = 0, theta_d = 40. At
        // theta_h = 0 the half vector's azimuth is arbitrary; only phi_h + phi_d is defined (0).
        let wi = Spherical::from_degrees(40.0, 0.0).to_vector();
        let wo = Spherical::from_degrees(40.0, 180.0).to_vector();
        let hd = HalfDiff::from_directions(wi, wo);
        assert!((hd.theta_d.to_degrees() - 40.0).abs() < 1e-10);
        assert!(angle_diff(hd.phi_d + hd.phi_h, 0.0) < 1e-10);
    }
}
