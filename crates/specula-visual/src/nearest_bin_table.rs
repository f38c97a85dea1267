//! A render-time copy of a measured table: a BRDF that is constant over each MERL cell (a MERL
//! `.binary`, binned samples) is copied into one interleaved single-precision array, so that a
//! lookup reads one cache line instead of one per channel plane. Over a 512 x 512 render at
//! 64 samples per pixel this roughly halves the time spent in the material.
//!
//! Whether a BRDF is such a table is tested, not assumed: pairs of configurations inside the
//! same cell (different theta_h, theta_d, phi_d within the cell, and different phi_h) must give
//! identical values. Analytic materials fail the test and are evaluated exactly as given.

use glam::DVec3;
use rayon::prelude::*;
use specula_core::brdf::{both_above_surface, Brdf, Rgb};
use specula_core::geometry::HalfDiff;
use specula_core::merl::{theta_h_centre_deg, theta_h_deg_at, Bin, CELLS};

/// Cells probed by [`NearestBinTable::detect`].
const PROBED_CELLS: usize = 64;

/// A MERL-grid table of f_r in 1/sr, R, G, B interleaved; NaN marks a cell not measured.
/// One extra zero cell at the end stands for "below the horizon".
pub struct NearestBinTable {
    name: String,
    cells: Vec<[f32; 3]>,
}

impl NearestBinTable {
    /// The table of `brdf` when it is constant over every probed MERL cell, else `None`.
    pub fn detect(brdf: &dyn Brdf) -> Option<Self> {
        let piecewise_constant = (0..PROBED_CELLS).all(|k| {
            // Spread the probes over the grid with a multiplicative hash.
            let index = (k as u64 * 0x9E37_79B9 + 12_345) as usize % CELLS;
            let bin = Bin::from_index(index);
            let inside = |frac: f64, phi_h_deg: f64| {
                let t = bin.theta_h_i as f64 + frac;
                let theta_h_deg = theta_h_deg_at(t).max(theta_h_centre_deg(0) * 0.5);
                HalfDiff::from_degrees(
                    theta_h_deg,
                    phi_h_deg,
                    bin.theta_d_i as f64 + frac,
                    bin.phi_d_i as f64 + frac,
                )
            };
            let a = brdf.eval_half_diff(inside(0.3, 0.0));
            let b = brdf.eval_half_diff(inside(0.7, 57.0));
            Bin::of(inside(0.3, 0.0)) == bin && a == b
        });
        piecewise_constant.then(|| Self::tabulate(brdf))
    }

    fn tabulate(brdf: &dyn Brdf) -> Self {
        let cells = (0..CELLS)
            .into_par_iter()
            .with_min_len(4096)
            .map(
                |index| match brdf.eval_half_diff(Bin::from_index(index).centre(0.0)) {
                    Some(v) if v.is_finite() => [v.x as f32, v.y as f32, v.z as f32],
                    _ => [f32::NAN; 3],
                },
            )
            .chain(rayon::iter::once([0.0; 3]))
            .collect();
        Self {
            name: brdf.name(),
            cells,
        }
    }
}

impl NearestBinTable {
    /// The cell of a pair of unit directions, or `CELLS` (a cell of zeros) below the horizon.
    ///
    /// The same bin as `Bin::of(HalfDiff::from_directions(wi, wo))` (binned by [`Bin::of`]),
    /// with half the trigonometry: the rotations that take `wi` into the half vector's frame use the half
    /// vector's own components as their sines and cosines, and phi_h is never needed.
    pub fn cell_index(&self, wi: DVec3, wo: DVec3) -> usize {
        if !both_above_surface(wi, wo) {
            return CELLS;
        }
        let sum = wi + wo;
        let h = if sum.length_squared() > 1e-24 {
            sum.normalize()
        } else {
            DVec3::Z
        };
        let rho = (h.x * h.x + h.y * h.y).sqrt();
        let (cos_phi, sin_phi) = if rho > 0.0 {
            (h.x / rho, h.y / rho)
        } else {
            (1.0, 0.0)
        };
        // Rz(-phi_h) then Ry(-theta_h), with cos(theta_h) = h.z and sin(theta_h) = rho.
        let x = cos_phi * wi.x + sin_phi * wi.y;
        let y = -sin_phi * wi.x + cos_phi * wi.y;
        let d = DVec3::new(h.z * x - rho * wi.z, y, rho * x + h.z * wi.z);
        Bin::of(HalfDiff::new(
            h.z.clamp(-1.0, 1.0).acos(),
            0.0,
            (d.z / d.length()).clamp(-1.0, 1.0).acos(),
            d.y.atan2(d.x),
        ))
        .index()
    }

