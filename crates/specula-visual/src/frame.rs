//! The shading frame at a surface point: z along the normal, as the BRDF's sample frame
//! (docs/book/src/design.md), with a tangent fixing the azimuth for anisotropic materials.

use glam::DVec3;

/// An orthonormal frame `(tangent, bitangent, normal)`.
#[derive(Debug, Clone, Copy)]
pub struct Frame {
    /// The tangent, fixing the azimuth phi = 0.
    pub tangent: DVec3,
    /// `normal x tangent`, completing the right-handed frame.
    pub bitangent: DVec3,
    /// The surface normal, the frame's z axis.
    pub normal: DVec3,
}

impl Frame {
    /// The frame of a normal and a preferred tangent direction (made orthogonal; any
    /// perpendicular direction if the two are parallel).
    pub fn new(normal: DVec3, tangent_hint: DVec3) -> Self {
        let projected = tangent_hint - normal * normal.dot(tangent_hint);
        let tangent = if projected.length_squared() > 1e-12 {
            projected.normalize()
        } else {
            normal.any_orthonormal_vector()
        };
        Self {
            tangent,
            bitangent: normal.cross(tangent),
            normal,
        }
    }

    /// A world direction in frame coordinates.
    pub fn to_local(&self, v: DVec3) -> DVec3 {
        DVec3::new(
            v.dot(self.tangent),
            v.dot(self.bitangent),
            v.dot(self.normal),
        )
    }

    /// A frame direction in world coordinates.
    pub fn to_world(&self, v: DVec3) -> DVec3 {
        v.x * self.tangent + v.y * self.bitangent + v.z * self.normal
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_and_is_right_handed() {
        let n = DVec3::new(0.3, -0.5, 0.8).normalize();
        for hint in [DVec3::X, DVec3::Y, n] {
            let f = Frame::new(n, hint);
            assert!((f.tangent.cross(f.bitangent) - f.normal).length() < 1e-12);
            let v = DVec3::new(0.1, 0.7, -0.2);
            assert!((f.to_world(f.to_local(v)) - v).length() < 1e-12);
            assert!((f.to_local(n) - DVec3::Z).length() < 1e-12);
        }
    }
}
