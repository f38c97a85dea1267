//! A theta_h column: one scalar BRDF value (the mean of R, G and B, 1/sr) at increasing
//! theta_h positions, with the piecewise-linear interpolation and the re-interpolation error
//! that sections 5.1 and 5.2 of the paper are built on.
//!
//! The re-interpolation error of a set of sample positions is the error of measuring a column
//! at those positions only: each sample takes the column's value there (linear interpolation
//! between the column's nodes), the samples are interpolated back at every node, and the mean
//! absolute difference from the column is the error.

use specula_core::Rgb;

/// The domain in which samples are interpolated back to the column's nodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Interpolation {
    /// Piecewise linear in the value, as the paper does.
    Linear,
    /// Piecewise linear in `ln(value + floor)`, i.e. piecewise exponential in the value; the
    /// floor is [`LOG_FLOOR_FRACTION`] of the column's largest value, so zeros stay finite.
    Log,
}

impl Interpolation {
    /// Both interpolations, linear first.
    pub const ALL: [Interpolation; 2] = [Interpolation::Linear, Interpolation::Log];

    /// The interpolation's name in tables and file names.
    pub fn name(self) -> &'static str {
        match self {
            Interpolation::Linear => "linear",
            Interpolation::Log => "log",
        }
    }
}

/// In the log domain, values are offset by this fraction of the column's peak before the
/// logarithm, so that zeros (the horizon) and noise floors stay finite.
pub const LOG_FLOOR_FRACTION: f64 = 1e-6;

/// The scalar a column holds for an RGB value: the mean of the three channels (docs/book/src/design.md,
/// "Fitting k").
pub fn scalar_of(rgb: Rgb) -> f64 {
    rgb.element_sum() / 3.0
}

/// A column of values at strictly increasing theta_h positions in degrees.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    theta_h_deg: Vec<f64>,
    values: Vec<f64>,
}

/// Why a column cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ColumnError {
    /// The column has fewer than two samples (the count).
    #[error("a column needs at least 2 samples, got {0}")]
    TooShort(usize),
    /// theta_h does not increase strictly between two consecutive samples.
    #[error("theta_h must increase strictly: {previous_deg} deg is followed by {next_deg} deg")]
    NotIncreasing {
        /// The earlier position, deg.
        previous_deg: f64,
        /// The position after it, not larger, deg.
        next_deg: f64,
    },
    /// A theta_h position (deg) lies outside `[0, 90]`.
    #[error("theta_h {0} deg is outside [0, 90]")]
    OutOfRange(f64),
    /// A value is negative, infinite or NaN.
    #[error("the value {value} at theta_h {theta_h_deg} deg is not a finite non-negative number")]
    BadValue {
        /// The position of the value, deg.
        theta_h_deg: f64,
        /// The value, 1/sr.
        value: f64,
    },
}

impl Column {
    /// A column from positions (degrees, strictly increasing within `[0, 90]`) and values
    /// (finite, non-negative, 1/sr).
    pub fn new(theta_h_deg: Vec<f64>, values: Vec<f64>) -> Result<Self, ColumnError> {
        assert_eq!(theta_h_deg.len(), values.len(), "one value per position");
        if theta_h_deg.len() < 2 {
            return Err(ColumnError::TooShort(theta_h_deg.len()));
        }
        for (&x, &v) in theta_h_deg.iter().zip(&values) {
            if !(0.0..=90.0).contains(&x) {
                return Err(ColumnError::OutOfRange(x));
            }
            if !(v.is_finite() && v >= 0.0) {
                return Err(ColumnError::BadValue {
                    theta_h_deg: x,
                    value: v,
                });
            }
        }
        if let Some(w) = theta_h_deg.windows(2).find(|w| w[0] >= w[1]) {
            return Err(ColumnError::NotIncreasing {
                previous_deg: w[0],
                next_deg: w[1],
            });
        }
        Ok(Self {
            theta_h_deg,
            values,
        })
    }

    /// A column from samples where some may be missing (`None`, e.g. cells of a MERL table
    /// that were not measured); the missing ones are left out. `None` when fewer than two
    /// remain.
    pub fn from_partial(theta_h_deg: &[f64], values: &[Option<f64>]) -> Option<Self> {
        let (xs, ys): (Vec<f64>, Vec<f64>) = theta_h_deg
            .iter()
            .zip(values)
            .filter_map(|(&x, v)| v.filter(|v| v.is_finite() && *v >= 0.0).map(|v| (x, v)))
            .unzip();
        Self::new(xs, ys).ok()
    }

