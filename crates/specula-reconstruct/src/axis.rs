//! One axis of the sample lattice: its nodes (angles in degrees, the coordinate the paper
//! interpolates in, 5.3), the clustering that finds the nodes in the samples, and where each
//! MERL bin centre falls between them.

/// Where a target angle falls among the nodes: between `lower` and `lower + 1` at
/// fraction `t`, or clamped to an end node (`outside`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Bracket {
    /// Index of the node at or below the target.
    pub lower: usize,
    /// Fraction of the way from node `lower` to node `lower + 1`, in `[0, 1]`.
    pub t: f64,
    /// Whether the target lies beyond the end nodes and was clamped.
    pub outside: bool,
}

/// The nodes of one axis, ascending, degrees.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Axis {
    /// The node angles, deg, ascending.
    pub nodes: Vec<f64>,
}

impl Axis {
    /// The nodes found in `coords` (degrees): values closer than
    /// `tolerance` are one node (their mean); if more than `max_nodes` remain, the closest
    /// neighbours merge until `max_nodes` are left.
    pub(crate) fn cluster(coords: &[f64], tolerance: f64, max_nodes: usize) -> Self {
        let mut sorted = coords.to_vec();
        sorted.sort_by(f64::total_cmp);
        // Each cluster as (sum, count, last value).
        let mut clusters: Vec<(f64, usize, f64)> = Vec::new();
        for v in sorted {
            match clusters.last_mut() {
                Some((sum, n, last)) if v - *last <= tolerance => {
                    *sum += v;
                    *n += 1;
                    *last = v;
                }
                _ => clusters.push((v, 1, v)),
            }
        }
        let mut nodes: Vec<(f64, usize)> = clusters
            .iter()
            .map(|(s, n, _)| (s / *n as f64, *n))
            .collect();
        while nodes.len() > max_nodes.max(1) {
            let i = (0..nodes.len() - 1)
                .min_by(|&a, &b| {
                    (nodes[a + 1].0 - nodes[a].0).total_cmp(&(nodes[b + 1].0 - nodes[b].0))
                })
                .expect("at least two nodes");
            let (a, b) = (nodes[i], nodes[i + 1]);
            let n = a.1 + b.1;
            nodes[i] = ((a.0 * a.1 as f64 + b.0 * b.1 as f64) / n as f64, n);
            nodes.remove(i + 1);
        }
        Self {
            nodes: nodes.into_iter().map(|(u, _)| u).collect(),
        }
    }

    /// Number of nodes.
    pub(crate) fn len(&self) -> usize {
        self.nodes.len()
    }

    /// The node nearest to a coordinate.
    pub(crate) fn nearest(&self, u: f64) -> usize {
        let b = self.bracket(u);
        if b.t > 0.5 {
            b.lower + 1
        } else {
            b.lower
        }
    }

    /// Where coordinate `u` falls among the nodes.
    pub(crate) fn bracket(&self, u: f64) -> Bracket {
        let n = self.nodes.len();
        let last = n - 1;
        if n == 1 || u <= self.nodes[0] {
            return Bracket {
                lower: 0,
                t: 0.0,
                outside: u < self.nodes[0],
            };
        }
        if u >= self.nodes[last] {
            return Bracket {
                lower: last - 1,
                t: 1.0,
                outside: u > self.nodes[last],
            };
        }
        let upper = self.nodes.partition_point(|&x| x <= u);
        let lower = upper - 1;
        Bracket {
            lower,
            t: (u - self.nodes[lower]) / (self.nodes[upper] - self.nodes[lower]),
            outside: false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clustering_merges_near_values_then_closest_pairs() {
        let axis = Axis::cluster(&[3.0, 0.0, 3.0001, 6.0, 0.00005, 10.0], 1e-3, 10);
        assert_eq!(axis.len(), 4);
        assert!(
            (axis.nodes[0] - 0.000025).abs() < 1e-12 && (axis.nodes[1] - 3.00005).abs() < 1e-12
        );
        let merged = Axis::cluster(&[0.0, 1.0, 1.5, 5.0], 1e-3, 3);
        assert_eq!(merged.nodes, vec![0.0, 1.25, 5.0]);
    }

    #[test]
    fn brackets_interpolate_and_clamp() {
        let axis = Axis {
            nodes: vec![0.0, 3.0, 9.0],
        };
        assert_eq!(
            axis.bracket(1.5),
            Bracket {
                lower: 0,
                t: 0.5,
                outside: false
            }
        );
        assert_eq!(
            axis.bracket(3.0),
            Bracket {
                lower: 1,
                t: 0.0,
                outside: false
            }
        );
        assert_eq!(
            axis.bracket(7.5),
            Bracket {
                lower: 1,
                t: 0.75,
                outside: false
            }
        );
        assert_eq!(
            axis.bracket(9.5),
            Bracket {
                lower: 1,
                t: 1.0,
                outside: true
            }
        );
        assert_eq!(
            axis.bracket(-1.0),
            Bracket {
                lower: 0,
                t: 0.0,
                outside: true
            }
        );
        assert_eq!(axis.nearest(7.0), 2);
        assert_eq!(axis.nearest(5.0), 1);
    }
}
