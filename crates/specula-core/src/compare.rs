//! Error figures between two BRDF tables over the MERL grid.
//!
//! Every figure is taken per cell at its bin centre (phi_h = 0) over the cells measured in
//! both tables whose light and camera directions are both within `max_elevation_deg` of the
//! normal (90 for all cells above the surface), averaged over the three channels:
//!
//! - `relative_rmse`: cosine-weighted relative RMSE,
//!   `sqrt( sum w^2 (a - b)^2 / sum w^2 b^2 )` with `w = cos(theta_i) cos(theta_o)`,
//!   i.e. the RMSE of the reflected radiance under unit irradiance relative to B's;
//! - `log_rmse`: `sqrt( mean (ln(1 + a cos(theta_i)) - ln(1 + b cos(theta_i)))^2 )`, which
//!   weighs the peak and the tail alike;
//! - `slice_mae`: the paper's figure (section 5.1), the mean absolute difference of f_r in
//!   1/sr over the characteristic slice phi_d = 90 deg (all theta_h, theta_d).

use crate::merl::{Bin, MerlBrdf, CELLS};
use rayon::prelude::*;

/// Error figures of table `a` against the reference `b` (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorFigures {
    /// Cells that entered the figures.
    pub cells: usize,
    /// Cosine-weighted relative RMSE (dimensionless; see the module documentation).
    pub relative_rmse: f64,
    /// RMSE of `ln(1 + f_r cos(theta_i))`, weighing the peak and the tail alike.
    pub log_rmse: f64,
    /// The paper's figure (section 5.1): mean absolute difference of f_r, 1/sr, over the
    /// characteristic slice phi_d = 90 deg.
    pub slice_mae: f64,
}

#[derive(Default, Clone, Copy)]
struct Sums {
    cells: usize,
    weighted_sq_diff: f64,
    weighted_sq_ref: f64,
    log_sq_diff: f64,
    slice_abs_diff: f64,
    slice_cells: usize,
}

impl Sums {
    fn merge(self, o: Sums) -> Sums {
        Sums {
            cells: self.cells + o.cells,
            weighted_sq_diff: self.weighted_sq_diff + o.weighted_sq_diff,
            weighted_sq_ref: self.weighted_sq_ref + o.weighted_sq_ref,
            log_sq_diff: self.log_sq_diff + o.log_sq_diff,
            slice_abs_diff: self.slice_abs_diff + o.slice_abs_diff,
            slice_cells: self.slice_cells + o.slice_cells,
        }
    }
}

/// Cells per chunk of [`compare`]'s sums.
const COMPARE_CHUNK: usize = 16_384;

/// Compares `a` against the reference `b` over the cells whose light and camera directions
/// are within `max_elevation_deg` of the normal.
pub fn compare(a: &MerlBrdf, b: &MerlBrdf, max_elevation_deg: f64) -> ErrorFigures {
    let min_cos = max_elevation_deg.to_radians().cos().max(1e-12);
    // Fixed chunks summed in order: the same figures to the last bit on every run (a
    // work-stealing reduction would associate the sums differently from run to run).
    let partial: Vec<Sums> = (0..CELLS.div_ceil(COMPARE_CHUNK))
        .into_par_iter()
        .map(|chunk| {
            (chunk * COMPARE_CHUNK..((chunk + 1) * COMPARE_CHUNK).min(CELLS)).fold(
                Sums::default(),
                |mut s, index| {
                    let (Some(fa), Some(fb)) = (a.cell(index), b.cell(index)) else {
                        return s;
                    };
                    let bin = Bin::from_index(index);
                    let (wi, wo) = bin.centre(0.0).to_directions();
                    if wi.z < min_cos || wo.z < min_cos {
                        return s;
                    }
                    let w = wi.z * wo.z;
                    s.cells += 1;
                    s.weighted_sq_diff += (w * w) * (fa - fb).length_squared();
                    s.weighted_sq_ref += (w * w) * fb.length_squared();
                    for c in 0..3 {
                        let la = (fa[c] * wi.z).ln_1p();
                        let lb = (fb[c] * wi.z).ln_1p();
                        s.log_sq_diff += (la - lb).powi(2);
                    }
                    if bin.phi_d_i == 90 {
                        s.slice_cells += 1;
                        s.slice_abs_diff += (fa - fb).abs().element_sum() / 3.0;
                    }
                    s
                },
            )
        })
        .collect();
    let sums = partial.into_iter().fold(Sums::default(), Sums::merge);
    ErrorFigures {
        cells: sums.cells,
        relative_rmse: (sums.weighted_sq_diff / sums.weighted_sq_ref).sqrt(),
        log_rmse: (sums.log_sq_diff / (3 * sums.cells) as f64).sqrt(),
        slice_mae: sums.slice_abs_diff / sums.slice_cells as f64,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::Rgb;

    fn constant(v: f64) -> MerlBrdf {
        let mut t = MerlBrdf::empty("c");
        for i in 0..CELLS {
            t.set_cell(i, Some(Rgb::splat(v)));
        }
        t
    }

    #[test]
    fn identical_tables_have_zero_error() {
        let a = constant(0.3);
        let e = compare(&a, &a, 90.0);
        assert_eq!((e.relative_rmse, e.log_rmse, e.slice_mae), (0.0, 0.0, 0.0));
        assert!(e.cells > CELLS / 3);
    }

    #[test]
    fn a_uniform_scale_gives_its_relative_error() {
        let e = compare(&constant(0.33), &constant(0.3), 90.0);
        assert!((e.relative_rmse - 0.1).abs() < 1e-9, "{e:?}");
        assert!((e.slice_mae - 0.03).abs() < 1e-9);
        let near = compare(&constant(0.33), &constant(0.3), 75.0);
        assert!(near.cells < e.cells);
    }
}
