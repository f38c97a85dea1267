//! Ordering the samples of a plan to shorten the measurement: a travelling-salesman path over
//! axis space that starts at the park position, where the cost of an edge is the move plus
//! settle time of [`TimeModel::transition_s`] (per-axis speeds and accelerations, axes in
//! parallel).
//!
//! The heuristic:
//! 1. nearest neighbour from the park position;
//! 2. 2-opt and Or-opt (moving runs of 1 to 3 samples, either way round), both searching only
//!    each sample's nearest neighbours (candidate lists), until neither improves;
//! 3. for each sample, the free alternative position (other camera side, tilted light arm)
//!    that is cheapest between its neighbours on the path;
//!
//! then steps 2 and 3 again with candidate lists for the new positions, for a few rounds.
//! The captures are the same in any order, so what changes is the move and settle time.

use crate::kinematics::AxisPositions;
use crate::plan::{Plan, PlannedSample, Status};
use crate::timing::TimeModel;
use rayon::prelude::*;
use std::collections::BinaryHeap;

/// Tuning of [`order_with`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrderingOptions {
    /// Candidates per sample for 2-opt and Or-opt.
    pub neighbours: usize,
    /// Rounds of (improve the path, re-pick the alternatives).
    pub rounds: usize,
}

impl Default for OrderingOptions {
    fn default() -> Self {
        Self {
            neighbours: 10,
            rounds: 3,
        }
    }
}

/// The plan with its measurable samples reordered (and their positions re-picked among their
/// free alternatives) to shorten the total time; excluded samples stay at the end.
pub fn order(plan: &Plan) -> Plan {
    order_with(plan, &OrderingOptions::default())
}

/// [`order`] with explicit tuning.
pub fn order_with(plan: &Plan, options: &OrderingOptions) -> Plan {
    let (measured, axes): (Vec<&PlannedSample>, Vec<AxisPositions>) = plan.measured().unzip();
    let mut path = Path::new(&plan.time_model, axes);
    let mut tour = path.nearest_neighbour_tour();
    for _ in 0..options.rounds.max(1) {
        let neighbours = path.candidate_lists(options.neighbours.max(1));
        path.improve(&mut tour, &neighbours);
        if !path.repick_alternatives(&tour, &measured) {
            break;
        }
    }
    let mut samples: Vec<PlannedSample> = tour[1..]
        .iter()
        .map(|&node| {
            let mut sample = measured[node - 1].clone();
            if let Status::Ok { axes, .. } = &mut sample.status {
                *axes = path.points[node];
            }
            sample
        })
        .collect();
    samples.extend(plan.samples.iter().filter(|s| !s.status.is_ok()).cloned());
    let mut ordered = Plan {
        samples,
        time_model: plan.time_model.clone(),
    };
    ordered.retime();
    ordered
}

/// Nodes of the path: 0 is the park position, node `k >= 1` is measured sample `k - 1` at its
/// current position.
struct Path<'a> {
    model: &'a TimeModel,
    points: Vec<AxisPositions>,
}

/// Gains smaller than this (seconds) are not worth a move; avoids cycling on rounding.
const MIN_GAIN_S: f64 = 1e-9;

impl<'a> Path<'a> {
    /// The park position, then the measured samples' positions.
    fn new(model: &'a TimeModel, measured_axes: Vec<AxisPositions>) -> Self {
        let mut points = vec![model.park];
        points.extend(measured_axes);
        Self { model, points }
    }

    fn cost(&self, a: usize, b: usize) -> f64 {
        self.model.transition_s(&self.points[a], &self.points[b])
    }

