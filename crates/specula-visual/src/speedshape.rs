//! A procedural speedshape: a smooth, flattened, curved teardrop like the test objects that
//! paint makers spray (paper Fig. 1, 2 and 17). Both convex and saddle-like regions show how a
//! material's highlight stretches with curvature.
//!
//! The surface is the zero set of a signed-distance bound: Inigo Quilez's exact round-cone
//! distance (a sphere swept into a smaller one), squashed vertically and bent along its long
//! axis. Squashing and bending are divided by their Lipschitz bounds, so the function never
//! overestimates the distance and sphere tracing is safe.

use crate::camera::Ray;
use crate::frame::Frame;
use crate::hit::Hit;
use glam::{DMat3, DVec3};

/// Largest number of sphere-tracing steps before a ray is declared a miss.
const MAX_STEPS: usize = 400;
/// Distance below which a ray has reached the surface, scene units.
const SURFACE_EPSILON: f64 = 2e-5;

// The teardrop in object space: a round cone along x.
const HEAD_CENTRE_X: f64 = -0.55;
const HEAD_RADIUS: f64 = 0.6;
const TAIL_CENTRE_X: f64 = 0.85;
const TAIL_RADIUS: f64 = 0.15;
/// Vertical squash of the teardrop (height over width).
const SQUASH_Y: f64 = 0.6;
/// Curvature of the bend `y -= BEND (x - HEAD_CENTRE_X)^2`: the tail rises.
const BEND: f64 = -0.18;
/// Lipschitz bound of the bend within the bounding sphere, where
/// `|x - HEAD_CENTRE_X| <= BOUND_RADIUS + 0.55`: `sqrt(1 + (2 BEND 2.15)^2) = 1.265`.
const BEND_LIPSCHITZ: f64 = 1.27;
/// Radius of a sphere about the origin holding the object, object space.
const BOUND_RADIUS: f64 = 1.6;

/// The speedshape placed in the scene: rotated and scaled about the origin.
#[derive(Debug, Clone)]
pub struct Speedshape {
    /// World to object rotation.
    world_to_object: DMat3,
    /// Object scale in the world.
    scale: f64,
}

impl Speedshape {
    /// The placement used by `specula render --shape speedshape`: a three-quarter view from
    /// slightly above, filling the standard camera's frame.
    pub fn standard() -> Self {
        let object_to_world = DMat3::from_rotation_x(25f64.to_radians())
            * DMat3::from_rotation_y(-30f64.to_radians());
        Self {
            world_to_object: object_to_world.transpose(),
            scale: 0.9,
        }
    }

    /// The signed distance bound at a world point (negative inside).
    pub fn distance(&self, p: DVec3) -> f64 {
        let q = self.world_to_object * p / self.scale;
        self.scale * object_distance(q)
    }

    /// The outward unit normal at a world point near the surface (tetrahedral gradient).
    pub fn normal(&self, p: DVec3) -> DVec3 {
        let h = 1e-5;
        let k = [
            DVec3::new(1.0, -1.0, -1.0),
            DVec3::new(-1.0, -1.0, 1.0),
            DVec3::new(-1.0, 1.0, -1.0),
            DVec3::new(1.0, 1.0, 1.0),
        ];
        k.iter()
            .map(|k| *k * self.distance(p + h * *k))
            .sum::<DVec3>()
            .normalize()
    }

    /// The range of `t` over which `ray` is inside the bounding sphere, if it meets it.
    fn bound_interval(&self, ray: &Ray) -> Option<(f64, f64)> {
        let radius = BOUND_RADIUS * self.scale;
        let b = ray.origin.dot(ray.dir);
        let c = ray.origin.length_squared() - radius * radius;
        let discriminant = b * b - c;
        if discriminant < 0.0 {
            return None;
        }
        let root = discriminant.sqrt();
        let (near, far) = (-b - root, -b + root);
        (far > 0.0).then_some((near.max(0.0), far))
    }

    /// Sphere-traces `ray`: the first `t` at which it reaches the surface.
    fn trace(&self, ray: &Ray) -> Option<f64> {
        let (mut t, far) = self.bound_interval(ray)?;
        for _ in 0..MAX_STEPS {
            let d = self.distance(ray.at(t));
            if d < SURFACE_EPSILON {
                return Some(t);
            }
            t += d;
            if t > far {
                return None;
            }
        }
        None
    }