    /// f_r of a cell from [`NearestBinTable::cell_index`]; 0 where not measured.
    pub fn cell_value(&self, index: usize) -> Rgb {
        let [r, g, b] = self.cells[index];
        if r.is_nan() {
            Rgb::ZERO
        } else {
            Rgb::new(r as f64, g as f64, b as f64)
        }
    }
}

impl Brdf for NearestBinTable {
    fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
        if !both_above_surface(wi, wo) {
            return Some(Rgb::ZERO);
        }
        self.eval_half_diff(HalfDiff::from_directions(wi, wo))
    }

    fn eval_half_diff(&self, hd: HalfDiff) -> Option<Rgb> {
        let [r, g, b] = self.cells[Bin::of(hd).index()];
        (!r.is_nan()).then(|| Rgb::new(r as f64, g as f64, b as f64))
    }

    fn name(&self) -> String {
        self.name.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::merl::MerlBrdf;

    /// A smooth analytic stand-in.
    struct Smooth;
    impl Brdf for Smooth {
        fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
            let hd = HalfDiff::from_directions(wi, wo);
            Some(Rgb::new(
                1.0 + hd.theta_h,
                2.0 + hd.theta_d,
                3.0 + hd.phi_d.cos(),
            ))
        }
        fn name(&self) -> String {
            "smooth".into()
        }
    }

    #[test]
    fn a_pair_on_the_phi_d_wrap_is_binned_as_merls_reader_bins_it() {
        // Half vector on the normal and phi_d a hair below 0, which folds to bin 0, not 179.
        let (s, c) = (0.6, 0.8);
        let wi = DVec3::new(s, -1e-20, c);
        let wo = DVec3::new(-s, 1e-20, c);
        let table = NearestBinTable {
            name: String::new(),
            cells: Vec::new(),
        };
        let index = table.cell_index(wi, wo);
        assert_eq!(index, Bin::of(HalfDiff::from_directions(wi, wo)).index());
        assert_eq!(Bin::from_index(index).phi_d_i, 0);
    }

    #[test]
    fn a_merl_table_is_copied_exactly_and_an_analytic_brdf_is_not() {
        assert!(NearestBinTable::detect(&Smooth).is_none());
        let mut merl = specula_core::tabulate::tabulate(&Smooth, 0.0);
        merl.set_cell(
            Bin {
                theta_h_i: 0,
                theta_d_i: 30,
                phi_d_i: 90,
            }
            .index(),
            None,
        );
        let table = NearestBinTable::detect(&merl).expect("a MERL table is detected");
        let mut state = 7u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        assert_eq!(
            table.cell_value(table.cell_index(DVec3::Z, -DVec3::Z)),
            Rgb::ZERO
        );
        for _ in 0..2000 {
            let wi = crate::lobe::sample_cosine(next(), next());
            let wo = crate::lobe::sample_cosine(next(), next());
            let reference = Bin::of(HalfDiff::from_directions(wi, wo)).index();
            assert_eq!(table.cell_index(wi, wo), reference, "{wi} {wo}");
            match (merl.eval(wi, wo), table.eval(wi, wo)) {
                (Some(a), Some(b)) => assert!((a - b).abs().max_element() < 1e-6 * a.max_element()),
                (a, b) => assert_eq!(a, b),
            }
        }
        let hole = Bin {
            theta_h_i: 0,
            theta_d_i: 30,
            phi_d_i: 90,
        }
        .centre(0.0);
        assert_eq!(table.eval_half_diff(hole), None);
        assert_eq!(MerlBrdf::empty("x").measured_count(), 0);
    }
}
