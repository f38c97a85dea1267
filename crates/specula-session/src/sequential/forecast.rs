//! What the table's uncertainty says about its error, and where measuring would reduce it
//! most.
//!
//! A cell whose relative standard uncertainty is `u` (k = 1,
//! `specula_reconstruct::uncertainty`) and whose value is `f` adds, in expectation, to the
//! squares of the two error figures of `specula compare` (`specula_core::compare`, within
//! 75 deg):
//!
//! ```text
//! relative RMSE^2:  w^2 f^2 u^2 / sum(w^2 f^2)          w = cos(theta_i) cos(theta_o)
//! log RMSE^2:       ln((1 + x (1 + u)) / (1 + x))^2 / (3 N)   x = f cos(theta_i)
//! ```
//!
//! (the second the change of `ln(1 + x)` when the value is off by `u`: `x u / (1 + x)` for a
//! small `u`, and no more than `ln(1 + u)` for a large one), summed over the channels. A
//! cell's *share* is its part of each figure's square, the two figures counting alike; a candidate plane of the lattice
//! ([`super::lattice`]) is credited with the shares of the cells nearer to it than to any
//! other candidate node of its axis, while no chosen node is nearer, and whose nearest
//! candidate position the device reaches: measuring it would take those cells from
//! interpolation across a gap to a measured neighbour. A cell whose nearest position the
//! device cannot reach credits no plane (measuring elsewhere would not make it measured).

use super::lattice::{CandidateLattice, AXES};
use rayon::prelude::*;
use specula_core::geometry::{within_elevation, USED_ELEVATION_DEG};
use specula_core::merl::{Bin, MerlBrdf, CELLS};
use specula_core::statistics::median;
use specula_reconstruct::uncertainty::RelativeUncertainty;

/// A cell within the used elevations, with what its share needs.
#[derive(Debug, Clone, Copy)]
struct Cell {
    index: usize,
    /// `cos(theta_i) cos(theta_o)`.
    weight: f64,
    /// `cos(theta_i)`.
    cos_i: f64,
    /// The nearest candidate node on each axis.
    nearest: [u32; AXES],
}

/// The cells that enter the error figures, each with its nearest candidate nodes.
pub(crate) struct CellMap {
    cells: Vec<Cell>,
}

impl CellMap {
    /// The cells within [`USED_ELEVATION_DEG`] and their nearest nodes of `lattice`.
    pub(crate) fn new(lattice: &CandidateLattice) -> Self {
        let half_turn = lattice.nodes_deg[2]
            .last()
            .is_some_and(|&p| p > 90.0 + 1e-9);
        let cells = (0..CELLS)
            .into_par_iter()
            .filter_map(|index| {
                let bin = Bin::from_index(index);
                let hd = bin.centre(0.0);
                if !within_elevation(hd, USED_ELEVATION_DEG) {
                    return None;
                }
                let (wi, wo) = hd.to_directions();
                let [theta_h, theta_d, phi_d] = bin.centre_deg();
                let phi_d = if half_turn {
                    phi_d
                } else {
                    phi_d.min(180.0 - phi_d)
                };
                let coordinate = [theta_h, theta_d, phi_d];
                let nearest = std::array::from_fn(|a| {
                    nearest_node(&lattice.nodes_deg[a], coordinate[a]) as u32
                });
                Some(Cell {
                    index,
                    weight: wi.z * wo.z,
                    cos_i: wi.z,
                    nearest,
                })
            })
            .collect();
        Self { cells }
    }
}

/// The index of the node of `nodes` (increasing) nearest to `x`.
fn nearest_node(nodes: &[f64], x: f64) -> usize {
    let above = nodes.partition_point(|&n| n < x);
    match above {
        0 => 0,
        i if i == nodes.len() => i - 1,
        i if x - nodes[i - 1] <= nodes[i] - x => i - 1,
        i => i,
    }
}

/// What a table's uncertainty says: its median, and each candidate plane's credit.
#[derive(Debug, Clone)]
pub(crate) struct Forecast {
    /// The median over the cells of their relative standard uncertainty (k = 1; the mean of
    /// the channels').
    pub median_relative: f64,
    /// Per axis and node: the shares of the cells it would take from a gap (0 for a chosen
    /// node), summing to at most 2 (both figures whole).
    pub credit: [Vec<f64>; AXES],
}

