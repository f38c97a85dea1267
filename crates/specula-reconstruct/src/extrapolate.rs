//! Extrapolation of the lattice nodes no sample reached (occlusion, theta limits, grazing
//! angles, and the normal's nodes a design measures at one phi_d only). The paper
//! extrapolates them "from measured values" without saying how (5.3); ours is, first, the
//! identity at the normal and then nearest-node continuation in the reconstruction's value
//! domain:
//!
//! 0. at the normal: at theta_h 0 the half vector is the normal, and turning the pair of
//!    directions about it (phi_d) changes nothing for an isotropic surface, so every phi_d of
//!    a theta_d names one configuration. A missing node there takes the mean of the measured
//!    nodes of its theta_d at the normal and counts as measured, not extrapolated: it is the
//!    configuration they measured (a sequential design measures the normal at one phi_d,
//!    `specula_session`'s candidate lattice);
//! 1. along theta_d: a missing node takes the value of the nearest known node with the same
//!    theta_h and phi_d (the device's reach ends at a largest theta_d for each theta_h and
//!    phi_d, so this continues each theta_d row past its last reachable node);
//! 2. then along theta_h, for rows with no known node at all (e.g. theta_h beyond the reach);
//! 3. then along phi_d. After the passes every node is known as soon as one was.
//!
//! In the linear domain this is a constant continuation of f (the paper's baseline); in the
//! log domain of the lobe residual (see [`crate::domain`]) it continues the ratio of the
//! measurement to a fitted microfacet lobe, so the lobe's Fresnel rise and its shape carry
//! the extrapolated region.

use crate::lattice::{at_the_normal, Lattice, NodeStatus};

/// Fills every missing node (see the module documentation) when at least one node is
/// measured; measured nodes are unchanged.
pub(crate) fn fill_missing(lattice: &mut Lattice) {
    fill_the_normal(lattice);
    let [nh, nd, np] = lattice.shape();
    // Axis order: theta_d (1), theta_h (0), phi_d (2).
    for axis in [1usize, 0, 2] {
        let len = [nh, nd, np][axis];
        let coords = [&lattice.theta_h, &lattice.theta_d, &lattice.phi_d][axis]
            .nodes
            .clone();
        let (outer_a, outer_b) = match axis {
            0 => (nd, np),
            1 => (nh, np),
            _ => (nh, nd),
        };
        for a in 0..outer_a {
            for b in 0..outer_b {
                let node = |i: usize| match axis {
                    0 => lattice.index(i, a, b),
                    1 => lattice.index(a, i, b),
                    _ => lattice.index(a, b, i),
                };
                let line: Vec<usize> = (0..len).map(node).collect();
                fill_line(lattice, &line, &coords);
            }
        }
    }
}

/// Pass 0 of the module documentation: the missing nodes at theta_h 0 take, theta_d by
/// theta_d, the mean of that theta_d's measured nodes there, and are measured.
fn fill_the_normal(lattice: &mut Lattice) {
    if !lattice
        .theta_h
        .nodes
        .first()
        .is_some_and(|&h| at_the_normal(h))
    {
        return;
    }
    let [_, nd, np] = lattice.shape();
    for d in 0..nd {
        let line: Vec<usize> = (0..np).map(|p| lattice.index(0, d, p)).collect();
        let measured: Vec<usize> = line
            .iter()
            .copied()
            .filter(|&i| lattice.status[i] == NodeStatus::Measured)
            .collect();
        if measured.is_empty() {
            continue;
        }
        let mean: [f64; 3] = std::array::from_fn(|c| {
            measured.iter().map(|&i| lattice.values[c][i]).sum::<f64>() / measured.len() as f64
        });
        for &i in &line {
            if lattice.status[i] == NodeStatus::Missing {
                for (c, &v) in mean.iter().enumerate() {
                    lattice.values[c][i] = v;
                }
                lattice.status[i] = NodeStatus::Measured;
            }
        }
    }
}