    /// For each node, its `k` cheapest other nodes, cheapest first (never the park node,
    /// which stays first). Scans outwards along the bounding axis and stops once that axis
    /// alone costs more than the k-th best found.
    fn candidate_lists(&self, k: usize) -> Vec<Vec<usize>> {
        let index = AxisIndex::new(self);
        let n = self.points.len();
        (0..n)
            .into_par_iter()
            .map(|a| {
                let mut best: BinaryHeap<(u64, usize)> = BinaryHeap::with_capacity(k + 1);
                let r = index.rank[a];
                let (mut left, mut right) = (r, r + 1);
                loop {
                    let gap_left = (left > 0).then(|| index.coord[a] - index.coord_at(left - 1));
                    let gap_right = (right < n).then(|| index.coord_at(right) - index.coord[a]);
                    let (b, gap) = match (gap_left, gap_right) {
                        (Some(l), Some(h)) if l <= h => {
                            left -= 1;
                            (index.sorted[left], l)
                        }
                        (_, Some(h)) => {
                            right += 1;
                            (index.sorted[right - 1], h)
                        }
                        (Some(l), None) => {
                            left -= 1;
                            (index.sorted[left], l)
                        }
                        (None, None) => break,
                    };
                    if best.len() == k
                        && index.bound_s(self, gap) >= f64::from_bits(best.peek().expect("k > 0").0)
                    {
                        break;
                    }
                    if b == 0 {
                        continue;
                    }
                    // Costs are non-negative, so their bit patterns sort like the numbers.
                    best.push((self.cost(a, b).to_bits(), b));
                    if best.len() > k {
                        best.pop();
                    }
                }
                best.into_sorted_vec().into_iter().map(|(_, b)| b).collect()
            })
            .collect()
    }

    /// Greedy path from the park node: always the cheapest unvisited node next. The
    /// unvisited nodes form a linked list in bounding-axis order, searched outwards from the
    /// current node until the axis bound exceeds the best found.
    fn nearest_neighbour_tour(&self) -> Vec<usize> {
        const NONE: usize = usize::MAX;
        let index = AxisIndex::new(self);
        let n = self.points.len();
        // prev/next over ranks of unvisited nodes.
        let mut prev: Vec<usize> = (0..n).map(|r| if r == 0 { NONE } else { r - 1 }).collect();
        let mut next: Vec<usize> = (0..n)
            .map(|r| if r + 1 == n { NONE } else { r + 1 })
            .collect();
        let mut tour = Vec::with_capacity(n);
        let mut current = 0;
        for _ in 0..n {
            tour.push(current);
            let r = index.rank[current];
            let (p, q) = (prev[r], next[r]);
            if p != NONE {
                next[p] = q;
            }
            if q != NONE {
                prev[q] = p;
            }
            let (mut left, mut right) = (p, q);
            let mut best: Option<(f64, usize)> = None;
            loop {
                let gap_left = (left != NONE).then(|| index.coord[current] - index.coord_at(left));
                let gap_right =
                    (right != NONE).then(|| index.coord_at(right) - index.coord[current]);
                let (rank, gap) = match (gap_left, gap_right) {
                    (Some(l), Some(h)) if l <= h => (left, l),
                    (_, Some(h)) => (right, h),
                    (Some(l), None) => (left, l),
                    (None, None) => break,
                };
                if best.is_some_and(|(c, _)| index.bound_s(self, gap) >= c) {
                    break;
                }
                if rank == left {
                    left = prev[left];
                } else {
                    right = next[right];
                }
                let b = index.sorted[rank];
                let c = self.cost(current, b);
                if best.is_none_or(|(bc, _)| c < bc) {
                    best = Some((c, b));
                }
            }
            match best {
                Some((_, b)) => current = b,
                None => break,
            }
        }
        tour
    }

    /// 2-opt and Or-opt until neither finds an improving move.
    fn improve(&self, tour: &mut Vec<usize>, neighbours: &[Vec<usize>]) {
        loop {
            let a = self.two_opt(tour, neighbours);
            let b = self.or_opt(tour, neighbours);
            if !(a || b) {
                break;
            }
        }
    }

