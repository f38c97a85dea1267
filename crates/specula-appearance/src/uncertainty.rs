//! The expanded uncertainty (k = 2) of every appearance figure of a measured table, from the
//! standard uncertainty of its cells (`OUT.uncertainty.binary`), by Monte Carlo (GUM
//! Supplement 1): each draw perturbs the table by a field of standard normal deviates times
//! the cells' uncertainties and computes the figures again; `U = 2 s`, `s` the standard
//! deviation of a figure over the [`DRAWS`] draws.
//!
//! The reconstruction's errors are not independent from cell to cell (a table interpolated
//! between two planes errs alike across the gap, a lobe too narrow is too narrow across its
//! whole peak), so the field is smooth: per channel, standard normal deviates at the nodes of
//! a grid [`NODE_SPACING_BINS`] MERL bins apart, interpolated trilinearly and rescaled to unit
//! variance, the grid shifted by a random offset in each draw so that no cell sits on a node
//! more than another (the field is then the same in law everywhere). The grid lies over the
//! MERL indices in polar form about the mirror direction, `(i_h cos phi_d, i_h sin phi_d,
//! i_d)` with `i_h` the theta_h index (its square-root spacing) and `i_d` the theta_d index:
//! at theta_h 0 every phi_d is the same configuration of an isotropic material, so those
//! cells take the same deviate, and near the peak a degree of phi_d moves a cell as little
//! as it moves the directions. Figures integrate over apertures of a few degrees, so cells
//! with independent deviates would average their errors away inside one and understate
//! `U`; a ratio of two readings apart (haze: the specular and 2 deg off it) moves when its
//! readings' deviates differ, which a field shared over both would hide.

use crate::figures::{appearance, column_values, Appearance, Options};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use rayon::prelude::*;
use specula_core::merl::{Bin, MerlBrdf, CELLS, PHI_D_BINS, THETA_D_BINS, THETA_H_BINS};
use specula_core::Rgb;

/// Monte Carlo draws per table.
pub const DRAWS: usize = 100;

/// The spacing of the correlated field's nodes, in MERL bins (theta_h and theta_d indices):
/// about the spacing of a sequential design's planes in those indices (theta_h planes 1 to 7
/// bins apart below 3 deg, theta_d planes 1 to 12 deg), over which the reconstruction's
/// errors are shared. Chosen on the training truths of the guide's coverage study (among 4,
/// 6 and 10 bins, all of whose figures lay within U at 4).
pub const NODE_SPACING_BINS: f64 = 4.0;

/// The seed of the first draw (the others follow it): the same table gives the same `U`.
const SEED: u64 = 0x5EC_0A1A;

/// Each figure's expanded uncertainty (k = 2), in [`column_values`]'s order without a
/// reference, of `table` with the standard uncertainty `u` (1/sr per cell, negative where
/// none). `None` where the figure is unknown in some draw, or where it depends on a cell
/// without an uncertainty ([`moved_by_cells_without_one`]): nothing says what that cell is
/// worth, so neither what the figure is.
pub fn expanded_uncertainty(table: &MerlBrdf, u: &MerlBrdf, options: &Options) -> Vec<Option<f64>> {
    let unknown = moved_by_cells_without_one(table, u, options);
    let points = GridPoints::new();
    let draws: Vec<Vec<Option<f64>>> = (0..DRAWS)
        .into_par_iter()
        .map(|draw| {
            let mut rng = ChaCha8Rng::seed_from_u64(SEED.wrapping_add(draw as u64));
            let field = Field::draw(&mut rng, &points);
            let perturbed = perturbed(table, u, &field, &points);
            column_values(&appearance(&perturbed, options), None)
        })
        .collect();
    let columns = draws.first().map_or(0, Vec::len);
    (0..columns)
        .map(|k| {
            let values: Option<Vec<f64>> = draws.iter().map(|d| d[k]).collect();
            let values = values.filter(|_| !unknown.get(k).copied().unwrap_or(false));
            values.map(|v| 2.0 * standard_deviation(&v))
        })
        .collect()
}

