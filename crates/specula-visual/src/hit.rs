//! A ray's intersection with an object: what [`crate::shape`] and [`crate::speedshape`]
//! return and the renderer shades. A leaf, so that the shapes share it without depending on
//! each other.

use crate::frame::Frame;
use glam::DVec3;

/// A ray's first intersection with the object.
#[derive(Debug, Clone, Copy)]
pub struct Hit {
    /// The intersection point, world frame.
    pub position: DVec3,
    /// The shading frame: outward normal and tangent.
    pub frame: Frame,
}