    /// Candidate-list 2-opt on the open path: reversing `tour[i+1..=j]` replaces the edges
    /// `(t_i, t_i+1)` and `(t_j, t_j+1)` by `(t_i, t_j)` and `(t_i+1, t_j+1)` (no second
    /// edge when `j` is last). Returns whether it improved anything.
    fn two_opt(&self, tour: &mut [usize], neighbours: &[Vec<usize>]) -> bool {
        let n = tour.len();
        let mut pos = positions(tour);
        let mut improved_any = false;
        let mut improved = true;
        while improved {
            improved = false;
            for i in 0..n {
                let a = tour[i];
                // The edge after a: (a, succ). Connect a to a neighbour c instead.
                if i + 1 < n {
                    let succ_cost = self.cost(a, tour[i + 1]);
                    for &c in &neighbours[a] {
                        if self.cost(a, c) >= succ_cost {
                            break;
                        }
                        let j = pos[c];
                        let (p, q) = if j > i { (i, j) } else { (j, i) };
                        if q > p + 1 && self.two_opt_gain(tour, p, q) > MIN_GAIN_S {
                            reverse(tour, &mut pos, p + 1, q);
                            improved = true;
                            break;
                        }
                    }
                }
                // The edge before a: (pred, a). Connect a to a neighbour c, whose own
                // predecessor edge goes.
                let i = pos[a];
                if i >= 1 {
                    let pred_cost = self.cost(tour[i - 1], a);
                    for &c in &neighbours[a] {
                        if self.cost(a, c) >= pred_cost {
                            break;
                        }
                        let j = pos[c];
                        if j == 0 {
                            continue;
                        }
                        let (p, q) = if j > i {
                            (i - 1, j - 1)
                        } else {
                            (j - 1, i - 1)
                        };
                        if q > p + 1 && self.two_opt_gain(tour, p, q) > MIN_GAIN_S {
                            reverse(tour, &mut pos, p + 1, q);
                            improved = true;
                            break;
                        }
                    }
                }
            }
            improved_any |= improved;
        }
        improved_any
    }

    /// Time saved by reversing `tour[p+1..=q]`.
    fn two_opt_gain(&self, tour: &[usize], p: usize, q: usize) -> f64 {
        let (a, b, c) = (tour[p], tour[p + 1], tour[q]);
        let mut gain = self.cost(a, b) - self.cost(a, c);
        if let Some(&d) = tour.get(q + 1) {
            gain += self.cost(c, d) - self.cost(b, d);
        }
        gain
    }

    /// Candidate-list Or-opt: move a run of 1 to 3 nodes next to a neighbour of its first or
    /// last node, either way round. Returns whether it improved anything.
    fn or_opt(&self, tour: &mut Vec<usize>, neighbours: &[Vec<usize>]) -> bool {
        let mut pos = positions(tour);
        let mut improved_any = false;
        let mut improved = true;
        while improved {
            improved = false;
            for len in 1..=3 {
                let mut start = 1;
                while start + len <= tour.len() {
                    if let Some((target, reversed)) =
                        self.best_insertion(tour, &pos, start, len, neighbours)
                    {
                        move_run(tour, start, len, target, reversed);
                        let (lo, hi) = (start.min(target), (start + len).max(target + 1));
                        for (i, &node) in tour.iter().enumerate().take(hi + 1).skip(lo) {
                            pos[node] = i;
                        }
                        improved = true;
                    }
                    start += 1;
                }
            }
            improved_any |= improved;
        }
        improved_any
    }