    /// The sample positions theta_h, deg, increasing.
    pub fn theta_h_deg(&self) -> &[f64] {
        &self.theta_h_deg
    }

    /// The values at [`Column::theta_h_deg`], one per position.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Number of samples (at least two).
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// The largest value and where it is: `(theta_h_deg, value)`, the first one on a tie.
    pub fn peak(&self) -> (f64, f64) {
        self.theta_h_deg.iter().zip(&self.values).fold(
            (0.0, f64::NEG_INFINITY),
            |best, (&x, &v)| if v > best.1 { (x, v) } else { best },
        )
    }

    /// Always false: a column has at least two samples.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The column's value at each of the increasing positions `at_deg`, by linear
    /// interpolation between nodes, constant beyond the first and last node.
    pub fn sample(&self, at_deg: &[f64]) -> Vec<f64> {
        let mut out = Vec::with_capacity(at_deg.len());
        lerp_sorted(&self.theta_h_deg, &self.values, at_deg, |v| out.push(v));
        out
    }

    /// The error of measuring this column only at `positions_deg` (increasing) and
    /// interpolating the samples back in the given domain: the mean absolute difference from
    /// the column over its nodes, 1/sr (the fit error of paper 5.2 and the slice error of
    /// 5.1 are built on it). Two merge walks; for many columns on the same nodes,
    /// [`Resampling`] does their searches once.
    pub fn reinterpolation_error(&self, positions_deg: &[f64], domain: Interpolation) -> f64 {
        with_sample_buffer(positions_deg.len(), |samples| {
            let mut column = SortedSearch::new(&self.theta_h_deg);
            for (sample, &x) in samples.iter_mut().zip(positions_deg) {
                *sample = column.locate(x).value(&self.values);
            }
            let mut total = 0.0;
            let mut values = self.values.iter();
            let mut next_value = || *values.next().expect("one rebuilt value per node");
            match domain {
                Interpolation::Linear => {
                    lerp_sorted(positions_deg, samples, &self.theta_h_deg, |rebuilt| {
                        total += (rebuilt - next_value()).abs();
                    })
                }
                Interpolation::Log => {
                    let floor = self.log_floor();
                    samples.iter_mut().for_each(|v| *v = (*v + floor).ln());
                    lerp_sorted(positions_deg, samples, &self.theta_h_deg, |rebuilt| {
                        total += (rebuilt.exp() - floor - next_value()).abs();
                    })
                }
            }
            total / self.len() as f64
        })
    }

    /// The offset added before taking logarithms (see [`LOG_FLOOR_FRACTION`]); positive.
    pub fn log_floor(&self) -> f64 {
        let peak = self.values.iter().copied().fold(0.0, f64::max);
        (peak * LOG_FLOOR_FRACTION).max(f64::MIN_POSITIVE)
    }
}

/// Linear interpolation of the polyline `(xs, ys)` (xs increasing) at the increasing
/// positions `at`, constant beyond its ends, handing each result to `emit` in order. One merge
/// walk: O(len(xs) + len(at)).
pub fn lerp_sorted(xs: &[f64], ys: &[f64], at: &[f64], mut emit: impl FnMut(f64)) {
    debug_assert_eq!(xs.len(), ys.len());
    let mut search = SortedSearch::new(xs);
    for &x in at {
        emit(search.locate(x).value(ys));
    }
}

/// Where a position falls on a polyline's nodes.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Located {
    /// At or before the first node: the polyline's first value.
    First,
    /// At or after the last node: its last value.
    Last,
    /// Between nodes `seg` and `seg + 1`, at the fraction `w` of the way.
    Between(usize, f64),
}

impl Located {
    /// The value there of the polyline with values `ys`.
    fn value(self, ys: &[f64]) -> f64 {
        match self {
            Located::First => ys[0],
            Located::Last => ys[ys.len() - 1],
            Located::Between(seg, w) => ys[seg] + w * (ys[seg + 1] - ys[seg]),
        }
    }
}

/// A merge-walk cursor on increasing nodes `xs` for queries at non-decreasing positions: the
/// segment search resumes where the previous query left it.
struct SortedSearch<'a> {
    xs: &'a [f64],
    seg: usize,
}

