//! Tabulation of any BRDF into the MERL grid at its bin centres (docs/book/src/design.md), in parallel.

use crate::brdf::{Brdf, PhiDRow};
use crate::merl::{phi_d_centres_rad, MerlBrdf};

/// Evaluates `brdf` at the centre of every MERL cell, with the half vector at azimuth
/// `phi_h_rad` (irrelevant for isotropic materials; it selects the slice of an anisotropic one).
/// Cells the BRDF reports as not measured stay not measured. The grid is walked row by row
/// ([`Brdf::eval_phi_d_row`]), so analytic models compute their row factors once.
pub fn tabulate(brdf: &dyn Brdf, phi_h_rad: f64) -> MerlBrdf {
    let phi_d = phi_d_centres_rad();
    let cos_phi_d = phi_d.map(f64::cos);
    MerlBrdf::from_rows(brdf.name(), |row, out| {
        let centre = row.bin(0).centre(phi_h_rad);
        let row = PhiDRow {
            theta_h: centre.theta_h,
            theta_d: centre.theta_d,
            phi_h: centre.phi_h,
            phi_d: &phi_d,
            cos_phi_d: &cos_phi_d,
        };
        brdf.eval_phi_d_row(&row, out);
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::Rgb;
    use crate::geometry::HalfDiff;
    use crate::merl::{Bin, CELLS};
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

    /// The row path of the materials (factors of theta_h and theta_d computed once per row)
    /// gives what evaluating each cell on its own gives.
    #[test]
    fn rows_agree_with_cell_by_cell_evaluation() {
        use crate::materials::preset;
        for name in [
            "silver-925",
            "green-paint",
            "silver-925-scratched",
            "chrome",
        ] {
            let material = preset(name).unwrap();
            let rows = tabulate(&material, 0.3);
            for index in (0..CELLS).step_by(97) {
                let cell = material.eval_half_diff(Bin::from_index(index).centre(0.3));
                let (row, cell) = (rows.cell(index).unwrap(), cell.unwrap());
                let tolerance = 1e-12 * cell.max_element().max(1e-300);
                assert!(
                    (row - cell).abs().max_element() <= tolerance,
                    "{name}, cell {index}: {row} by rows, {cell} cell by cell"
                );
            }
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