    /// The ray's first intersection with the speedshape, if any.
    pub(crate) fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let t = self.trace(ray)?;
        let position = ray.at(t);
        let normal = self.normal(position);
        let long_axis = self.world_to_object.transpose() * DVec3::X;
        Some(Hit {
            position,
            frame: Frame::new(normal, long_axis),
        })
    }

    /// True when a ray from `origin` (just off the surface) towards `dir` meets the object.
    pub fn blocks(&self, origin: DVec3, dir: DVec3) -> bool {
        self.trace(&Ray { origin, dir }).is_some()
    }
}

/// The distance bound in object space.
fn object_distance(q: DVec3) -> f64 {
    let dx = q.x - HEAD_CENTRE_X;
    let bent = DVec3::new(q.x, (q.y - BEND * dx * dx) / SQUASH_Y, q.z);
    SQUASH_Y * round_cone(bent) / BEND_LIPSCHITZ
}

/// Exact distance to the round cone from `(HEAD_CENTRE_X, 0, 0)`, radius `HEAD_RADIUS`, to
/// `(TAIL_CENTRE_X, 0, 0)`, radius `TAIL_RADIUS` (Quilez, "distance functions").
fn round_cone(p: DVec3) -> f64 {
    let a = DVec3::new(HEAD_CENTRE_X, 0.0, 0.0);
    let ba = DVec3::new(TAIL_CENTRE_X - HEAD_CENTRE_X, 0.0, 0.0);
    let (r1, r2) = (HEAD_RADIUS, TAIL_RADIUS);
    let l2 = ba.dot(ba);
    let rr = r1 - r2;
    let a2 = l2 - rr * rr;
    let il2 = 1.0 / l2;
    let pa = p - a;
    let y = pa.dot(ba);
    let z = y - l2;
    let x2 = (pa * l2 - ba * y).length_squared();
    let y2 = y * y * l2;
    let z2 = z * z * l2;
    let k = rr.signum() * rr * rr * x2;
    if z.signum() * a2 * z2 > k {
        return (x2 + z2).sqrt() * il2 - r2;
    }
    if y.signum() * a2 * y2 < k {
        return (x2 + y2).sqrt() * il2 - r1;
    }
    ((x2 * a2 * il2).sqrt() + y * rr) * il2 - r1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_cone_is_exact_at_the_spheres() {
        // Beyond the head sphere along -x and the tail sphere along +x.
        let d = round_cone(DVec3::new(HEAD_CENTRE_X - HEAD_RADIUS - 0.3, 0.0, 0.0));
        assert!((d - 0.3).abs() < 1e-12, "{d}");
        let d = round_cone(DVec3::new(TAIL_CENTRE_X + TAIL_RADIUS + 0.2, 0.0, 0.0));
        assert!((d - 0.2).abs() < 1e-12, "{d}");
        assert!(round_cone(DVec3::new(HEAD_CENTRE_X, 0.0, 0.0)) < 0.0);
    }

    #[test]
    fn distance_bound_never_overestimates() {
        // For random points, a sphere of the reported radius must not contain a surface point:
        // check along many directions that the sign does not change inside it.
        let shape = Speedshape::standard();
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for _ in 0..300 {
            let p = DVec3::new(next(), next(), next()) * 1.4;
            let d = shape.distance(p);
            for _ in 0..20 {
                let dir = DVec3::new(next(), next(), next()).normalize_or_zero();
                let inside = shape.distance(p + dir * d.abs() * 0.999);
                assert!(
                    inside.signum() == d.signum() || inside.abs() < 1e-9,
                    "{p} {d} {inside}"
                );
            }
        }
    }

    #[test]
    fn the_standard_placement_is_seen_by_the_camera() {
        let shape = Speedshape::standard();
        let ray = Ray {
            origin: DVec3::new(0.0, 0.0, 4.0),
            dir: DVec3::NEG_Z,
        };
        let hit = shape
            .intersect(&ray)
            .expect("the centre ray meets the object");
        assert!(shape.distance(hit.position).abs() < 1e-4);
        assert!(
            hit.frame.normal.z > 0.0,
            "faces the camera: {}",
            hit.frame.normal
        );
        let away = Ray {
            origin: DVec3::new(0.0, 0.0, 4.0),
            dir: DVec3::Z,
        };
        assert!(shape.intersect(&away).is_none());
    }
}