impl<'a> SortedSearch<'a> {
    fn new(xs: &'a [f64]) -> Self {
        Self { xs, seg: 0 }
    }

    /// Where `x` (not below any earlier query) falls.
    fn locate(&mut self, x: f64) -> Located {
        let xs = self.xs;
        if x <= xs[0] {
            return Located::First;
        }
        if x >= xs[xs.len() - 1] {
            return Located::Last;
        }
        while xs[self.seg + 1] < x {
            self.seg += 1;
        }
        let seg = self.seg;
        let (x0, x1) = (xs[seg], xs[seg + 1]);
        Located::Between(seg, (x - x0) / (x1 - x0))
    }
}

/// Whether two node lists are equal; without stopping at the first difference, so that the
/// comparison vectorises (it is made once per error in [`Resampling::error`]).
fn same_nodes(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).fold(true, |same, (x, y)| same & (x == y))
}

/// Linear interpolation on fixed nodes at fixed increasing positions, of any values: where
/// each position falls, found once. Increasing positions make the ones before the first
/// node a prefix and those after the last a suffix.
#[derive(Debug, Clone)]
struct Stencil {
    /// Positions at or before the first node.
    first: usize,
    /// The positions between nodes: segment and fraction.
    between: Vec<(usize, f64)>,
    /// Positions at or after the last node.
    last: usize,
}

impl Stencil {
    fn new(xs: &[f64], at: &[f64]) -> Self {
        let mut stencil = Self {
            first: 0,
            between: Vec::with_capacity(at.len()),
            last: 0,
        };
        let mut search = SortedSearch::new(xs);
        for &x in at {
            match search.locate(x) {
                Located::First => stencil.first += 1,
                Located::Last => stencil.last += 1,
                Located::Between(seg, w) => stencil.between.push((seg, w)),
            }
        }
        stencil
    }

    /// [`lerp_sorted`] of the values `ys` on the stencil's nodes at its positions.
    fn apply(&self, ys: &[f64], mut emit: impl FnMut(f64)) {
        (0..self.first).for_each(|_| emit(Located::First.value(ys)));
        for &(seg, w) in &self.between {
            emit(Located::Between(seg, w).value(ys));
        }
        (0..self.last).for_each(|_| emit(Located::Last.value(ys)));
    }
}

/// The linear re-interpolation of columns on given nodes from samples at given positions,
/// with where every sample falls among the nodes and every node among the samples found
/// once. The analysis of paper 5.1 takes the error of one set of positions on the 90
/// columns of a slice, which share their nodes, and the fit of 5.2 the errors of the same
/// scan positions on each of them: [`Resampling::error`] then neither searches nor divides.
#[derive(Debug, Clone)]
pub struct Resampling {
    nodes_deg: Vec<f64>,
    positions_deg: Vec<f64>,
    /// The samples: the positions on the nodes.
    sample: Stencil,
    /// The interpolation back: the nodes on the positions.
    back: Stencil,
}

impl Resampling {
    /// For columns on `nodes_deg` sampled at `positions_deg` (both increasing, non-empty).
    pub fn new(nodes_deg: &[f64], positions_deg: &[f64]) -> Self {
        Self {
            nodes_deg: nodes_deg.to_vec(),
            positions_deg: positions_deg.to_vec(),
            sample: Stencil::new(nodes_deg, positions_deg),
            back: Stencil::new(positions_deg, nodes_deg),
        }
    }

    /// The positions the columns are sampled at, deg.
    pub fn positions_deg(&self) -> &[f64] {
        &self.positions_deg
    }

    /// `column.reinterpolation_error(positions, Interpolation::Linear)`, to the last bit
    /// (the same operations on the same operands). A column on other nodes (one with
    /// missing cells) takes that walk instead.
    pub fn error(&self, column: &Column) -> f64 {
        if !same_nodes(&column.theta_h_deg, &self.nodes_deg) {
            return column.reinterpolation_error(&self.positions_deg, Interpolation::Linear);
        }
        with_sample_buffer(self.positions_deg.len(), |samples| {
            let mut slots = samples.iter_mut();
            self.sample.apply(&column.values, |v| {
                *slots.next().expect("one sample per position") = v;
            });
            let mut total = 0.0;
            let mut values = column.values.iter();
            self.back.apply(samples, |rebuilt| {
                let value = values.next().expect("one rebuilt value per node");
                total += (rebuilt - value).abs();
            });
            total / column.len() as f64
        })
    }
}

