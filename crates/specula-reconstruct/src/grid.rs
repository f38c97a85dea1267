//! Interpolation of the lattice at the MERL bin centres (paper 5.3: "linearly interpolated
//! into the sampling format of the MERL database"), as three separable one-dimensional
//! passes: along theta_h, then theta_d, then phi_d, the last one in parallel.
//!
//! Bin centres are in index space (docs/book/src/design.md): theta_h = (i + 0.5)^2 / 90 deg,
//! theta_d = j + 0.5 deg, phi_d = k + 0.5 deg folded into [0, 90] by the symmetry of
//! [`crate::sample::fold_phi_d_rad`], so phi_d bins k and 179 - k are equal.

use crate::axis::{Axis, Bracket};
use crate::kernel::{Kernel, Line};
use crate::lattice::{Lattice, NodeStatus, NODE_TOLERANCE};
use rayon::prelude::*;
use specula_core::merl::{theta_h_centre_deg, Bin, CELLS, PHI_D_BINS, THETA_D_BINS, THETA_H_BINS};

/// The phi_d bins of one half, `[0, 90)`; the other half mirrors them.
const PHI_D_HALF: usize = PHI_D_BINS / 2;

/// Where the MERL bin centres fall on each lattice axis.
struct Targets {
    theta_h: Vec<Bracket>,
    theta_d: Vec<Bracket>,
    /// The first half of the phi_d bins (centres 0.5 .. 89.5 degrees).
    phi_d: Vec<Bracket>,
}

impl Targets {
    fn of(lattice: &Lattice) -> Self {
        let theta_h = (0..THETA_H_BINS)
            .map(|i| lattice.theta_h.bracket(theta_h_centre_deg(i)))
            .collect();
        let degrees =
            |axis: &Axis, n: usize| (0..n).map(|j| axis.bracket(j as f64 + 0.5)).collect();
        Self {
            theta_h,
            theta_d: degrees(&lattice.theta_d, THETA_D_BINS),
            phi_d: degrees(&lattice.phi_d, PHI_D_HALF),
        }
    }
}

/// Whether the first and last node of an axis lie on the given symmetry points.
fn even_ends(axis: &Axis, first: Option<f64>, last: Option<f64>) -> [bool; 2] {
    let on =
        |node: f64, point: Option<f64>| point.is_some_and(|p| (node - p).abs() <= NODE_TOLERANCE);
    [
        on(axis.nodes[0], first),
        on(axis.nodes[axis.len() - 1], last),
    ]
}

/// The lattice's values interpolated at every MERL bin centre, one plane per channel in MERL
/// cell order. Every node must be known (measured or filled).
pub(crate) fn interpolate_to_merl(lattice: &Lattice, kernel: Kernel) -> [Vec<f64>; 3] {
    let targets = Targets::of(lattice);
    let lines = lines(lattice);
    lattice
        .values
        .each_ref()
        .map(|plane| interpolate_plane(lattice.shape(), plane, &targets, &lines, kernel))
}

/// The lattice's values at the centre of MERL cell `index`, one per channel: what
/// [`interpolate_to_merl`] gives there, bit for bit (the same three passes, through this one
/// cell's brackets), for a caller that reads a few cells and not the 1.5 million.
pub(crate) fn interpolate_cell(lattice: &Lattice, kernel: Kernel, index: usize) -> [f64; 3] {
    let bin = Bin::from_index(index);
    let theta_h = [lattice.theta_h.bracket(theta_h_centre_deg(bin.theta_h_i))];
    let theta_d = [lattice.theta_d.bracket(bin.theta_d_i as f64 + 0.5)];
    let phi_d_i = bin.phi_d_i.min(PHI_D_BINS - 1 - bin.phi_d_i);
    let phi_d = [lattice.phi_d.bracket(phi_d_i as f64 + 0.5)];
    let lines = lines(lattice);
    let shape = lattice.shape();
    let mut slopes = vec![0.0; shape[2]];
    lattice.values.each_ref().map(|plane| {
        let by_d = theta_passes(shape, plane, [&theta_h, &theta_d], &lines, kernel);
        let mut out = [0.0];
        lines[2].interpolate(kernel, &by_d, &mut slopes, &phi_d, &mut out);
        out[0]
    })
}

/// The three axes as interpolation lines with their even ends.
fn lines(lattice: &Lattice) -> [Line<'_>; 3] {
    // theta_h = 0 is not treated as an even end: see crate::kernel.
    [
        Line {
            nodes: &lattice.theta_h.nodes,
            even_ends: even_ends(&lattice.theta_h, None, None),
        },
        Line {
            nodes: &lattice.theta_d.nodes,
            even_ends: even_ends(&lattice.theta_d, Some(0.0), None),
        },
        Line {
            nodes: &lattice.phi_d.nodes,
            even_ends: even_ends(&lattice.phi_d, Some(0.0), Some(90.0)),
        },
    ]
}

