//! The sample lattice: the tensor grid theta_h x theta_d x phi_d spanned by the distinct
//! coordinates of the samples (phi_d folded into [0, 90] degrees), with one value per node and
//! channel in the reconstruction's value domain, and each node's status.
//!
//! A measurement plan (paper 5.3) is such a grid with holes where the device could not reach;
//! scattered samples are binned to a coarser lattice whose nodes are clusters of their
//! coordinates, so that the lattice never has more than [`MAX_NODES_PER_SAMPLE`] nodes per
//! sample.

use crate::axis::Axis;
use crate::sample::fold_phi_d_rad;
use specula_core::{HalfDiff, Sample};

/// Angles closer than this (degrees) are one node.
pub(crate) const NODE_TOLERANCE: f64 = 1e-3;
/// The lattice has at most this many nodes per sample; sparser samples are binned.
pub(crate) const MAX_NODES_PER_SAMPLE: usize = 16;
/// No axis has more nodes than this.
const MAX_NODES_PER_AXIS: usize = 512;

/// Where a node's value comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum NodeStatus {
    /// The mean of the samples at the node.
    Measured,
    /// Extrapolated from measured nodes (see [`crate::extrapolate`]).
    Filled,
    /// No value yet.
    Missing,
}

/// The tensor lattice of node values, one plane per channel, index `(h * nd + d) * np + p`.
#[derive(Debug, Clone)]
pub(crate) struct Lattice {
    /// The theta_h axis, deg.
    pub theta_h: Axis,
    /// The theta_d axis, deg.
    pub theta_d: Axis,
    /// The folded phi_d axis, deg, in `[0, 90]`.
    pub phi_d: Axis,
    /// Node values per channel in the method's value domain, index `(h * nd + d) * np + p`.
    pub values: [Vec<f64>; 3],
    /// Where each node's value comes from, same index.
    pub status: Vec<NodeStatus>,
}

/// Whether a node at `theta_h_deg` is at the normal (theta_h 0), where every phi_d of a
/// theta_d names one configuration of an isotropic surface
/// ([`crate::phi_d_halves`]'s samples at the normal).
pub(crate) fn at_the_normal(theta_h_deg: f64) -> bool {
    theta_h_deg.abs() < NODE_TOLERANCE
}

/// The lattice coordinates of `hd`: theta_h, theta_d and folded phi_d in degrees.
pub(crate) fn coordinates(hd: HalfDiff) -> [f64; 3] {
    [
        hd.theta_h.to_degrees(),
        hd.theta_d.to_degrees(),
        fold_phi_d_rad(hd.phi_d).to_degrees(),
    ]
}

impl Lattice {
    /// The lattice spanned by the samples, every node missing.
    pub(crate) fn spanned_by(samples: &[Sample]) -> Self {
        let coords: Vec<[f64; 3]> = samples.iter().map(|s| coordinates(s.hd)).collect();
        let axis = |a: usize, max_nodes: usize| {
            let values: Vec<f64> = coords.iter().map(|c| c[a]).collect();
            Axis::cluster(&values, NODE_TOLERANCE, max_nodes)
        };
        let mut axes = [0, 1, 2].map(|a| axis(a, MAX_NODES_PER_AXIS));
        let nodes: usize = axes.iter().map(Axis::len).product();
        let budget = MAX_NODES_PER_SAMPLE * samples.len();
        if nodes > budget {
            let scale = (budget as f64 / nodes as f64).cbrt();
            let lens = axes.each_ref().map(Axis::len);
            axes = [0, 1, 2].map(|a| axis(a, ((lens[a] as f64 * scale) as usize).max(2)));
        }
        let [theta_h, theta_d, phi_d] = axes;
        let n = theta_h.len() * theta_d.len() * phi_d.len();
        Self {
            theta_h,
            theta_d,
            phi_d,
            values: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            status: vec![NodeStatus::Missing; n],
        }
    }

