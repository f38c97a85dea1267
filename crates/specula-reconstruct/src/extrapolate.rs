//! Extrapolation of the lattice nodes no sample reached (occlusion, theta limits, grazing
//! angles). The paper extrapolates them "from measured values" without saying how (5.3);
//! ours is nearest-node continuation in the reconstruction's value domain:
//!
//! 1. along theta_d: a missing node takes the value of the nearest known node with the same
//!    theta_h and phi_d (the device's reach ends at a largest theta_d for each theta_h and
//!    phi_d, so this continues each theta_d row past its last reachable node);
//! 2. then along theta_h, for rows with no known node at all (e.g. theta_h beyond the reach);
//! 3. then along phi_d. After the three passes every node is known as soon as one was.
//!
//! In the linear domain this is a constant continuation of f (the paper's baseline); in the
//! log domain of the lobe residual (see [`crate::domain`]) it continues the ratio of the
//! measurement to a fitted microfacet lobe, so the lobe's Fresnel rise and its shape carry
//! the extrapolated region.

use crate::lattice::{Lattice, NodeStatus};

/// Fills every missing node (see the module documentation) when at least one node is
/// measured; measured nodes are unchanged.
pub(crate) fn fill_missing(lattice: &mut Lattice) {
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

    #[test]
    fn one_measured_node_fills_the_whole_lattice() {
        let mut l = lattice(2, 2, 3);
        set(&mut l, 0, 0, 0, 4.0);
        fill_missing(&mut l);
        assert!(l.values[0].iter().all(|&v| v == 4.0));
        assert_eq!(l.status_counts(), (1, 11, 0));
    }
}