/// The most samples an error evaluation holds on the stack (the paper takes 30); more are
/// allocated.
const STACK_SAMPLES: usize = 64;

/// Runs `f` on a buffer of `n` samples, on the stack when it fits: an error is evaluated
/// some 50,000 times per material in the analysis of paper 5.1, and an allocation each
/// time would cost a third of it.
fn with_sample_buffer<R>(n: usize, f: impl FnOnce(&mut [f64]) -> R) -> R {
    if n <= STACK_SAMPLES {
        f(&mut [0.0; STACK_SAMPLES][..n])
    } else {
        f(&mut vec![0.0; n])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn column(xs: &[f64], ys: &[f64]) -> Column {
        Column::new(xs.to_vec(), ys.to_vec()).unwrap()
    }

    #[test]
    fn the_peak_is_the_first_largest_value() {
        assert_eq!(
            column(&[0.0, 1.0, 2.0, 3.0], &[1.0, 5.0, 5.0, 2.0]).peak(),
            (1.0, 5.0)
        );
        assert_eq!(column(&[0.5, 1.0], &[0.0, 0.0]).peak(), (0.5, 0.0));
    }

    #[test]
    fn sample_interpolates_and_clamps() {
        let c = column(&[0.0, 10.0, 30.0], &[4.0, 2.0, 6.0]);
        assert_eq!(
            c.sample(&[0.0, 5.0, 10.0, 20.0, 30.0]),
            vec![4.0, 3.0, 2.0, 4.0, 6.0]
        );
        let beyond = column(&[1.0, 2.0], &[1.0, 3.0]);
        assert_eq!(beyond.sample(&[0.0, 1.5, 90.0]), vec![1.0, 2.0, 3.0]);
    }

    #[test]
    fn a_linear_column_is_rebuilt_exactly_from_its_ends() {
        let xs: Vec<f64> = (0..=90).map(f64::from).collect();
        let ys: Vec<f64> = xs.iter().map(|x| 2.0 + 0.5 * x).collect();
        let c = column(&xs, &ys);
        assert!(c.reinterpolation_error(&[0.0, 90.0], Interpolation::Linear) < 1e-12);
    }

    #[test]
    fn an_exponential_column_is_rebuilt_exactly_in_the_log_domain() {
        let xs: Vec<f64> = (0..=90).map(f64::from).collect();
        let ys: Vec<f64> = xs.iter().map(|x| 100.0 * (-0.1 * x).exp()).collect();
        let c = column(&xs, &ys);
        // ln(y + floor) is not exactly linear in x, so the log domain is not exact, but
        // three orders of magnitude better than the linear one.
        let log = c.reinterpolation_error(&[0.0, 90.0], Interpolation::Log);
        let linear = c.reinterpolation_error(&[0.0, 90.0], Interpolation::Linear);
        assert!(
            linear > 1.0 && log < 1e-3 * linear,
            "log {log}, linear {linear}"
        );
    }

    #[test]
    fn a_peak_between_samples_is_missed_by_its_full_height() {
        // Nodes 0, 1, 2 with a spike at 1: sampling the ends gives a flat line, error 10/3.
        let c = column(&[0.0, 1.0, 2.0], &[0.0, 10.0, 0.0]);
        let e = c.reinterpolation_error(&[0.0, 2.0], Interpolation::Linear);
        assert!((e - 10.0 / 3.0).abs() < 1e-12);
    }

    #[test]
    fn bad_columns_are_refused() {
        assert_eq!(
            Column::new(vec![1.0], vec![1.0]),
            Err(ColumnError::TooShort(1))
        );
        assert!(matches!(
            Column::new(vec![1.0, 1.0], vec![1.0, 2.0]),
            Err(ColumnError::NotIncreasing { .. })
        ));
        assert!(matches!(
            Column::new(vec![0.0, 91.0], vec![1.0, 2.0]),
            Err(ColumnError::OutOfRange(_))
        ));
        assert!(matches!(
            Column::new(vec![0.0, 1.0], vec![-1.0, 2.0]),
            Err(ColumnError::BadValue { .. })
        ));
        assert!(Column::from_partial(&[0.0, 1.0, 2.0], &[Some(1.0), None, None]).is_none());
        let c = Column::from_partial(&[0.0, 1.0, 2.0], &[Some(1.0), None, Some(3.0)]).unwrap();
        assert_eq!(c.theta_h_deg(), &[0.0, 2.0]);
    }

    #[test]
    fn a_resampling_serves_columns_on_other_nodes_by_the_walk() {
        let positions = [0.0, 0.5, 3.0, 50.0];
        let plan = Resampling::new(&[0.0, 1.0, 2.0, 90.0], &positions);
        assert_eq!(plan.positions_deg(), &positions);
        let other = column(&[0.0, 2.0, 90.0], &[5.0, 1.0, 0.0]);
        assert_eq!(
            plan.error(&other),
            other.reinterpolation_error(&positions, Interpolation::Linear)
        );
        let own = column(&[0.0, 1.0, 2.0, 90.0], &[5.0, 3.0, 1.0, 0.0]);
        assert_eq!(
            plan.error(&own),
            own.reinterpolation_error(&positions, Interpolation::Linear)
        );
        assert!(plan.error(&own) > 0.1);
    }

    proptest! {
        /// Sampling a column at its own nodes and interpolating back is exact, in both domains.
        #[test]
        fn own_nodes_rebuild_the_column(ys in proptest::collection::vec(0.0..100.0f64, 2..40)) {
            let n = ys.len();
            let xs: Vec<f64> = (0..n).map(|i| 90.0 * (i as f64 / (n - 1) as f64).powi(2)).collect();
            let c = column(&xs, &ys);
            prop_assert!(c.reinterpolation_error(&xs, Interpolation::Linear) < 1e-9);
            prop_assert!(c.reinterpolation_error(&xs, Interpolation::Log) < 1e-9);
        }

        /// The error, directly and through a [`Resampling`], is to the last bit the
        /// computation spelled out: sample the column, then interpolate the samples back onto
        /// the nodes. Positions on a half-degree grid repeat and meet the nodes, to exercise
        /// the ties.
        #[test]
        fn the_error_is_the_spelled_out_computation_to_the_last_bit(
            ys in proptest::collection::vec(0.0..100.0f64, 2..40),
            at in proptest::collection::vec(-10i32..190, 1..40),
        ) {
            let n = ys.len();
            let xs: Vec<f64> = (0..n).map(|i| 90.0 * (i as f64 / (n - 1) as f64).powi(2)).collect();
            let c = column(&xs, &ys);
            let mut positions: Vec<f64> = at.iter().map(|&h| f64::from(h) / 2.0).collect();
            positions.sort_by(f64::total_cmp);
            let samples = c.sample(&positions);
            let floor = c.log_floor();
            let logs: Vec<f64> = samples.iter().map(|v| (v + floor).ln()).collect();
            let (mut linear, mut log) = (0.0, 0.0);
            let mut node = 0;
            lerp_sorted(&positions, &samples, &xs, |r| {
                linear += (r - ys[node]).abs();
                node += 1;
            });
            node = 0;
            lerp_sorted(&positions, &logs, &xs, |r| {
                log += (r.exp() - floor - ys[node]).abs();
                node += 1;
            });
            let one_pass = |domain| c.reinterpolation_error(&positions, domain).to_bits();
            prop_assert_eq!(one_pass(Interpolation::Linear), (linear / n as f64).to_bits());
            prop_assert_eq!(one_pass(Interpolation::Log), (log / n as f64).to_bits());
            let resampled = Resampling::new(&xs, &positions).error(&c);
            prop_assert_eq!(resampled.to_bits(), (linear / n as f64).to_bits());
        }

        /// The merge walk agrees with a per-point binary search.
        #[test]
        fn merge_walk_matches_search(ys in proptest::collection::vec(0.0..10.0f64, 2..20),
                                     mut at in proptest::collection::vec(-5.0..95.0f64, 0..50)) {
            at.sort_by(f64::total_cmp);
            let n = ys.len();
            let xs: Vec<f64> = (0..n).map(|i| 90.0 * i as f64 / (n - 1) as f64).collect();
            let c = column(&xs, &ys);
            let fast = c.sample(&at);
            for (x, v) in at.iter().zip(fast) {
                let i = xs.partition_point(|&p| p <= *x).clamp(1, n - 1);
                let w = ((x - xs[i - 1]) / (xs[i] - xs[i - 1])).clamp(0.0, 1.0);
                let slow = ys[i - 1] + w * (ys[i] - ys[i - 1]);
                prop_assert!((v - slow).abs() < 1e-9, "{x}: {v} vs {slow}");
            }
        }
    }
}