    /// The best place for the run `tour[start..start+len]`: `(k, reversed)` means "after the
    /// node now at position k", with the run reversed or not; `None` when nothing gains.
    fn best_insertion(
        &self,
        tour: &[usize],
        pos: &[usize],
        start: usize,
        len: usize,
        neighbours: &[Vec<usize>],
    ) -> Option<(usize, bool)> {
        let end = start + len - 1;
        let (first, last) = (tour[start], tour[end]);
        let prev = tour[start - 1];
        let next = tour.get(end + 1).copied();
        let removal_gain =
            self.cost(prev, first) + next.map_or(0.0, |x| self.cost(last, x) - self.cost(prev, x));
        if removal_gain <= MIN_GAIN_S {
            return None;
        }
        let mut best: Option<(f64, usize, bool)> = None;
        let mut consider = |k: usize| {
            if k + 1 >= start && k <= end {
                return; // inside or right before the run: no move
            }
            let left = tour[k];
            let right = tour.get(k + 1).copied();
            let join = |x: usize, y: usize| {
                self.cost(left, x) + right.map_or(0.0, |r| self.cost(y, r) - self.cost(left, r))
            };
            for (added, reversed) in [(join(first, last), false), (join(last, first), true)] {
                let gain = removal_gain - added;
                if gain > MIN_GAIN_S && best.is_none_or(|(g, _, _)| gain > g) {
                    best = Some((gain, k, reversed));
                }
            }
        };
        // Only joins to a neighbour cheaper than what removing the run saves can gain.
        for end_node in [first, last] {
            for &c in &neighbours[end_node] {
                if self.cost(end_node, c) >= removal_gain {
                    break;
                }
                let k = pos[c];
                consider(k);
                if k >= 1 {
                    consider(k - 1);
                }
            }
        }
        best.map(|(_, k, reversed)| (k, reversed))
    }

    /// Gives each node the free alternative that is cheapest between its path neighbours.
    /// Returns whether any position changed.
    fn repick_alternatives(&mut self, tour: &[usize], measured: &[&PlannedSample]) -> bool {
        let mut changed = false;
        for k in 1..tour.len() {
            let node = tour[k];
            let prev = self.points[tour[k - 1]];
            let next = tour.get(k + 1).map(|&x| self.points[x]);
            let cost = |at: &AxisPositions| {
                self.model.transition_s(&prev, at)
                    + next.map_or(0.0, |n| self.model.transition_s(at, &n))
            };
            let current = cost(&self.points[node]);
            let best = measured[node - 1]
                .alternatives()
                .iter()
                .map(|alt| (cost(alt), *alt))
                .min_by(|x, y| x.0.total_cmp(&y.0));
            if let Some((c, alt)) = best {
                if c < current - MIN_GAIN_S {
                    self.points[node] = alt;
                    changed = true;
                }
            }
        }
        changed
    }
}

/// The nodes sorted along the axis whose own move and settle time bounds the transition cost
/// best: as the axes move in parallel and the settle is the longest of the moved axes, that
/// axis's move plus settle never exceeds the full cost.
struct AxisIndex {
    axis: usize,
    /// Node ids in increasing coordinate.
    sorted: Vec<usize>,
    /// `rank[node]`: its place in `sorted`.
    rank: Vec<usize>,
    /// `coord[node]`: its coordinate on the axis, radians.
    coord: Vec<f64>,
}

impl AxisIndex {
    /// Picks the axis that needs the longest time to cross the spread of the nodes.
    fn new(path: &Path) -> Self {
        let axis = (0..4)
            .max_by(|&x, &y| {
                let span_time = |axis: usize| {
                    let values = path.points.iter().map(|p| p.as_array()[axis]);
                    let (lo, hi) = values
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                            (lo.min(v), hi.max(v))
                        });
                    path.model.axes[axis].move_time_s(hi - lo)
                };
                span_time(x).total_cmp(&span_time(y))
            })
            .expect("four axes");
        let coord: Vec<f64> = path.points.iter().map(|p| p.as_array()[axis]).collect();
        let mut sorted: Vec<usize> = (0..coord.len()).collect();
        sorted.sort_by(|&a, &b| coord[a].total_cmp(&coord[b]));
        let mut rank = vec![0; coord.len()];
        for (r, &node) in sorted.iter().enumerate() {
            rank[node] = r;
        }
        Self {
            axis,
            sorted,
            rank,
            coord,
        }
    }

    fn coord_at(&self, rank: usize) -> f64 {
        self.coord[self.sorted[rank]]
    }

    /// A lower bound of the transition cost between nodes `gap` apart on this axis.
    fn bound_s(&self, path: &Path, gap: f64) -> f64 {
        if gap > path.model.deadband_rad {
            let motion = &path.model.axes[self.axis];
            motion.move_time_s(gap) + motion.settle_s
        } else {
            0.0
        }
    }
}

