//! Placing n theta_h samples beyond the paper's one-parameter families.
//!
//! **The oracle** ([`optimal_placement`]): for a known column, the placement of `n` samples
//! among the column's nodes, first and last node included, that minimises the
//! re-interpolation error, found exactly by dynamic programming. With knots at nodes the
//! error splits into independent segments: `cost(a, b)` is the summed absolute error at the
//! nodes strictly between knots `a` and `b` of the interpolation from `a` to `b`, and
//! `E[m][b] = min_a E[m-1][a] + cost(a, b)` is the least error of `m + 1` knots from the
//! first node to node `b`. O(N^3) for the costs, O(n N^2) for the recursion (N = nodes).
//!
//! **The practical placement** ([`place_theta_h`]): the same dynamic programme run on a dense
//! model of the probe (section 5.2's column at theta_d = 40 degrees, interpolated smoothly in
//! the log domain by [`crate::probe_model`]) instead of on the unknown truth. The measurement
//! plan then uses those theta_h for every theta_d; how well that transfers to the other
//! columns is measured by [`crate::placement_study`].

use crate::column::{Column, Interpolation};
use crate::probe::Probe;
use crate::probe_model::dense_model;

/// A placement and its re-interpolation error on the column it was made for.
#[derive(Debug, Clone, PartialEq)]
pub struct Placement {
    /// The sample positions, degrees, increasing.
    pub theta_h_deg: Vec<f64>,
    /// The column's re-interpolation error with these samples, 1/sr.
    pub error: f64,
}

/// The least-error placement of `n >= 2` samples among the nodes of `column` (see the
/// module documentation). With `n` at least the column's length, every node is a sample.
pub fn optimal_placement(column: &Column, n: usize, domain: Interpolation) -> Placement {
    assert!(n >= 2, "a placement needs at least 2 samples");
    let xs = column.theta_h_deg();
    let nodes = xs.len();
    if n >= nodes {
        return Placement {
            theta_h_deg: xs.to_vec(),
            error: column.reinterpolation_error(xs, domain),
        };
    }
    let cost = segment_costs(column, domain);
    let at = |a: usize, b: usize| cost[a * nodes + b];

    // best[b]: least error of the current number of knots from node 0 to node b;
    // parent[m][b]: the knot before b in that optimum.
    let mut best = vec![f64::INFINITY; nodes];
    best[0] = 0.0;
    let mut parent = vec![vec![usize::MAX; nodes]; n];
    for layer in parent.iter_mut().skip(1) {
        let mut next = vec![f64::INFINITY; nodes];
        for b in 1..nodes {
            for (a, &before) in best.iter().enumerate().take(b) {
                let e = before + at(a, b);
                if e < next[b] {
                    next[b] = e;
                    layer[b] = a;
                }
            }
        }
        best = next;
    }
    let mut knots = vec![nodes - 1];
    for layer in parent.iter().skip(1).rev() {
        let before = layer[*knots.last().expect("not empty")];
        knots.push(before);
    }
    knots.reverse();
    debug_assert_eq!(knots[0], 0);
    Placement {
        theta_h_deg: knots.iter().map(|&k| xs[k]).collect(),
        error: best[nodes - 1] / nodes as f64,
    }
}

/// `cost[a * N + b]` for `a < b`: the summed absolute error at nodes `a+1 .. b-1` of the
/// interpolation between nodes `a` and `b` in `domain`.
fn segment_costs(column: &Column, domain: Interpolation) -> Vec<f64> {
    let xs = column.theta_h_deg();
    let ys = column.values();
    let nodes = xs.len();
    let floor = column.log_floor();
    let transformed: Vec<f64> = match domain {
        Interpolation::Linear => ys.to_vec(),
        Interpolation::Log => ys.iter().map(|y| (y + floor).ln()).collect(),
    };
    let back = |v: f64| match domain {
        Interpolation::Linear => v,
        Interpolation::Log => v.exp() - floor,
    };
    let mut cost = vec![0.0; nodes * nodes];
    for a in 0..nodes {
        for b in a + 2..nodes {
            let mut sum = 0.0;
            let span = xs[b] - xs[a];
            for j in a + 1..b {
                let w = (xs[j] - xs[a]) / span;
                let v = transformed[a] + w * (transformed[b] - transformed[a]);
                sum += (back(v) - ys[j]).abs();
            }
            cost[a * nodes + b] = sum;
        }
    }
    cost
}

/// Nodes of the probe's dense model on which [`place_theta_h`] places: three per probe sample.
pub(crate) const MODEL_NODES: usize = 3 * 89 + 1;

/// The practical placement: `n >= 2` theta_h positions in degrees (increasing, the probe's
/// first and last positions included) chosen from the probe alone: the oracle's dynamic
/// programme (linear interpolation, as the reconstruction uses) run on the probe's dense
/// model ([`crate::probe_model`]), so that samples may fall between the probe's own.
/// Reusable by the measurement planner.
pub fn place_theta_h(probe: &Probe, n: usize) -> Vec<f64> {
    place_on_probe_column(&probe.column(), n, Interpolation::Linear)
}

