//! The objects a material is shown on: the unit sphere and a speedshape (a procedural stand-in
//! for the curved paint samples of the paper's Fig. 2 and Fig. 17; see [`crate::speedshape`]).

use crate::camera::Ray;
use crate::frame::Frame;
use crate::hit::Hit;
use crate::speedshape::Speedshape;
use glam::DVec3;

/// Offset along the normal before tracing a shadow ray, scene units.
const SHADOW_BIAS: f64 = 1e-4;

/// Which object to render.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShapeKind {
    /// The unit sphere at the origin.
    Sphere,
    /// The speedshape, a curved teardrop like paint makers' test objects (paper Fig. 1).
    Speedshape,
}

impl std::str::FromStr for ShapeKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "sphere" => Ok(ShapeKind::Sphere),
            "speedshape" => Ok(ShapeKind::Speedshape),
            other => Err(format!(
                "unknown shape '{other}' (expected sphere or speedshape)"
            )),
        }
    }
}

/// An object placed in the scene.
#[derive(Debug, Clone)]
pub enum Shape {
    /// The unit sphere at the origin.
    Sphere,
    /// The speedshape (see [`crate::speedshape`]).
    Speedshape(Speedshape),
}

impl Shape {
    /// The object of `kind` in its standard placement.
    pub(crate) fn new(kind: ShapeKind) -> Self {
        match kind {
            ShapeKind::Sphere => Shape::Sphere,
            ShapeKind::Speedshape => Shape::Speedshape(Speedshape::standard()),
        }
    }

    /// The first intersection of `ray` with the object, if any.
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        match self {
            Shape::Sphere => intersect_unit_sphere(ray),
            Shape::Speedshape(s) => s.intersect(ray),
        }
    }

    /// True when the object blocks the direction `dir` seen from the surface point of `hit`
    /// (self-shadowing). The sphere is convex: a direction above its tangent plane is never
    /// blocked.
    pub fn occludes(&self, hit: &Hit, dir: DVec3) -> bool {
        match self {
            Shape::Sphere => false,
            Shape::Speedshape(s) => {
                s.blocks(hit.position + SHADOW_BIAS * 20.0 * hit.frame.normal, dir)
            }
        }
    }
}

fn intersect_unit_sphere(ray: &Ray) -> Option<Hit> {
    // |o + t d|^2 = 1 with |d| = 1: t^2 + 2 b t + c = 0.
    let b = ray.origin.dot(ray.dir);
    let c = ray.origin.length_squared() - 1.0;
    let discriminant = b * b - c;
    if discriminant < 0.0 {
        return None;
    }
    let root = discriminant.sqrt();
    let t = if -b - root > SHADOW_BIAS {
        -b - root
    } else {
        -b + root
    };
    if t <= SHADOW_BIAS {
        return None;
    }
    let position = ray.at(t);
    let normal = position.normalize();
    Some(Hit {
        position,
        frame: Frame::new(normal, DVec3::Y.cross(normal)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_hits_where_expected() {
        let ray = Ray {
            origin: DVec3::new(0.0, 0.0, 4.0),
            dir: DVec3::NEG_Z,
        };
        let hit = Shape::Sphere.intersect(&ray).unwrap();
        assert!((hit.position - DVec3::Z).length() < 1e-12);
        assert!((hit.frame.normal - DVec3::Z).length() < 1e-12);
        let miss = Ray {
            origin: DVec3::new(1.01, 0.0, 4.0),
            dir: DVec3::NEG_Z,
        };
        assert!(Shape::Sphere.intersect(&miss).is_none());
        assert!("Speedshape".parse::<ShapeKind>().is_ok() && "cube".parse::<ShapeKind>().is_err());
    }
}