/// Per figure (in [`column_values`]'s order), whether it changes when the cells of `table`
/// that have no uncertainty in `u` change, each channel of each by its own factor between 1.5
/// and 2.5 (so that a ratio of two regions moves too): whether it depends on one of them.
/// Empty (none does) when every cell with a value has an uncertainty, as in every table a
/// measurement writes: the figures are then not computed twice more.
fn moved_by_cells_without_one(table: &MerlBrdf, u: &MerlBrdf, options: &Options) -> Vec<bool> {
    let without_one = |index: usize| table.cell(index).is_some() && u.cell(index).is_none();
    if !(0..CELLS).into_par_iter().any(without_one) {
        return Vec::new();
    }
    let factor = |index: usize, c: usize| {
        let hashed = ((3 * index + c) as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 40;
        1.5 + hashed as f64 / (1u64 << 24) as f64
    };
    let probed = MerlBrdf::from_fn(specula_core::Brdf::name(table), |index| {
        let v = table.cell(index)?;
        if u.cell(index).is_some() {
            return Some(v);
        }
        Some(Rgb::new(
            v.x * factor(index, 0),
            v.y * factor(index, 1),
            v.z * factor(index, 2),
        ))
    });
    let before = column_values(&appearance(table, options), None);
    let after = column_values(&appearance(&probed, options), None);
    before
        .iter()
        .zip(&after)
        .map(|(b, a)| match (b, a) {
            (Some(b), Some(a)) => (a - b).abs() > 1e-9 * b.abs().max(1e-12),
            (b, a) => b.is_some() != a.is_some(),
        })
        .collect()
}

/// The names of the [`expanded_uncertainty`] columns: `U_` before each figure's.
pub fn column_names(figure_columns: &[String]) -> Vec<String> {
    figure_columns.iter().map(|c| format!("U_{c}")).collect()
}

/// How many figures of `truth` lie within their `expanded` uncertainty of `measured`'s, and
/// how many could be compared: `(covered, compared)`.
pub fn figures_within(
    measured: &Appearance,
    expanded: &[Option<f64>],
    truth: &Appearance,
) -> (usize, usize) {
    let m = column_values(measured, None);
    let t = column_values(truth, None);
    let mut compared = 0;
    let mut covered = 0;
    for ((m, t), u) in m.iter().zip(&t).zip(expanded) {
        if let (Some(m), Some(t), Some(u)) = (m, t, u) {
            compared += 1;
            if (m - t).abs() <= *u {
                covered += 1;
            }
        }
    }
    (covered, compared)
}

fn standard_deviation(values: &[f64]) -> f64 {
    let n = values.len() as f64;
    if n < 2.0 {
        return 0.0;
    }
    let mean = values.iter().sum::<f64>() / n;
    (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
}

/// One draw of the correlated field (see the module documentation).
struct Field {
    /// A standard normal deviate per node of the grid and channel.
    deviates: Vec<[f64; 3]>,
    /// The draw's shift of the grid, in node spacings, each in `[0, 1)`.
    offset: [f64; 3],
}

/// The field's grid and every cell's place on it, in node spacings before a draw's offset:
/// its polar coordinates `(i_h cos phi_d, i_h sin phi_d, i_d)` at the bin's centre, the first
/// moved by 90 bins so that it is never negative. Worked out once per pair of theta_h and
/// phi_d bins, and once for all draws.
struct GridPoints {
    polar: Vec<[f64; 2]>,
    /// Nodes of the grid that holds every cell after any offset: along `i_h cos phi_d`
    /// (from -90 to 90 bins), `i_h sin phi_d` (0 to 90) and `i_d` (0 to 90).
    nodes: [usize; 3],
}

impl GridPoints {
    fn new() -> Self {
        let half = (THETA_H_BINS as f64 / NODE_SPACING_BINS).ceil() as usize;
        let along_d = (THETA_D_BINS as f64 / NODE_SPACING_BINS).ceil() as usize;
        let polar = (0..THETA_H_BINS * PHI_D_BINS)
            .map(|k| {
                let i_h = (k / PHI_D_BINS) as f64 + 0.5;
                let phi_d = ((k % PHI_D_BINS) as f64 + 0.5).to_radians();
                [
                    (i_h * phi_d.cos() + THETA_H_BINS as f64) / NODE_SPACING_BINS,
                    i_h * phi_d.sin() / NODE_SPACING_BINS,
                ]
            })
            .collect();
        Self {
            polar,
            nodes: [2 * half + 2, half + 2, along_d + 2],
        }
    }

    fn of(&self, index: usize) -> [f64; 3] {
        let bin = Bin::from_index(index);
        let [x, y] = self.polar[bin.theta_h_i * PHI_D_BINS + bin.phi_d_i];
        [x, y, (bin.theta_d_i as f64 + 0.5) / NODE_SPACING_BINS]
    }
}

impl Field {
    fn draw(rng: &mut ChaCha8Rng, points: &GridPoints) -> Self {
        Self {
            deviates: (0..points.nodes.iter().product())
                .map(|_| std::array::from_fn(|_| rng.sample(StandardNormal)))
                .collect(),
            offset: std::array::from_fn(|_| rng.random::<f64>()),
        }
    }

    /// The deviates at cell `index`: the trilinear interpolation of the eight nodes around
    /// it, divided by the root sum of the squared weights (unit variance wherever the cell
    /// lies between the nodes).
    fn at(&self, index: usize, points: &GridPoints) -> [f64; 3] {
        let [nx, ny, nz] = points.nodes;
        let point = points.of(index);
        let g: [f64; 3] = std::array::from_fn(|k| point[k] + self.offset[k]);
        let lower: [usize; 3] = std::array::from_fn(|k| g[k].floor() as usize);
        let fraction: [f64; 3] = std::array::from_fn(|k| g[k] - lower[k] as f64);
        let mut sum = [0.0; 3];
        let mut squared_weights = 0.0;
        for corner in 0..8 {
            let up = [corner & 1 == 1, corner & 2 == 2, corner & 4 == 4];
            let weight: f64 = (0..3)
                .map(|k| {
                    if up[k] {
                        fraction[k]
                    } else {
                        1.0 - fraction[k]
                    }
                })
                .product();
            let node = |k: usize, n: usize| (lower[k] + usize::from(up[k])).min(n - 1);
            let deviates = self.deviates[(node(0, nx) * ny + node(1, ny)) * nz + node(2, nz)];
            for (s, d) in sum.iter_mut().zip(deviates) {
                *s += weight * d;
            }
            squared_weights += weight * weight;
        }
        sum.map(|s| s / squared_weights.sqrt())
    }
}

/// `table + z u` per cell and channel, at least zero; cells without an uncertainty as they are.
fn perturbed(table: &MerlBrdf, u: &MerlBrdf, field: &Field, points: &GridPoints) -> MerlBrdf {
    MerlBrdf::from_fn(specula_core::Brdf::name(table), |index| {
        let v = table.cell(index)?;
        let Some(u) = u.cell(index) else {
            return Some(v);
        };
        let z = field.at(index, points);
        Some(Rgb::new(
            (v.x + z[0] * u.x).max(0.0),
            (v.y + z[1] * u.y).max(0.0),
            (v.z + z[2] * u.z).max(0.0),
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The correlation of the field's deviates (channel 0) at cells `a` and `b` over `draws`
    /// draws, and their variances.
    fn statistics(a: usize, b: usize, draws: usize) -> (f64, f64, f64) {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let points = GridPoints::new();
        let (mut aa, mut bb, mut ab) = (0.0, 0.0, 0.0);
        for _ in 0..draws {
            let field = Field::draw(&mut rng, &points);
            let (x, y) = (field.at(a, &points)[0], field.at(b, &points)[0]);
            aa += x * x;
            bb += y * y;
            ab += x * y;
        }
        let n = draws as f64;
        (ab / (aa * bb).sqrt(), aa / n, bb / n)
    }

    fn cell(theta_h_i: usize, theta_d_i: usize, phi_d_i: usize) -> usize {
        Bin {
            theta_h_i,
            theta_d_i,
            phi_d_i,
        }
        .index()
    }

    #[test]
    fn the_field_has_unit_variance_and_is_shared_where_the_configurations_are_near() {
        // theta_h 0: phi_d 0 and 90 deg are the same configuration of an isotropic material.
        let (rho, va, vb) = statistics(cell(0, 30, 0), cell(0, 30, 90), 2000);
        assert!(rho > 0.9, "{rho}");
        for v in [va, vb] {
            assert!((0.85..1.15).contains(&v), "{v}");
        }
        // Next bins along theta_d share much of their deviates; 20 bins apart, nothing.
        let (near, _, _) = statistics(cell(40, 30, 45), cell(40, 31, 45), 2000);
        let (far, va, vb) = statistics(cell(40, 30, 45), cell(40, 50, 45), 2000);
        assert!(near > 0.7, "{near}");
        assert!(far.abs() < 0.1, "{far}");
        for v in [va, vb] {
            assert!((0.85..1.15).contains(&v), "{v}");
        }
        // Far from the peak a few degrees of phi_d move the directions by many bins.
        let (apart, _, _) = statistics(cell(80, 30, 10), cell(80, 30, 40), 2000);
        assert!(apart.abs() < 0.1, "{apart}");
    }
}
