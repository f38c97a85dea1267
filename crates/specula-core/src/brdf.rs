//! The BRDF abstraction every part of Specula evaluates: analytic reference materials,
//! measured tables (MERL), model fits and reconstructions.

use crate::geometry::HalfDiff;
use glam::DVec3;

/// An RGB triple of BRDF values in 1/sr (`x` red, `y` green, `z` blue).
pub type Rgb = DVec3;

/// A bidirectional reflectance distribution function f_r (paper section 3), in 1/sr per
/// RGB channel.
pub trait Brdf: Send + Sync {
    /// f_r for light arriving from `wi` and leaving towards `wo`, both unit vectors in the
    /// sample frame (z is the normal). `None` means "not measured" (a hole in a measured
    /// table); a direction at or below the horizon gives zero.
    fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb>;

    /// f_r at half-difference angles. The default converts to directions; isotropic tables
    /// override it to skip the round trip.
    fn eval_half_diff(&self, hd: HalfDiff) -> Option<Rgb> {
        let (wi, wo) = hd.to_directions();
        self.eval(wi, wo)
    }

    /// A short human-readable name (a preset, a file name, a fit's material).
    fn name(&self) -> String;
}

impl<T: Brdf + ?Sized> Brdf for Box<T> {
    fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
        (**self).eval(wi, wo)
    }
    fn eval_half_diff(&self, hd: HalfDiff) -> Option<Rgb> {
        (**self).eval_half_diff(hd)
    }
    fn name(&self) -> String {
        (**self).name()
    }
}

impl<T: Brdf + ?Sized> Brdf for std::sync::Arc<T> {
    fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
        (**self).eval(wi, wo)
    }
    fn eval_half_diff(&self, hd: HalfDiff) -> Option<Rgb> {
        (**self).eval_half_diff(hd)
    }
    fn name(&self) -> String {
        (**self).name()
    }
}

/// True when both directions are strictly above the surface, i.e. when f_r may be non-zero.
pub fn both_above_surface(wi: DVec3, wo: DVec3) -> bool {
    wi.z > 0.0 && wo.z > 0.0
}