/// `pos[node]` = index of `node` in `tour`.
fn positions(tour: &[usize]) -> Vec<usize> {
    let mut pos = vec![0; tour.len()];
    for (i, &node) in tour.iter().enumerate() {
        pos[node] = i;
    }
    pos
}

/// Reverses `tour[from..=to]` and keeps `pos` up to date.
fn reverse(tour: &mut [usize], pos: &mut [usize], from: usize, to: usize) {
    tour[from..=to].reverse();
    for (i, &node) in tour.iter().enumerate().take(to + 1).skip(from) {
        pos[node] = i;
    }
}

/// Moves the run `tour[start..start+len]` to right after the node now at position `after`,
/// reversed if asked.
fn move_run(tour: &mut Vec<usize>, start: usize, len: usize, after: usize, reversed: bool) {
    let mut run: Vec<usize> = tour.drain(start..start + len).collect();
    if reversed {
        run.reverse();
    }
    let insert_at = if after < start {
        after + 1
    } else {
        after + 1 - len
    };
    tour.splice(insert_at..insert_at, run);
}

/// Total move and settle time of a plan's execution order, seconds: what ordering reduces.
pub fn transition_time_s(plan: &Plan) -> f64 {
    plan.steps().iter().map(|s| s.move_s + s.settle_s).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::device::Device;
    use specula_core::sampling::{Family, SamplingFunction};

    fn small_plan() -> (Device, Plan) {
        let device = Device::utia();
        let th = SamplingFunction::new(Family::Exponential, 4.78)
            .unwrap()
            .positions_deg(8);
        let td: Vec<f64> = (0..10).map(|i| i as f64 * 9.0).collect();
        let pd = [0.0, 30.0, 60.0, 90.0];
        let plan = Plan::from_grid(&th, &td, &pd, 45.0, &device);
        (device, plan)
    }

    #[test]
    fn ordering_keeps_every_sample_and_shortens_the_moves() {
        let (device, plan) = small_plan();
        let ordered = order(&plan);
        let mut before: Vec<usize> = plan.samples.iter().map(|s| s.index).collect();
        let mut after: Vec<usize> = ordered.samples.iter().map(|s| s.index).collect();
        before.sort_unstable();
        after.sort_unstable();
        assert_eq!(before, after);

        let (a, b) = (plan.summary(&device), ordered.summary(&device));
        assert_eq!(
            (a.measurable, a.limit, a.occluded),
            (b.measurable, b.limit, b.occluded)
        );
        assert!((a.capture_s - b.capture_s).abs() < 1e-6);
        assert!(
            transition_time_s(&ordered) < transition_time_s(&plan),
            "{} vs {}",
            transition_time_s(&ordered),
            transition_time_s(&plan)
        );
        // Every position is still a free alternative that gives the sample's directions.
        for (s, axes) in ordered.measured() {
            assert!(s.alternatives().contains(&axes));
            let (wi, wo) = axes.directions();
            assert!((wi - s.wi).length() < 1e-9 && (wo - s.wo).length() < 1e-9);
        }
    }

    /// Exhaustive search on a handful of samples: the heuristic should find the optimum (or
    /// be within a few percent of it) on such small problems.
    #[test]
    fn near_optimal_on_tiny_instances() {
        let device = Device::utia();
        let hds: Vec<_> = [
            (2.0, 30.0, 0.0),
            (20.0, 10.0, 90.0),
            (5.0, 45.0, 45.0),
            (40.0, 20.0, 15.0),
            (1.0, 60.0, 75.0),
            (12.0, 33.0, 30.0),
            (30.0, 5.0, 60.0),
        ]
        .iter()
        .map(|&(th, td, pd)| specula_core::HalfDiff::from_degrees(th, 45.0, td, pd))
        .collect();
        let plan = Plan::from_half_diffs(&hds, &device);
        let measured: Vec<&PlannedSample> = plan.measured().map(|(s, _)| s).collect();
        assert_eq!(measured.len(), hds.len());
        let ordered = order(&plan);
        let heuristic = transition_time_s(&ordered);

        // Brute force over every order and every alternative per sample (small enough).
        let model = &plan.time_model;
        let mut best = f64::INFINITY;
        let mut perm: Vec<usize> = (0..measured.len()).collect();
        permute(&mut perm, 0, &mut |order: &[usize]| {
            // Dynamic programming over alternatives along this order.
            let mut costs: Vec<(AxisPositions, f64)> = vec![(model.park, 0.0)];
            for &k in order {
                costs = measured[k]
                    .alternatives()
                    .iter()
                    .map(|alt| {
                        let c = costs
                            .iter()
                            .map(|(p, c)| c + model.transition_s(p, alt))
                            .fold(f64::INFINITY, f64::min);
                        (*alt, c)
                    })
                    .collect();
            }
            let total = costs.iter().map(|c| c.1).fold(f64::INFINITY, f64::min);
            best = best.min(total);
        });
        assert!(
            heuristic <= best * 1.05 + 1e-9,
            "heuristic {heuristic} vs optimum {best}"
        );
        assert!(heuristic >= best - 1e-9);
    }

    fn permute(v: &mut Vec<usize>, k: usize, visit: &mut impl FnMut(&[usize])) {
        if k == v.len() {
            visit(v);
            return;
        }
        for i in k..v.len() {
            v.swap(k, i);
            permute(v, k + 1, visit);
            v.swap(k, i);
        }
    }

    #[test]
    fn plans_with_nothing_to_order() {
        let device = Device::utia();
        // Only an unreachable and an occluded sample.
        let hds = [
            specula_core::HalfDiff::from_degrees(60.0, 45.0, 60.0, 0.0),
            specula_core::HalfDiff::from_degrees(0.0, 45.0, 0.0, 0.0),
        ];
        let plan = Plan::from_half_diffs(&hds, &device);
        let ordered = order(&plan);
        assert_eq!(ordered.samples.len(), 2);
        assert_eq!(transition_time_s(&ordered), 0.0);
        let one = Plan::from_half_diffs(&hds[..0], &device);
        assert!(order(&one).samples.is_empty());
        let options = OrderingOptions {
            neighbours: 0,
            rounds: 0,
        };
        let (_, small) = small_plan();
        let ordered = order_with(&small, &options);
        assert_eq!(ordered.measured().count(), small.measured().count());
    }

    #[test]
    fn run_moves_are_correct() {
        let mut t = vec![0, 1, 2, 3, 4, 5, 6];
        move_run(&mut t, 1, 2, 4, false); // [1, 2] after node at 4 (= 4)
        assert_eq!(t, vec![0, 3, 4, 1, 2, 5, 6]);
        let mut t = vec![0, 1, 2, 3, 4, 5, 6];
        move_run(&mut t, 4, 3, 1, true); // [4, 5, 6] reversed after 1
        assert_eq!(t, vec![0, 1, 6, 5, 4, 2, 3]);
        let mut t = vec![0, 1, 2, 3];
        let mut pos = positions(&t);
        reverse(&mut t, &mut pos, 1, 3);
        assert_eq!(t, vec![0, 3, 2, 1]);
        assert_eq!(pos, positions(&t));
    }
}
