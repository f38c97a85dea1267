//! One axis of the sample lattice: its nodes in an interpolation coordinate, the clustering
//! that finds the nodes in the samples, and where each MERL bin centre falls between them.

/// How an angle (radians) maps to the coordinate in which an axis interpolates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Coordinate {
    /// Degrees, as the paper interpolates all three axes (section 5.3).
    Degrees,
    /// MERL's theta_h index coordinate `sqrt(theta_h_deg * 90)`, in which the bins are
    /// uniform and a peak at theta_h = 0 is resolved as finely as MERL resolves it.
    MerlThetaH,
}

impl Coordinate {
    /// The coordinate of an angle in radians.
    pub fn of_rad(self, angle_rad: f64) -> f64 {
        let deg = angle_rad.to_degrees();
        match self {
            Coordinate::Degrees => deg,
            Coordinate::MerlThetaH => (deg.max(0.0) * 90.0).sqrt(),
        }
    }

    /// The angle in radians of a coordinate.
    pub fn to_rad(self, u: f64) -> f64 {
        match self {
            Coordinate::Degrees => u.to_radians(),
            Coordinate::MerlThetaH => (u * u / 90.0).to_radians(),
        }
    }
}

/// Where a target coordinate falls among the nodes: between `lower` and `lower + 1` at
/// fraction `t`, or clamped to an end node (`outside`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bracket {
    pub lower: usize,
    pub t: f64,
    pub outside: bool,
}

/// The nodes of one axis, ascending, in the axis' coordinate.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    pub coordinate: Coordinate,
    pub nodes: Vec<f64>,
}

impl Axis {
    /// The nodes found in `coords` (already in the axis' coordinate): values closer than
    /// `tolerance` are one node (their mean); if more than `max_nodes` remain, the closest
    /// neighbours merge until `max_nodes` are left.
    pub fn cluster(coordinate: Coordinate, coords: &[f64], tolerance: f64, max_nodes: usize) -> Self {
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
        let mut nodes: Vec<(f64, usize)> = clusters.iter().map(|(s, n, _)| (s / *n as f64, *n)).collect();
        while nodes.len() > max_nodes.max(1) {
            let i = (0..nodes.len() - 1)
                .min_by(|&a, &b| (nodes[a + 1].0 - nodes[a].0).total_cmp(&(nodes[b + 1].0 - nodes[b].0)))
                .expect("at least two nodes");
            let (a, b) = (nodes[i], nodes[i + 1]);
            let n = a.1 + b.1;
            nodes[i] = ((a.0 * a.1 as f64 + b.0 * b.1 as f64) / n as f64, n);
            nodes.remove(i + 1);
        }
        Self {
            coordinate,
            nodes: nodes.into_iter().map(|(u, _)| u).collect(),
        }
    }

    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The node nearest to a coordinate.
    pub fn nearest(&self, u: f64) -> usize {
        let b = self.bracket(u);
        if b.t > 0.5 {
            b.lower + 1
        } else {
            b.lower
        }
    }

    /// Where coordinate `u` falls among the nodes.
    pub fn bracket(&self, u: f64) -> Bracket {
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
        let axis = Axis::cluster(Coordinate::Degrees, &[3.0, 0.0, 3.0001, 6.0, 0.00005, 10.0], 1e-3, 10);
        assert_eq!(axis.len(), 4);
        assert!((axis.nodes[0] - 0.000025).abs() < 1e-12 && (axis.nodes[1] - 3.00005).abs() < 1e-12);
        let merged = Axis::cluster(Coordinate::Degrees, &[0.0, 1.0, 1.5, 5.0], 1e-3, 3);
        assert_eq!(merged.nodes, vec![0.0, 1.25, 5.0]);
    }

    #[test]
    fn brackets_interpolate_and_clamp() {
        let axis = Axis { coordinate: Coordinate::Degrees, nodes: vec![0.0, 3.0, 9.0] };
        assert_eq!(axis.bracket(1.5), Bracket { lower: 0, t: 0.5, outside: false });
        assert_eq!(axis.bracket(3.0), Bracket { lower: 1, t: 0.0, outside: false });
        assert_eq!(axis.bracket(7.5), Bracket { lower: 1, t: 0.75, outside: false });
        assert_eq!(axis.bracket(9.5), Bracket { lower: 1, t: 1.0, outside: true });
        assert_eq!(axis.bracket(-1.0), Bracket { lower: 0, t: 0.0, outside: true });
        assert_eq!(axis.nearest(7.0), 2);
        assert_eq!(axis.nearest(5.0), 1);
    }

    #[test]
    fn merl_theta_h_coordinate_round_trips() {
        for deg in [0.0, 0.01, 1.0, 45.0, 90.0] {
            let c = Coordinate::MerlThetaH;
            assert!((c.to_rad(c.of_rad(f64::to_radians(deg))).to_degrees() - deg).abs() < 1e-9);
        }
        assert!((Coordinate::MerlThetaH.of_rad(1f64.to_radians()) - 90f64.sqrt()).abs() < 1e-12);
    }
}