/// Gives each missing node of one line the value of the nearest node known before this pass.
fn fill_line(lattice: &mut Lattice, line: &[usize], coords: &[f64]) {
    let known: Vec<usize> = (0..line.len())
        .filter(|&i| lattice.status[line[i]] != NodeStatus::Missing)
        .collect();
    if known.is_empty() || known.len() == line.len() {
        return;
    }
    for i in 0..line.len() {
        if lattice.status[line[i]] != NodeStatus::Missing {
            continue;
        }
        let source = *known
            .iter()
            .min_by(|&&a, &&b| {
                (coords[a] - coords[i])
                    .abs()
                    .total_cmp(&(coords[b] - coords[i]).abs())
            })
            .expect("known is not empty");
        for c in 0..3 {
            lattice.values[c][line[i]] = lattice.values[c][line[source]];
        }
        lattice.status[line[i]] = NodeStatus::Filled;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::axis::Axis;

    fn lattice(nh: usize, nd: usize, np: usize) -> Lattice {
        let axis = |n: usize| Axis {
            nodes: (0..n).map(|i| 10.0 * i as f64).collect(),
        };
        let n = nh * nd * np;
        Lattice {
            theta_h: axis(nh),
            theta_d: axis(nd),
            phi_d: axis(np),
            values: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            status: vec![NodeStatus::Missing; n],
        }
    }

    fn set(l: &mut Lattice, h: usize, d: usize, p: usize, v: f64) {
        let i = l.index(h, d, p);
        for c in 0..3 {
            l.values[c][i] = v;
        }
        l.status[i] = NodeStatus::Measured;
    }

    #[test]
    fn rows_continue_along_theta_d_then_theta_h() {
        let mut l = lattice(3, 4, 1);
        // theta_h 0: measured at d = 0, 1; theta_h 1: at d = 0 only; theta_h 2: nothing.
        set(&mut l, 0, 0, 0, 1.0);
        set(&mut l, 0, 1, 0, 2.0);
        set(&mut l, 1, 0, 0, 5.0);
        fill_missing(&mut l);
        let v = |l: &Lattice, h, d| l.values[1][l.index(h, d, 0)];
        assert_eq!([v(&l, 0, 2), v(&l, 0, 3)], [2.0, 2.0]);
        assert_eq!([v(&l, 1, 1), v(&l, 1, 3)], [5.0, 5.0]);
        // theta_h 2 had no known node in its theta_d row: it continues theta_h 1.
        assert_eq!([v(&l, 2, 0), v(&l, 2, 3)], [5.0, 5.0]);
        assert_eq!(l.status_counts(), (3, 9, 0));
        assert_eq!(l.status[l.index(0, 1, 0)], NodeStatus::Measured);
    }

    /// At theta_h 0 every phi_d is one configuration: a node measured at one phi_d there
    /// gives its value to its theta_d's other phi_d, not the theta_d beside it nor the
    /// theta_h beyond.
    #[test]
    fn the_normal_measured_at_one_phi_d_holds_at_every_phi_d() {
        let mut l = lattice(2, 2, 3);
        set(&mut l, 0, 0, 2, 3.0);
        set(&mut l, 0, 1, 2, 7.0);
        for d in 0..2 {
            for p in 0..3 {
                set(&mut l, 1, d, p, 100.0);
            }
        }
        fill_missing(&mut l);
        let v = |l: &Lattice, d, p| l.values[2][l.index(0, d, p)];
        assert_eq!([v(&l, 0, 0), v(&l, 0, 1)], [3.0, 3.0]);
        assert_eq!([v(&l, 1, 0), v(&l, 1, 1)], [7.0, 7.0]);
        assert_eq!(l.status_counts(), (12, 0, 0), "measured, not extrapolated");
    }

    /// Without a node at theta_h 0 nothing is an identity: the first theta_h row continues
    /// along theta_d as any other.
    #[test]
    fn a_lattice_that_starts_off_the_normal_fills_along_theta_d_first() {
        let mut l = lattice(2, 2, 2);
        l.theta_h.nodes = vec![1.0, 11.0];
        set(&mut l, 0, 0, 0, 3.0);
        set(&mut l, 0, 1, 1, 7.0);
        fill_missing(&mut l);
        let v = |l: &Lattice, d, p| l.values[0][l.index(0, d, p)];
        assert_eq!([v(&l, 0, 1), v(&l, 1, 0)], [7.0, 3.0]);
    }

    #[test]
    fn one_measured_node_fills_the_whole_lattice() {
        let mut l = lattice(2, 2, 3);
        set(&mut l, 0, 0, 0, 4.0);
        fill_missing(&mut l);
        assert!(l.values[0].iter().all(|&v| v == 4.0));
        // The node is at the normal: its theta_d's other two phi_d are that configuration.
        assert_eq!(l.status_counts(), (3, 9, 0));
    }
}