/// The three passes for one channel.
fn interpolate_plane(
    shape: [usize; 3],
    plane: &[f64],
    targets: &Targets,
    lines: &[Line; 3],
    kernel: Kernel,
) -> Vec<f64> {
    let np = shape[2];
    let by_d = theta_passes(
        shape,
        plane,
        [&targets.theta_h, &targets.theta_d],
        lines,
        kernel,
    );
    // Pass 3, phi_d: [90][90][np] -> [90][90][180], one theta_h bin per task.
    let mut cells = vec![0.0; CELLS];
    let slab = THETA_D_BINS * PHI_D_BINS;
    cells
        .par_chunks_mut(slab)
        .enumerate()
        .for_each(|(i, slab_out)| {
            let mut slopes = vec![0.0; np];
            for (j, row) in slab_out.chunks_exact_mut(PHI_D_BINS).enumerate() {
                let start = (i * THETA_D_BINS + j) * np;
                let (first, second) = row.split_at_mut(PHI_D_HALF);
                lines[2].interpolate(
                    kernel,
                    &by_d[start..start + np],
                    &mut slopes,
                    &targets.phi_d,
                    first,
                );
                for (m, v) in second.iter_mut().zip(first.iter().rev()) {
                    *m = *v;
                }
            }
        });
    cells
}

/// Passes 1 and 2 of one channel: the `plane` of a lattice of `shape` `[nh][nd][np]`
/// interpolated along theta_h at the brackets `at[0]`, then along theta_d at `at[1]`, into
/// `[at[0].len()][at[1].len()][np]`.
fn theta_passes(
    shape: [usize; 3],
    plane: &[f64],
    at: [&[Bracket]; 2],
    lines: &[Line; 3],
    kernel: Kernel,
) -> Vec<f64> {
    let [nh, nd, np] = shape;
    let [theta_h, theta_d] = at;
    let (th, td) = (theta_h.len(), theta_d.len());
    let mut slopes = vec![0.0; nh.max(nd)];
    // Pass 1, theta_h: [nh][nd][np] -> [th][nd][np].
    let mut by_h = vec![0.0; th * nd * np];
    let mut column = vec![0.0; nh];
    let mut out = vec![0.0; th];
    for d in 0..nd {
        for p in 0..np {
            for (h, c) in column.iter_mut().enumerate() {
                *c = plane[(h * nd + d) * np + p];
            }
            lines[0].interpolate(kernel, &column, &mut slopes, theta_h, &mut out);
            for (i, v) in out.iter().enumerate() {
                by_h[(i * nd + d) * np + p] = *v;
            }
        }
    }
    // Pass 2, theta_d: [th][nd][np] -> [th][td][np].
    let mut by_d = vec![0.0; th * td * np];
    let mut column = vec![0.0; nd];
    let mut out = vec![0.0; td];
    for i in 0..th {
        for p in 0..np {
            for (d, c) in column.iter_mut().enumerate() {
                *c = by_h[(i * nd + d) * np + p];
            }
            lines[1].interpolate(kernel, &column, &mut slopes, theta_d, &mut out);
            for (j, v) in out.iter().enumerate() {
                by_d[(i * td + j) * np + p] = *v;
            }
        }
    }
    by_d
}