    /// The lattice spanned by the samples holding, at each node, the mean of the values
    /// `domain_values[i]` of the samples that fall on it.
    pub(crate) fn of_samples(samples: &[Sample], domain_values: &[[f64; 3]]) -> Self {
        let mut lattice = Self::spanned_by(samples);
        let mut counts = vec![0usize; lattice.status.len()];
        for (sample, value) in samples.iter().zip(domain_values) {
            let node = lattice.node_of(sample);
            counts[node] += 1;
            for (plane, v) in lattice.values.iter_mut().zip(value) {
                plane[node] += v;
            }
        }
        for (node, &count) in counts.iter().enumerate() {
            if count > 0 {
                for c in 0..3 {
                    lattice.values[c][node] /= count as f64;
                }
                lattice.status[node] = NodeStatus::Measured;
            }
        }
        lattice
    }

    /// The node `sample` falls on: the nearest along each axis.
    pub(crate) fn node_of(&self, sample: &Sample) -> usize {
        let [h, d, p] = coordinates(sample.hd);
        self.index(
            self.theta_h.nearest(h),
            self.theta_d.nearest(d),
            self.phi_d.nearest(p),
        )
    }

    /// Node counts along theta_h, theta_d and phi_d.
    pub(crate) fn shape(&self) -> [usize; 3] {
        [self.theta_h.len(), self.theta_d.len(), self.phi_d.len()]
    }

    /// The flat index of node `(h, d, p)`.
    pub(crate) fn index(&self, h: usize, d: usize, p: usize) -> usize {
        (h * self.theta_d.len() + d) * self.phi_d.len() + p
    }

    /// How many nodes have each status: (measured, filled, missing).
    pub(crate) fn status_counts(&self) -> (usize, usize, usize) {
        let count = |s| self.status.iter().filter(|x| **x == s).count();
        (
            count(NodeStatus::Measured),
            count(NodeStatus::Filled),
            count(NodeStatus::Missing),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::{HalfDiff, Rgb};

    fn grid_samples() -> Vec<Sample> {
        let mut out = Vec::new();
        for h in [0.0, 0.5, 2.0, 10.0] {
            for d in [0.0, 30.0, 60.0] {
                for p in [0.0, 45.0, 90.0, 135.0] {
                    // 135 folds onto 45: two samples on one node.
                    out.push(Sample::new(
                        HalfDiff::from_degrees(h, 45.0, d, p),
                        Rgb::splat(h + d + p),
                    ));
                }
            }
        }
        out
    }

    #[test]
    fn a_grid_spans_its_own_lattice_and_folds_phi_d() {
        let samples = grid_samples();
        let values: Vec<[f64; 3]> = samples.iter().map(|s| [s.value.x; 3]).collect();
        let lattice = Lattice::of_samples(&samples, &values);
        assert_eq!(lattice.shape(), [4, 3, 3]);
        assert_eq!(lattice.status_counts(), (36, 0, 0));
        // Node (h = 0.5, d = 30, p = 45) holds the mean of the phi_d = 45 and 135 samples.
        let node = lattice.index(1, 1, 1);
        assert!((lattice.values[0][node] - (0.5 + 30.0 + 90.0)).abs() < 1e-9);
    }

    #[test]
    fn scattered_samples_are_binned() {
        let samples: Vec<Sample> = (0..50)
            .map(|i| {
                let x = i as f64;
                Sample::new(
                    HalfDiff::from_degrees(x * 1.1, 0.0, x * 1.3 % 90.0, x * 7.7 % 90.0),
                    Rgb::ONE,
                )
            })
            .collect();
        let lattice = Lattice::spanned_by(&samples);
        let nodes: usize = lattice.shape().iter().product();
        assert!(nodes <= MAX_NODES_PER_SAMPLE * 50, "{:?}", lattice.shape());
        assert!(lattice.shape().iter().all(|&n| n >= 2));
    }
}
