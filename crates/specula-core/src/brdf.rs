//! The BRDF abstraction every part of Specula evaluates: analytic reference materials,
//! measured tables (MERL), model fits and reconstructions.

use crate::geometry::HalfDiff;
use glam::DVec3;
use std::sync::Arc;

/// An RGB triple of BRDF values in 1/sr (`x` red, `y` green, `z` blue).
pub type Rgb = DVec3;

/// Rec. 709 relative luminance of a linear RGB triple (ITU-R BT.709 primaries, D65).
pub fn luminance(c: Rgb) -> f64 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

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

    /// f_r at each cell of `row` (a row of the MERL grid), written into `out` (one value per
    /// phi_d). Tabulation walks the grid this way; the default evaluates each cell with
    /// [`Brdf::eval_half_diff`], and analytic isotropic models override it to compute the
    /// factors of theta_h and theta_d alone (Fresnel, D) once per row.
    fn eval_phi_d_row(&self, row: &PhiDRow, out: &mut [Option<Rgb>]) {
        eval_phi_d_row_per_cell(self, row, out);
    }

    /// f_r at many direction pairs at once: `out[k] = self.eval(wi[k], wo[k])`, the three
    /// slices of the same length. Batched callers (the Python package's `Brdf.eval` on
    /// `(N, 3)` arrays) use it; the default evaluates pair by pair, and analytic materials
    /// override it to decide once, not per pair, which model and which of their terms apply.
    fn eval_pairs(&self, wi: &[DVec3], wo: &[DVec3], out: &mut [Option<Rgb>]) {
        eval_pairs_one_by_one(self, wi, wo, out);
    }

    /// f_r as a continuous function of the directions, for integrals over apertures (gloss,
    /// haze) and readings between a table's samples: a table of samples interpolates between
    /// them instead of returning the nearest one, whose steps an integral would otherwise add
    /// up. The default is [`Brdf::eval`], right for every BRDF that is a function already.
    fn eval_smooth(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
        self.eval(wi, wo)
    }

    /// A short human-readable name (a preset, a file name, a fit's material).
    fn name(&self) -> String;
}

/// Configurations of constant theta_h, theta_d and phi_h, phi_d varying: a row of the MERL
/// grid when tabulating (angles in radians).
#[derive(Debug, Clone, Copy)]
pub struct PhiDRow<'a> {
    /// Angle of the half vector to the normal, radians.
    pub theta_h: f64,
    /// Angle between the half vector and `wi`, radians.
    pub theta_d: f64,
    /// Azimuth of the half vector, radians.
    pub phi_h: f64,
    /// phi_d of each cell.
    pub phi_d: &'a [f64],
    /// `cos(phi_d)` of each cell, computed once for all rows.
    pub cos_phi_d: &'a [f64],
}

/// [`Brdf::eval_phi_d_row`] one cell at a time, for BRDFs with no shortcut.
pub fn eval_phi_d_row_per_cell<B: Brdf + ?Sized>(brdf: &B, row: &PhiDRow, out: &mut [Option<Rgb>]) {
    for (phi_d, out) in row.phi_d.iter().zip(out) {
        *out = brdf.eval_half_diff(HalfDiff::new(row.theta_h, row.phi_h, row.theta_d, *phi_d));
    }
}

/// [`Brdf::eval_pairs`] one pair at a time, for BRDFs with no shortcut.
pub fn eval_pairs_one_by_one<B: Brdf + ?Sized>(
    brdf: &B,
    wi: &[DVec3],
    wo: &[DVec3],
    out: &mut [Option<Rgb>],
) {
    assert_pairs(wi, wo, out);
    for ((wi, wo), out) in wi.iter().zip(wo).zip(out) {
        *out = brdf.eval(*wi, *wo);
    }
}

/// Panics unless the slices of a batch ([`Brdf::eval_pairs`]) have the same length.
pub fn assert_pairs(wi: &[DVec3], wo: &[DVec3], out: &[Option<Rgb>]) {
    assert!(
        wi.len() == wo.len() && wo.len() == out.len(),
        "eval_pairs: {} wi, {} wo and {} outputs",
        wi.len(),
        wo.len(),
        out.len()
    );
}

/// A smart pointer to a BRDF is the BRDF: every method goes to the pointee (its own
/// shortcuts included, which the trait's defaults would otherwise hide).
macro_rules! brdf_through_pointer {
    ($($pointer:ident),*) => {$(
        impl<T: Brdf + ?Sized> Brdf for $pointer<T> {
            fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
                (**self).eval(wi, wo)
            }
            fn eval_half_diff(&self, hd: HalfDiff) -> Option<Rgb> {
                (**self).eval_half_diff(hd)
            }
            fn eval_phi_d_row(&self, row: &PhiDRow, out: &mut [Option<Rgb>]) {
                (**self).eval_phi_d_row(row, out)
            }
            fn eval_pairs(&self, wi: &[DVec3], wo: &[DVec3], out: &mut [Option<Rgb>]) {
                (**self).eval_pairs(wi, wo, out)
            }
            fn eval_smooth(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
                (**self).eval_smooth(wi, wo)
            }
            fn name(&self) -> String {
                (**self).name()
            }
        }
    )*};
}

brdf_through_pointer!(Box, Arc);

/// True when both directions are strictly above the surface, i.e. when f_r may be non-zero.
pub fn both_above_surface(wi: DVec3, wo: DVec3) -> bool {
    wi.z > 0.0 && wo.z > 0.0
}