/// For every MERL cell, whether its value depends on extrapolation: a bin centre beyond the
/// lattice's end on some axis, or a filled node among the nodes that bracket it.
pub(crate) fn extrapolated_cells(lattice: &Lattice) -> Vec<bool> {
    let indicator: Vec<f64> = lattice
        .status
        .iter()
        .map(|s| if *s == NodeStatus::Filled { 1.0 } else { 0.0 })
        .collect();
    let targets = Targets::of(lattice);
    let filled = interpolate_plane(
        lattice.shape(),
        &indicator,
        &targets,
        &lines(lattice),
        Kernel::Linear,
    );
    let phi_outside: Vec<bool> = (0..PHI_D_BINS)
        .map(|k| targets.phi_d[k.min(PHI_D_BINS - 1 - k)].outside)
        .collect();
    (0..CELLS)
        .into_par_iter()
        .map(|index| {
            let i = index / (THETA_D_BINS * PHI_D_BINS);
            let j = (index / PHI_D_BINS) % THETA_D_BINS;
            filled[index] > 0.0
                || targets.theta_h[i].outside
                || targets.theta_d[j].outside
                || phi_outside[index % PHI_D_BINS]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::merl::Bin;

    /// A lattice holding a function of the node angles (degrees), all measured.
    fn lattice_of(
        f: impl Fn(f64, f64, f64) -> f64,
        theta_h: &[f64],
        theta_d: &[f64],
        phi_d: &[f64],
    ) -> Lattice {
        let axis = |nodes: &[f64]| Axis {
            nodes: nodes.to_vec(),
        };
        let mut values = Vec::new();
        for &h in theta_h {
            for &d in theta_d {
                for &p in phi_d {
                    values.push(f(h, d, p));
                }
            }
        }
        let n = values.len();
        Lattice {
            theta_h: axis(theta_h),
            theta_d: axis(theta_d),
            phi_d: axis(phi_d),
            values: [
                values.clone(),
                values.iter().map(|v| 2.0 * v).collect(),
                values,
            ],
            status: vec![NodeStatus::Measured; n],
        }
    }

    #[test]
    fn trilinear_functions_are_reproduced_at_every_centre() {
        // Linear in each angle separately, so trilinear interpolation is exact inside the lattice.
        let f = |h: f64, d: f64, p: f64| {
            1.0 + 0.5 * h + 0.25 * d * (1.0 + 0.01 * p) + 0.001 * h * d * p
        };
        let l = lattice_of(
            f,
            &[0.0, 0.3, 2.0, 20.0, 90.0],
            &[0.0, 3.0, 50.0, 90.0],
            &[0.0, 15.0, 60.0, 90.0],
        );
        let [r, g, _] = interpolate_to_merl(&l, Kernel::Linear);
        for index in (0..CELLS).step_by(997) {
            let b = Bin::from_index(index);
            let h = theta_h_centre_deg(b.theta_h_i);
            let p = b.phi_d_i as f64 + 0.5;
            let expected = f(h, b.theta_d_i as f64 + 0.5, p.min(180.0 - p));
            assert!(
                (r[index] - expected).abs() < 1e-9 * expected,
                "{b:?}: {} vs {expected}",
                r[index]
            );
            assert!((g[index] - 2.0 * expected).abs() < 1e-9 * expected);
        }
        assert!(extrapolated_cells(&l).iter().all(|e| !e));
    }

    #[test]
    fn phi_d_bins_mirror_and_the_ends_hold() {
        let f = |_h: f64, d: f64, p: f64| d + p;
        let l = lattice_of(f, &[0.0, 90.0], &[0.0, 30.0, 60.0], &[0.0, 90.0]);
        let [r, _, _] = interpolate_to_merl(&l, Kernel::MonotoneCubic);
        let at = |i, j, k| {
            r[Bin {
                theta_h_i: i,
                theta_d_i: j,
                phi_d_i: k,
            }
            .index()]
        };
        for k in 0..90 {
            assert_eq!(at(5, 20, k), at(5, 20, 179 - k));
        }
        // theta_d beyond the last node (60) holds its value and is flagged.
        assert_eq!(at(3, 80, 0), at(3, 60, 0));
        assert!(at(3, 59, 0) < at(3, 60, 0));
        let flags = extrapolated_cells(&l);
        assert!(
            flags[Bin {
                theta_h_i: 3,
                theta_d_i: 80,
                phi_d_i: 7
            }
            .index()]
        );
        assert!(
            !flags[Bin {
                theta_h_i: 3,
                theta_d_i: 59,
                phi_d_i: 7
            }
            .index()]
        );
    }

    #[test]
    fn cells_next_to_a_filled_node_are_flagged() {
        let mut l = lattice_of(
            |_, _, _| 1.0,
            &[0.0, 10.0, 90.0],
            &[0.0, 45.0, 90.0],
            &[0.0, 90.0],
        );
        let filled = l.index(0, 2, 0);
        l.status[filled] = NodeStatus::Filled;
        let flags = extrapolated_cells(&l);
        // theta_h bin 0 (0.003 deg) with theta_d bin 60 brackets node (0, 2, *).
        assert!(
            flags[Bin {
                theta_h_i: 0,
                theta_d_i: 60,
                phi_d_i: 10
            }
            .index()]
        );
        assert!(
            !flags[Bin {
                theta_h_i: 0,
                theta_d_i: 30,
                phi_d_i: 10
            }
            .index()]
        );
        // phi_d bin 179 (89.5 ... mirrored 0.5) is bracketed mostly by phi_d node 0.
        assert!(
            flags[Bin {
                theta_h_i: 0,
                theta_d_i: 60,
                phi_d_i: 179
            }
            .index()]
        );
        // theta_h bin 40 (18 deg) does not touch theta_h node 0.
        assert!(
            !flags[Bin {
                theta_h_i: 40,
                theta_d_i: 60,
                phi_d_i: 10
            }
            .index()]
        );
    }
}