/// [`place_theta_h`] for a probe held as a column, for a reconstruction in `domain`.
pub(crate) fn place_on_probe_column(probe: &Column, n: usize, domain: Interpolation) -> Vec<f64> {
    let model = dense_model(probe, MODEL_NODES.max(probe.len()));
    optimal_placement(&model, n, domain).theta_h_deg
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::column::lerp_sorted;
    use crate::probe::Probe;
    use proptest::prelude::*;
    use specula_core::sampling::{Family, SamplingFunction};
    use specula_core::Rgb;

    /// The least error over every placement, by exhaustive search.
    fn brute_force_best(column: &Column, n: usize, domain: Interpolation) -> f64 {
        let xs = column.theta_h_deg();
        let inner: Vec<usize> = (1..xs.len() - 1).collect();
        let mut best = f64::INFINITY;
        let mut chosen = Vec::new();
        fn walk(
            inner: &[usize],
            start: usize,
            left: usize,
            chosen: &mut Vec<usize>,
            visit: &mut dyn FnMut(&[usize]),
        ) {
            if left == 0 {
                visit(chosen);
                return;
            }
            for i in start..inner.len() {
                chosen.push(inner[i]);
                walk(inner, i + 1, left - 1, chosen, visit);
                chosen.pop();
            }
        }
        walk(&inner, 0, n - 2, &mut chosen, &mut |c| {
            let mut positions = vec![xs[0]];
            positions.extend(c.iter().map(|&k| xs[k]));
            positions.push(xs[xs.len() - 1]);
            best = best.min(column.reinterpolation_error(&positions, domain));
        });
        best
    }

    /// The column sampled at `positions` and interpolated back onto its nodes.
    fn rebuilt(column: &Column, positions: &[f64]) -> Vec<f64> {
        let samples = column.sample(positions);
        let mut out = Vec::new();
        lerp_sorted(positions, &samples, column.theta_h_deg(), |v| out.push(v));
        out
    }

    fn lobe_column(nodes: usize, width_deg: f64) -> Column {
        let xs = SamplingFunction::square_root().positions_deg(nodes);
        let ys = xs
            .iter()
            .map(|x| 0.1 + 50.0 * (-(x / width_deg).powi(2)).exp())
            .collect();
        Column::new(xs, ys).unwrap()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(24))]
        /// On small columns the programme finds the exhaustive search's optimum.
        #[test]
        fn matches_exhaustive_search(ys in proptest::collection::vec(0.0..20.0f64, 5..11),
                                     n in 2usize..6, log in any::<bool>()) {
            let xs: Vec<f64> = (0..ys.len()).map(|i| 90.0 * (i as f64 / (ys.len() - 1) as f64).powi(2)).collect();
            let column = Column::new(xs, ys).unwrap();
            let domain = if log { Interpolation::Log } else { Interpolation::Linear };
            let n = n.min(column.len());
            let dp = optimal_placement(&column, n, domain);
            let brute = brute_force_best(&column, n, domain);
            prop_assert!((dp.error - brute).abs() <= 1e-9 * brute.max(1.0), "{} vs {brute}", dp.error);
            prop_assert_eq!(dp.theta_h_deg.len(), n);
            let actual = column.reinterpolation_error(&dp.theta_h_deg, domain);
            prop_assert!((actual - dp.error).abs() <= 1e-9 * actual.max(1.0));
        }
    }

    #[test]
    fn never_worse_than_the_paper_families() {
        let column = lobe_column(90, 3.0);
        let oracle = optimal_placement(&column, 30, Interpolation::Linear);
        assert_eq!(oracle.theta_h_deg.len(), 30);
        assert_eq!(oracle.theta_h_deg[0], 0.0);
        assert_eq!(*oracle.theta_h_deg.last().unwrap(), 90.0);
        for f in [
            SamplingFunction::square_root(),
            SamplingFunction::new(Family::Exponential, 5.64).unwrap(),
        ] {
            let e = column.reinterpolation_error(&f.positions_deg(30), Interpolation::Linear);
            assert!(oracle.error <= e, "{f:?}: {e} < oracle {}", oracle.error);
        }
        let again = rebuilt(&column, &oracle.theta_h_deg);
        let mae = again
            .iter()
            .zip(column.values())
            .map(|(a, b)| (a - b).abs())
            .sum::<f64>()
            / 90.0;
        assert!((mae - oracle.error).abs() < 1e-12);
    }

    #[test]
    fn more_samples_never_hurt_and_all_nodes_are_exact() {
        let column = lobe_column(40, 5.0);
        let errors: Vec<f64> = (2..=40)
            .map(|n| optimal_placement(&column, n, Interpolation::Linear).error)
            .collect();
        assert!(
            errors.windows(2).all(|w| w[1] <= w[0] + 1e-15),
            "{errors:?}"
        );
        assert!(errors[errors.len() - 1] < 1e-12);
    }

    #[test]
    fn the_practical_placement_is_the_oracle_of_the_probe_model() {
        let column = lobe_column(90, 2.0);
        let rgb = column.values().iter().map(|&v| Rgb::splat(v)).collect();
        let probe = Probe::new(column.theta_h_deg().to_vec(), rgb).unwrap();
        let placed = place_theta_h(&probe, 30);
        let model = dense_model(&column, MODEL_NODES);
        assert_eq!(
            placed,
            optimal_placement(&model, 30, Interpolation::Linear).theta_h_deg
        );
        // Crowded at the peak: half the samples within the lobe's first 3 widths.
        assert!(
            placed.iter().filter(|&&x| x < 6.0).count() >= 15,
            "{placed:?}"
        );
        // On a dense truth it beats the best placement among the probe's own samples.
        let truth = lobe_column(MODEL_NODES, 2.0);
        let on_probe = optimal_placement(&column, 30, Interpolation::Linear).theta_h_deg;
        let ours = truth.reinterpolation_error(&placed, Interpolation::Linear);
        let probe_only = truth.reinterpolation_error(&on_probe, Interpolation::Linear);
        assert!(ours < probe_only, "{ours} vs {probe_only}");
    }
}