impl Forecast {
    /// The forecast of `table` with its relative uncertainty `u` over `map`'s cells, and the
    /// credit of the nodes `lattice` has not chosen.
    pub(crate) fn new(
        map: &CellMap,
        table: &MerlBrdf,
        u: &RelativeUncertainty,
        lattice: &CandidateLattice,
    ) -> Self {
        let mut relative: Vec<f64> = map
            .cells
            .iter()
            .filter(|c| table.cell(c.index).is_some())
            .filter_map(|c| u.0.get(c.index).copied().flatten())
            .map(|u| (u[0] + u[1] + u[2]) / 3.0)
            .collect();
        let parts: Vec<([u32; AXES], f64, f64)> = map
            .cells
            .par_iter()
            .filter_map(|c| {
                let f = table.cell(c.index)?;
                let u = u.0.get(c.index).copied().flatten()?;
                let f = [f.x, f.y, f.z];
                let mut rel = 0.0;
                let mut log = 0.0;
                for ch in 0..3 {
                    let radiance = f[ch].max(0.0) * c.cos_i;
                    rel += (c.weight * f[ch] * u[ch]).powi(2);
                    log += ((1.0 + radiance * (1.0 + u[ch])) / (1.0 + radiance))
                        .ln()
                        .powi(2);
                }
                Some((c.nearest, rel, log))
            })
            .collect();
        let rel_sum: f64 = parts.iter().map(|p| p.1).sum();
        let log_sum: f64 = parts.iter().map(|p| p.2).sum();
        let mut credit = lattice.nodes_deg.each_ref().map(|n| vec![0.0; n.len()]);
        for &(nearest, rel, log) in &parts {
            let nearest = nearest.map(|n| n as usize);
            if !lattice.reaches(nearest) {
                continue;
            }
            let share = rel / rel_sum.max(f64::MIN_POSITIVE) + log / log_sum.max(f64::MIN_POSITIVE);
            for a in 0..AXES {
                let node = nearest[a];
                if !lattice.chosen[a][node] {
                    credit[a][node] += share;
                }
            }
        }
        Self {
            median_relative: median(&mut relative),
            credit,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_acquisition::device::Device;
    use specula_core::Rgb;

    fn lattice() -> CandidateLattice {
        let mut l = CandidateLattice::new(
            vec![0.0, 2.0, 8.0, 20.0, 40.0],
            vec![5.0, 20.0, 35.0, 50.0, 65.0],
            vec![0.0, 45.0, 90.0],
            45.0,
            &Device::utia(),
        );
        l.chosen = [
            vec![true, false, true, false, true],
            vec![true, false, true, false, true],
            vec![true, false, true],
        ];
        l
    }

    #[test]
    fn nearest_nodes_split_at_the_midpoint() {
        let nodes = [0.0, 2.0, 8.0];
        assert_eq!(nearest_node(&nodes, -1.0), 0);
        assert_eq!(nearest_node(&nodes, 0.9), 0);
        assert_eq!(nearest_node(&nodes, 1.1), 1);
        assert_eq!(nearest_node(&nodes, 5.1), 2);
        assert_eq!(nearest_node(&nodes, 99.0), 2);
    }

    #[test]
    fn a_uniform_uncertainty_is_its_median_and_credits_only_open_nodes() {
        let lattice = lattice();
        let map = CellMap::new(&lattice);
        let table = MerlBrdf::from_fn("flat", |_| Some(Rgb::splat(0.3)));
        let u = RelativeUncertainty(vec![Some([0.05; 3]); CELLS]);
        let forecast = Forecast::new(&map, &table, &u, &lattice);
        assert!((forecast.median_relative - 0.05).abs() < 1e-12);
        for a in 0..AXES {
            for (i, &c) in forecast.credit[a].iter().enumerate() {
                if lattice.chosen[a][i] {
                    assert_eq!(c, 0.0);
                } else {
                    assert!(c > 0.0, "axis {a} node {i} owns cells");
                }
            }
            let total: f64 = forecast.credit[a].iter().sum();
            assert!(total < 2.0 + 1e-9);
        }
    }

    #[test]
    fn an_uncertain_region_credits_the_node_beside_it() {
        let lattice = lattice();
        let map = CellMap::new(&lattice);
        let table = MerlBrdf::from_fn("flat", |_| Some(Rgb::splat(0.3)));
        // Uncertain only where theta_d is near 50 deg (the open theta_d node 3).
        let u = RelativeUncertainty(
            (0..CELLS)
                .map(|i| {
                    let td = Bin::from_index(i).centre_deg()[1];
                    Some([if (td - 50.0).abs() < 6.0 { 0.5 } else { 0.01 }; 3])
                })
                .collect(),
        );
        let forecast = Forecast::new(&map, &table, &u, &lattice);
        assert!(forecast.credit[1][3] > 10.0 * forecast.credit[1][1]);
    }
}
