//! The simulated optics: the lens flare (paper 4.3). The light's finite disk is part of the
//! instrument's response ([`crate::response`]).
//!
//! **Lens flare.** Internal reflections in the lens make a ghost of the light: for the
//! paper's lens "merely a bright red spot" (4.3). The model is phenomenological: the ghost
//! falls into the region of interest when the light, seen from the camera, is between
//! `min_off_axis_deg` and `max_off_axis_deg` off the optical axis and its azimuth about the
//! axis (0 = the image's +x, towards lab +x for the camera at the zenith; the image's up is
//! the camera arm's axis) is within `half_arc_deg` of `azimuth_deg`. The ghost is a disk of
//! `radius_px` pixels, on the side of the region opposite the light, adding a reddish
//! radiance factor `strength_sr * colour * level`. Turning the configuration by 180 deg (the
//! camera on the other side of the zenith, the sample turned by 180 deg) turns the image, so
//! the ghost leaves the region: this is how a flagged capture can be retaken.

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// The lens flare's ghost (see the module documentation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LensFlare {
    /// Radiance factor of the ghost at full light, 1/sr, before its colour.
    pub strength_sr: f64,
    /// Colour of the ghost (reddish).
    pub colour: [f64; 3],
    /// Radius of the ghost, pixels.
    pub radius_px: f64,
    /// The band of off-axis angles of the light, seen from the camera, that make a ghost in
    /// the region, degrees.
    pub min_off_axis_deg: f64,
    /// Upper end of that band, degrees.
    pub max_off_axis_deg: f64,
    /// Centre and half-width of the band of the light's azimuths about the optical axis that
    /// put the ghost in the region, degrees.
    pub azimuth_deg: f64,
    /// Half-width of that band of azimuths, degrees.
    pub half_arc_deg: f64,
}

impl Default for LensFlare {
    fn default() -> Self {
        Self {
            strength_sr: 0.05,
            colour: [1.0, 0.3, 0.15],
            radius_px: 6.0,
            min_off_axis_deg: 10.0,
            max_off_axis_deg: 40.0,
            azimuth_deg: 180.0,
            half_arc_deg: 50.0,
        }
    }
}

/// A ghost inside the region of interest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ghost {
    /// Centre, pixels from the region's top-left corner (x right, y down).
    pub centre_px: DVec2,
    /// Radius, pixels.
    pub radius_px: f64,
    /// Radiance factor added to the ghost's pixels (light level included), 1/sr.
    pub radiance: DVec3,
}

impl LensFlare {
    /// The ghost for a camera at `camera_m` (lab, metres from the sample) looking at the
    /// sample, with the image's up along `up` (unit, orthogonal to the view), and the light at
    /// `light_m`; `None` when it misses the region of `roi_side_px` pixels.
    pub fn ghost(
        &self,
        camera_m: DVec3,
        up: DVec3,
        light_m: DVec3,
        level: f64,
        roi_side_px: u32,
    ) -> Option<Ghost> {
        let axis = -camera_m.normalize();
        let to_light = light_m - camera_m;
        let off_axis_deg = axis.angle_between(to_light).to_degrees();
        if !(self.min_off_axis_deg..=self.max_off_axis_deg).contains(&off_axis_deg) {
            return None;
        }
        let right = axis.cross(up);
        let azimuth = to_light.dot(up).atan2(to_light.dot(right));
        let from_band = wrap_pi(azimuth - self.azimuth_deg.to_radians());
        if from_band.abs() > self.half_arc_deg.to_radians() {
            return None;
        }
        // On the side opposite the light, a third of the way from the centre to the edge.
        let half = roi_side_px as f64 / 2.0;
        let opposite = DVec2::new(-azimuth.cos(), azimuth.sin());
        Some(Ghost {
            centre_px: DVec2::splat(half) + opposite * (half / 3.0),
            radius_px: self.radius_px,
            radiance: DVec3::from(self.colour) * self.strength_sr * level,
        })
    }
}

impl Ghost {
    /// True when the pixel at column `x`, row `y` lies in the ghost.
    pub fn covers(&self, x: u32, y: u32) -> bool {
        let centre = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
        centre.distance(self.centre_px) <= self.radius_px
    }
}

/// An angle wrapped into `(-pi, pi]`.
fn wrap_pi(angle: f64) -> f64 {
    let wrapped = angle.rem_euclid(2.0 * PI);
    if wrapped > PI {
        wrapped - 2.0 * PI
    } else {
        wrapped
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ghost_turns_away_with_the_image() {
        let flare = LensFlare::default();
        let camera = DVec3::new(30f64.to_radians().sin(), 0.0, 30f64.to_radians().cos()) * 2.0;
        let light = DVec3::new(-(30f64.to_radians().sin()), 0.0, 30f64.to_radians().cos()) * 1.1;
        let turned = |v: DVec3| DVec3::new(-v.x, -v.y, v.z);
        let up = DVec3::Y;
        let a = flare.ghost(camera, up, light, 1.0, 43);
        let b = flare.ghost(turned(camera), up, turned(light), 1.0, 43);
        assert!(a.is_some() != b.is_some(), "{a:?} {b:?}");
        let ghost = a.or(b).unwrap();
        assert!(ghost.radiance.x > ghost.radiance.y && ghost.radiance.y > ghost.radiance.z);
        let inside = (0..43).flat_map(|y| (0..43).map(move |x| (x, y)));
        let covered = inside.filter(|&(x, y)| ghost.covers(x, y)).count() as f64;
        let area = PI * ghost.radius_px * ghost.radius_px;
        assert!((covered / area - 1.0).abs() < 0.1, "{covered} vs {area}");
    }
}
