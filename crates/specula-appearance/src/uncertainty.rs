//! The expanded uncertainty (k = 2) of every appearance figure of a measured table, from the
//! standard uncertainty of its cells (`OUT.uncertainty.binary`), by Monte Carlo (GUM
//! Supplement 1): each draw perturbs the table by a field of standard normal deviates times
//! the cells' uncertainties and computes the figures again; `U = 2 s`, `s` the standard
//! deviation of a figure over the [`DRAWS`] draws.
//!
//! The reconstruction's errors are not independent from cell to cell (a lobe too narrow is
//! too narrow across its whole peak), so the field is correlated: one deviate per channel and
//! per block of a coarse lattice of [`BLOCKS`] blocks over theta_h, theta_d and phi_d, shared
//! by every cell of the block. Figures integrate over apertures of a few degrees, which one
//! block covers, so independent cells would average their errors away and understate `U`.

use crate::figures::{appearance, column_values, Appearance, Options};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use rayon::prelude::*;
use specula_core::merl::{Bin, MerlBrdf, CELLS, PHI_D_BINS, THETA_D_BINS, THETA_H_BINS};
use specula_core::Rgb;

/// Monte Carlo draws per table.
pub const DRAWS: usize = 40;

/// Blocks of the correlated field along theta_h, theta_d and phi_d.
pub const BLOCKS: [usize; 3] = [6, 6, 15];

/// The seed of the draws: the same table gives the same `U`.
const SEED: u64 = 0x5EC_0A1A;

/// Each figure's expanded uncertainty (k = 2), in [`column_values`]'s order without a
/// reference, of `table` with the standard uncertainty `u` (1/sr per cell, negative where
/// none). `None` where the figure is unknown in some draw, or where it depends on a cell
/// without an uncertainty ([`moved_by_cells_without_one`]): nothing says what that cell is
/// worth, so neither what the figure is.
pub fn expanded_uncertainty(table: &MerlBrdf, u: &MerlBrdf, options: &Options) -> Vec<Option<f64>> {
    let unknown = moved_by_cells_without_one(table, u, options);
    let mut rng = ChaCha8Rng::seed_from_u64(SEED);
    let draws: Vec<Vec<Option<f64>>> = (0..DRAWS)
        .map(|_| {
            let field = Field::draw(&mut rng);
            let perturbed = perturbed(table, u, &field);
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

/// One draw of the correlated field: a standard normal deviate per block and channel.
struct Field {
    deviates: Vec<[f64; 3]>,
}

impl Field {
    fn draw(rng: &mut ChaCha8Rng) -> Self {
        let blocks = BLOCKS.iter().product();
        Self {
            deviates: (0..blocks)
                .map(|_| std::array::from_fn(|_| rng.sample(StandardNormal)))
                .collect(),
        }
    }

    /// The deviates of the block holding cell `index`.
    fn at(&self, index: usize) -> [f64; 3] {
        let bin = Bin::from_index(index);
        let block = |i: usize, bins: usize, blocks: usize| i * blocks / bins;
        let h = block(bin.theta_h_i, THETA_H_BINS, BLOCKS[0]);
        let d = block(bin.theta_d_i, THETA_D_BINS, BLOCKS[1]);
        let p = block(bin.phi_d_i, PHI_D_BINS, BLOCKS[2]);
        self.deviates[(h * BLOCKS[1] + d) * BLOCKS[2] + p]
    }
}

/// `table + z u` per cell and channel, at least zero; cells without an uncertainty as they are.
fn perturbed(table: &MerlBrdf, u: &MerlBrdf, field: &Field) -> MerlBrdf {
    MerlBrdf::from_fn(specula_core::Brdf::name(table), |index| {
        let v = table.cell(index)?;
        let Some(u) = u.cell(index) else {
            return Some(v);
        };
        let z = field.at(index);
        Some(Rgb::new(
            (v.x + z[0] * u.x).max(0.0),
            (v.y + z[1] * u.y).max(0.0),
            (v.z + z[2] * u.z).max(0.0),
        ))
    })
}
