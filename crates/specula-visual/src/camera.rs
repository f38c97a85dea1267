//! The pinhole camera of every render: a ray through any point of the image plane.
//!
//! World frame: y up; the standard camera sits at `(0, 0, 4)` and looks at the origin
//! (towards -z) with a 34 deg horizontal field of view, so that the unit sphere fills most of
//! a square frame. The same camera is given to Mitsuba in `tools/mitsuba_render_check.py`.

use glam::DVec3;

/// A ray `origin + t dir`, `dir` of unit length.
#[derive(Debug, Clone, Copy)]
pub struct Ray {
    /// The ray's start, world frame.
    pub origin: DVec3,
    /// The ray's direction, unit length, world frame.
    pub dir: DVec3,
}

impl Ray {
    /// The point at distance `t` along the ray, in scene units.
    pub(crate) fn at(&self, t: f64) -> DVec3 {
        self.origin + t * self.dir
    }
}

/// A pinhole camera producing an image of `width` x `height` pixels.
#[derive(Debug, Clone, Copy)]
pub struct Camera {
    origin: DVec3,
    forward: DVec3,
    right: DVec3,
    up: DVec3,
    /// Half-width of the image plane at unit distance, `tan(fov_x / 2)`.
    half_width: f64,
    width: usize,
    height: usize,
}

/// Distance of the standard camera from the origin, in scene units (sphere radius 1).
pub const STANDARD_DISTANCE: f64 = 4.0;
/// Horizontal field of view of the standard camera, degrees.
pub const STANDARD_FOV_X_DEG: f64 = 34.0;

impl Camera {
    /// A camera at `origin` looking at `target`, `up` giving the image's vertical.
    pub fn looking_at(
        origin: DVec3,
        target: DVec3,
        up: DVec3,
        fov_x_deg: f64,
        width: usize,
        height: usize,
    ) -> Self {
        let forward = (target - origin).normalize();
        let right = forward.cross(up).normalize();
        let up = right.cross(forward);
        Self {
            origin,
            forward,
            right,
            up,
            half_width: (0.5 * fov_x_deg.to_radians()).tan(),
            width,
            height,
        }
    }

    /// The standard camera (see the module documentation) for an image of this size.
    pub fn standard(width: usize, height: usize) -> Self {
        Self::looking_at(
            DVec3::new(0.0, 0.0, STANDARD_DISTANCE),
            DVec3::ZERO,
            DVec3::Y,
            STANDARD_FOV_X_DEG,
            width,
            height,
        )
    }

    /// Image width, pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Image height, pixels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// The ray through the image point `(x, y)` in pixels: `x` from the left edge, `y` from
    /// the top edge (the centre of pixel `(i, j)` is `(i + 0.5, j + 0.5)`).
    pub fn ray(&self, x: f64, y: f64) -> Ray {
        let aspect = self.height as f64 / self.width as f64;
        let sx = (2.0 * x / self.width as f64 - 1.0) * self.half_width;
        let sy = (1.0 - 2.0 * y / self.height as f64) * self.half_width * aspect;
        Ray {
            origin: self.origin,
            dir: (self.forward + sx * self.right + sy * self.up).normalize(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_centre_ray_looks_at_the_target_and_the_edges_span_the_fov() {
        let cam = Camera::standard(100, 50);
        let centre = cam.ray(50.0, 25.0);
        assert!((centre.dir - DVec3::NEG_Z).length() < 1e-12);
        let left = cam.ray(0.0, 25.0).dir;
        let right = cam.ray(100.0, 25.0).dir;
        let fov = left.angle_between(right).to_degrees();
        assert!((fov - STANDARD_FOV_X_DEG).abs() < 1e-9, "{fov}");
        // Image x grows to the right (+x), image y grows downwards (-y).
        assert!(right.x > 0.0 && left.x < 0.0);
        assert!(cam.ray(50.0, 0.0).dir.y > 0.0);
        assert!((cam.ray(3.0, 7.0).at(2.0) - cam.ray(3.0, 7.0).origin).length() - 2.0 < 1e-12);
    }
}
