//! Tabulation of any BRDF into the MERL grid at its bin centres (DESIGN.md), in parallel.

use crate::brdf::Brdf;
use crate::merl::{Bin, MerlBrdf};

/// Evaluates `brdf` at the centre of every MERL cell, with the half vector at azimuth
/// `phi_h_rad` (irrelevant for isotropic materials; it selects the slice of an anisotropic one).
/// Cells the BRDF reports as not measured stay not measured.
pub fn tabulate(brdf: &dyn Brdf, phi_h_rad: f64) -> MerlBrdf {
    MerlBrdf::from_fn(brdf.name(), |index| {
        brdf.eval_half_diff(Bin::from_index(index).centre(phi_h_rad))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::Rgb;
    use crate::geometry::HalfDiff;
    use crate::merl::CELLS;
    use glam::DVec3;

    /// A BRDF that is a known function of the half-difference angles.
    struct Probe;
    impl Brdf for Probe {
        fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
            let hd = HalfDiff::from_directions(wi, wo);
            Some(Rgb::new(
                hd.theta_h,
                hd.theta_d,
                hd.phi_d.rem_euclid(std::f64::consts::PI),
            ))
        }
        fn name(&self) -> String {
            "probe".into()
        }
    }

    #[test]
    fn every_cell_holds_its_centre() {
        let t = tabulate(&Probe, 0.0);
        assert_eq!(t.measured_count(), CELLS);
        for index in [0, 1, 17_999, 700_001, CELLS - 1] {
            let c = Bin::from_index(index).centre(0.0);
            let v = t.cell(index).unwrap();
            assert!((v.x - c.theta_h).abs() < 1e-9 && (v.y - c.theta_d).abs() < 1e-9);
            assert!((v.z - c.phi_d).abs() < 1e-9, "{index}: {v} vs {c:?}");
        }
    }
}
