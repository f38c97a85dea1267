//! Fitting the parameter k of a theta_h sampling function to a dense column (paper 5.2).
//!
//! The fit error of a candidate k (docs/book/src/design.md, "Fitting k"): take the `n` positions `g_k(t)`,
//! give each the column's value there by linear interpolation in theta_h, interpolate those
//! back linearly at the column's own positions, and average the absolute difference from the
//! column (on the mean of R, G and B). k-hat minimises it.
//!
//! ## How the minimum is found, and local minima
//! The error is piecewise smooth in k with a kink each time a sample position crosses a node
//! of the column, so on a narrow peak it is a saw-tooth (teeth of about 10 % of the error,
//! a few percent of k apart) on top of a broad basin. The search works in a scan coordinate
//! `s` in which the families are evenly resolved (`s = ln k` for power and exponential,
//! `s = ln ln k` for base-k), in three stages ([`FitSearch`]):
//!
//! 1. a coarse scan of 64 evenly spaced `s` over the whole range (steps of 13 % in k) finds
//!    the broad basin;
//! 2. a fine scan of 128 points over 4 coarse steps either side of its lowest point (steps
//!    of 0.7 % in k) resolves the teeth;
//! 3. Brent's method (`argmin::BrentOpt`) refines each of the 3 lowest local minima of the
//!    fine scan on the bracket between its two neighbours;
//!
//! and k-hat is the lowest point seen in any stage. A global minimum outside the fine
//! window, or in a tooth narrower than a fine step, can be missed: against a brute-force
//! scan of 20,000 points, on Gaussian lobes 0.3 to 25 degrees wide, the result was never
//! more than 0.4 % worse (test `matches_a_brute_force_search_on_a_specular_lobe`), with
//! about 265 evaluations of the error.
//!
//! The base-k function `m (k^(t/m) - 1) / (k - 1)` is the exponential one with
//! `k_exp = ln k_base` (divide numerator and denominator by one), so both families give the
//! same positions and errors up to rounding, and the ranges are chosen to match: their fits
//! agree to within Brent's tolerance (rounding can steer the two Brent searches a few 1e-8
//! of k apart). The analysis of section 5.1 therefore takes base-k from the exponential fit
//! ([`base_of_exponential`]) instead of fitting it again.
//!
//! ## Cost
//! An evaluation of the error is 30 powers or exponentials for the positions and two merge
//! walks (about 0.4 and 0.2 microseconds). The 192 scan points are the same for every
//! column, so [`KFitter`], which fits many columns (the 90 of a slice in 5.1), computes their
//! positions once, and with the columns' shared nodes their [`Resampling`], which leaves a
//! scan point under 0.1 microseconds; Brent's evaluations (about 75 per fit) are computed
//! in full.

use crate::column::{Column, Interpolation, Resampling};
use argmin::core::{CostFunction, Error as ArgminError, Executor};
use argmin::solver::brent::BrentOpt;
use specula_core::sampling::{Family, InvalidK, SamplingFunction};
use std::collections::HashMap;

/// Brent's iteration limit per basin.
const BRENT_MAX_ITERS: u64 = 60;

/// The range of k searched: `[min, max]` for power and exponential; base-k searches
/// `[e^min, e^max]`, the same positions as the exponential range.
pub const K_RANGE: (f64, f64) = (0.02, 40.0);

/// k-hat and its fit error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KFit {
    /// The sampling function with the fitted k-hat.
    pub function: SamplingFunction,
    /// The fit error at k-hat, 1/sr (docs/book/src/design.md, "Fitting k").
    pub error: f64,
    /// How many times the error was evaluated.
    pub evaluations: usize,
}

/// Why a fit is impossible.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FitError {
    /// A sampling function has fewer than two samples (the count).
    #[error("need at least 2 samples per sampling function, got {0}")]
    TooFewSamples(usize),
    /// Every value of the column is 0: any k rebuilds it exactly, so k-hat would be made
    /// up.
    #[error("every value of the probe is 0 1/sr: there is no peak to fit k to")]
    ZeroColumn,
}

/// The fit error (docs/book/src/design.md, "Fitting k") of `function` with `n` samples against the dense column, 1/sr.
pub fn fit_error(column: &Column, function: &SamplingFunction, n: usize) -> f64 {
    column.reinterpolation_error(&function.positions_deg(n), Interpolation::Linear)
}

/// The family's k for a scan coordinate.
fn k_of(family: Family, s: f64) -> f64 {
    match family {
        Family::Power | Family::Exponential => s.exp(),
        Family::Base => s.exp().exp(),
    }
}

fn s_range() -> (f64, f64) {
    (K_RANGE.0.ln(), K_RANGE.1.ln())
}

/// The `n` sample positions of the family's function at scan coordinate `s`; `None` where k
/// is outside the family's domain.
fn positions_at(family: Family, s: f64, n: usize) -> Option<Vec<f64>> {
    SamplingFunction::new(family, k_of(family, s))
        .ok()
        .map(|f| f.positions_deg(n))
}

/// The base-k function with the positions of the exponential function of parameter
/// `k_exponential`: `k_base = e^k_exponential` (see the module documentation). Section 5.1's
/// analysis takes its base-k fits from its exponential ones with it instead of fitting again.
pub fn base_of_exponential(k_exponential: f64) -> Result<SamplingFunction, InvalidK> {
    SamplingFunction::new(Family::Base, k_exponential.exp())
}

/// The cost that argmin minimises: the fit error as a function of the scan coordinate.
struct ScanCost<'a> {
    column: &'a Column,
    family: Family,
    n: usize,
}

impl CostFunction for ScanCost<'_> {
    type Param = f64;
    type Output = f64;
    fn cost(&self, s: &f64) -> Result<f64, ArgminError> {
        Ok(
            positions_at(self.family, *s, self.n).map_or(f64::INFINITY, |positions| {
                self.column
                    .reinterpolation_error(&positions, Interpolation::Linear)
            }),
        )
    }
}

/// How [`fit_k`] searches for the minimum (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitSearch {
    /// Points of the coarse scan over the whole range.
    pub coarse_points: usize,
    /// Points of the fine scan around the coarse scan's lowest point.
    pub fine_points: usize,
    /// Half-width of the fine scan's window, in coarse steps.
    pub window_steps: f64,
    /// How many of the fine scan's lowest local minima Brent's method refines.
    pub refined_basins: usize,
}

impl Default for FitSearch {
    fn default() -> Self {
        Self {
            coarse_points: 64,
            fine_points: 128,
            window_steps: 4.0,
            refined_basins: 3,
        }
    }
}

/// Fits k of `family` for `n` samples to the dense `column` with the default search (see
/// the module documentation). A column that is 0 everywhere is refused ([`FitError::ZeroColumn`]).
pub fn fit_k(column: &Column, family: Family, n: usize) -> Result<KFit, FitError> {
    if column.values().iter().all(|&v| v == 0.0) {
        return Err(FitError::ZeroColumn);
    }
    fit_k_with(column, family, n, &FitSearch::default())
}

/// [`fit_k`] with an explicit search.
pub fn fit_k_with(
    column: &Column,
    family: Family,
    n: usize,
    search: &FitSearch,
) -> Result<KFit, FitError> {
    Ok(KFitter::new(family, n, search, None)?.fit(column))
}

/// [`fit_k_with`] for many columns: section 5.1 fits the 90 theta_d columns of a slice with
/// the same family and `n`. The sample positions of the coarse scan, and of each fine scan
/// window once used, do not depend on the column, and computing them (a power or an
/// exponential per position) is much of the cost of an error evaluation; the fitter computes
/// them once. Given the nodes the columns share, it also finds once where the positions
/// fall among the nodes and the nodes among the positions ([`Resampling`]), the rest of
/// that cost. Its fits are those of [`fit_k_with`], to the last bit.
pub struct KFitter {
    family: Family,
    n: usize,
    search: FitSearch,
    nodes_deg: Option<Vec<f64>>,
    coarse: ScanGrid,
    /// The fine scan windows used so far, by the coarse point they are centred on.
    fine: HashMap<usize, ScanGrid>,
}

impl KFitter {
    /// A fitter of k of `family` for `n >= 2` samples with the given search, for columns
    /// on `nodes_deg` if given (others are fitted too, without the precomputed weights).
    pub fn new(
        family: Family,
        n: usize,
        search: &FitSearch,
        nodes_deg: Option<&[f64]>,
    ) -> Result<Self, FitError> {
        if n < 2 {
            return Err(FitError::TooFewSamples(n));
        }
        let (lo, hi) = s_range();
        let points = search.coarse_points.max(2);
        Ok(Self {
            family,
            n,
            search: *search,
            nodes_deg: nodes_deg.map(<[f64]>::to_vec),
            coarse: ScanGrid::new(family, n, (lo, hi, points), nodes_deg),
            fine: HashMap::new(),
        })
    }

    /// k-hat for `column` (see the module documentation for the search).
    pub fn fit(&mut self, column: &Column) -> KFit {
        let (family, n, search) = (self.family, self.n, self.search);
        let coarse = self.coarse.scan(column);
        let (centre, coarse_best) = lowest(&coarse);
        let nodes_deg = self.nodes_deg.as_deref();
        let fine_grid = self.fine.entry(centre).or_insert_with(|| {
            let (lo, hi) = s_range();
            let half = search.window_steps * (hi - lo) / (coarse.len() - 1) as f64;
            let window = (
                (coarse_best.0 - half).max(lo),
                (coarse_best.0 + half).min(hi),
                search.fine_points.max(2),
            );
            ScanGrid::new(family, n, window, nodes_deg)
        });
        let fine = fine_grid.scan(column);
        let mut evaluations = coarse.len() + fine.len();
        let mut best = lowest(&[coarse_best, lowest(&fine).1]).1;

        for i in lowest_local_minima(&fine, search.refined_basins) {
            let left = fine[i.saturating_sub(1)].0;
            let right = fine[(i + 1).min(fine.len() - 1)].0;
            let solver = BrentOpt::new(left, right).set_tolerance(1e-8, 1e-9);
            let problem = ScanCost { column, family, n };
            let Ok(result) = Executor::new(problem, solver)
                .configure(|state| state.counting(true).max_iters(BRENT_MAX_ITERS))
                .run()
            else {
                continue;
            };
            let state = result.state();
            evaluations += state.counts.get("cost_count").copied().unwrap_or(0) as usize;
            if let Some(s) = state.best_param {
                if state.best_cost < best.1 {
                    best = (s, state.best_cost);
                }
            }
        }
        let function = SamplingFunction::new(family, k_of(family, best.0))
            .expect("the scan range is inside every family's domain");
        KFit {
            function,
            error: best.1,
            evaluations,
        }
    }
}

/// The sample positions of one scan point, with their [`Resampling`] on the fitter's nodes
/// when it has some.
enum ScanPositions {
    /// k is outside the family's domain: the error is infinite.
    Outside,
    Positions(Vec<f64>),
    Resampled(Resampling),
}

impl ScanPositions {
    fn error(&self, column: &Column) -> f64 {
        match self {
            ScanPositions::Outside => f64::INFINITY,
            ScanPositions::Positions(p) => column.reinterpolation_error(p, Interpolation::Linear),
            ScanPositions::Resampled(r) => r.error(column),
        }
    }
}

/// Evenly spaced scan coordinates and the family's sample positions at each.
struct ScanGrid {
    points: Vec<(f64, ScanPositions)>,
}

impl ScanGrid {
    /// `points` scan coordinates evenly spaced over `[lo, hi]`.
    fn new(
        family: Family,
        n: usize,
        (lo, hi, points): (f64, f64, usize),
        nodes_deg: Option<&[f64]>,
    ) -> Self {
        let step = (hi - lo) / (points - 1) as f64;
        let points = (0..points)
            .map(|i| {
                let s = lo + step * i as f64;
                let positions = match (positions_at(family, s, n), nodes_deg) {
                    (None, _) => ScanPositions::Outside,
                    (Some(p), None) => ScanPositions::Positions(p),
                    (Some(p), Some(nodes)) => ScanPositions::Resampled(Resampling::new(nodes, &p)),
                };
                (s, positions)
            })
            .collect();
        Self { points }
    }

    /// The fit error of `column` at every point of the grid: `(s, error)`.
    fn scan(&self, column: &Column) -> Vec<(f64, f64)> {
        self.points
            .iter()
            .map(|(s, positions)| (*s, positions.error(column)))
            .collect()
    }
}

/// The lowest point of a scan and its index (the first of equals).
fn lowest(scan: &[(f64, f64)]) -> (usize, (f64, f64)) {
    scan.iter()
        .copied()
        .enumerate()
        .min_by(|a, b| a.1 .1.total_cmp(&b.1 .1))
        .expect("a scan is not empty")
}

/// Indices of the (at most) `count` lowest local minima of a scan, lowest first. Plateaus
/// count once, at their first point; the ends count when lower than their one neighbour.
fn lowest_local_minima(scan: &[(f64, f64)], count: usize) -> Vec<usize> {
    let value = |i: usize| scan[i].1;
    let mut minima: Vec<usize> = (0..scan.len())
        .filter(|&i| {
            let left_ok = i == 0 || value(i - 1) > value(i);
            let right_ok = i + 1 == scan.len() || value(i + 1) >= value(i);
            left_ok && right_ok
        })
        .collect();
    minima.sort_by(|&a, &b| value(a).total_cmp(&value(b)));
    minima.truncate(count);
    minima
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A dense column on the probe's square-root positions from a known function.
    fn dense_column(f: impl Fn(f64) -> f64) -> Column {
        let xs = SamplingFunction::square_root().positions_deg(90);
        let ys = xs.iter().map(|&x| f(x)).collect();
        Column::new(xs, ys).unwrap()
    }

    /// A column that is the polyline through the `n` positions of `function` with values
    /// halving from one to the next (a peak at theta_h = 0), known at those positions and
    /// at the probe's: sampling it with `function` rebuilds it exactly (error 0), any
    /// other k does not, so k-hat must come back as the function's k.
    fn polyline_of(function: SamplingFunction, n: usize) -> Column {
        let knots = function.positions_deg(n);
        let heights: Vec<f64> = (0..n).map(|i| 100.0 * 0.5f64.powi(i as i32)).collect();
        let mut xs = SamplingFunction::square_root().positions_deg(90);
        xs.extend_from_slice(&knots);
        xs.sort_by(f64::total_cmp);
        xs.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        let knot_column = Column::new(knots, heights).unwrap();
        let ys = knot_column.sample(&xs);
        Column::new(xs, ys).unwrap()
    }

    /// Brute force over a fine grid of k, the slow and obviously right way.
    fn brute_force(column: &Column, family: Family, n: usize) -> (f64, f64) {
        let (lo, hi) = s_range();
        (0..20_000)
            .map(|i| {
                let s = lo + (hi - lo) * i as f64 / 19_999.0;
                let f = SamplingFunction::new(family, k_of(family, s)).unwrap();
                (f.k, fit_error(column, &f, n))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap()
    }

    #[test]
    fn recovers_k_of_a_column_built_from_the_sampling_function() {
        for (family, k0) in [
            (Family::Exponential, 4.78),
            (Family::Exponential, 5.64),
            (Family::Exponential, 1.5),
            (Family::Power, 3.3),
            (Family::Base, 250.0),
        ] {
            let truth = SamplingFunction::new(family, k0).unwrap();
            let fit = fit_k(&polyline_of(truth, 12), family, 12).unwrap();
            assert!(
                (fit.function.k - k0).abs() < 1e-4 * k0,
                "{family} k0 {k0}: {fit:?}"
            );
            assert!(fit.error < 1e-6, "{fit:?}");
            // Any other k is worse.
            let off = SamplingFunction::new(family, k0 * 1.05).unwrap();
            assert!(fit_error(&polyline_of(truth, 12), &off, 12) > 1e-3);
        }
    }

    #[test]
    fn matches_a_brute_force_search_on_a_specular_lobe() {
        // A Beckmann-like lobe over a diffuse floor, the shape of a glossy paint.
        let lobe = |x: f64| {
            let t = x.to_radians().tan();
            0.05 + 40.0 * (-(t * t) / 0.01).exp()
        };
        let column = dense_column(lobe);
        for family in Family::ALL {
            let fit = fit_k(&column, family, 30).unwrap();
            let (_, brute_error) = brute_force(&column, family, 30);
            // Never worse than the brute force by more than 1 %, and usually better.
            assert!(
                fit.error <= brute_error * 1.01,
                "{family}: {fit:?} vs brute {brute_error}"
            );
            assert!(fit.evaluations < 400, "{fit:?}");
        }
    }

    #[test]
    fn base_k_is_the_exponential_family_in_disguise() {
        let lobe = |x: f64| 3.0 / (1.0 + (x / 2.0).powi(2)) + 0.1;
        let column = dense_column(lobe);
        let exp = fit_k(&column, Family::Exponential, 30).unwrap();
        let base = fit_k(&column, Family::Base, 30).unwrap();
        assert!((base.function.k.ln() - exp.function.k).abs() < 1e-6 * exp.function.k);
        assert!((base.error - exp.error).abs() < 1e-9 * exp.error.max(1e-12));
    }

    #[test]
    fn a_fitter_reused_over_columns_fits_each_as_fit_k_does() {
        // Lobes from 0.3 to 30 degrees wide, whose fine windows differ and recur, and a
        // column on other nodes.
        let mut columns: Vec<Column> = [0.3, 30.0, 2.0, 0.3, 8.0, 2.0]
            .iter()
            .map(|&width| dense_column(|x| 0.05 + 40.0 * (-(x / width).powi(2)).exp()))
            .collect();
        let truth = SamplingFunction::new(Family::Exponential, 4.78).unwrap();
        columns.push(polyline_of(truth, 30));
        let nodes = columns[0].theta_h_deg().to_vec();
        for family in Family::ALL {
            for shared_nodes in [None, Some(nodes.as_slice())] {
                let mut fitter =
                    KFitter::new(family, 30, &FitSearch::default(), shared_nodes).unwrap();
                for column in &columns {
                    assert_eq!(fitter.fit(column), fit_k(column, family, 30).unwrap());
                }
                assert!(fitter.fine.len() >= 3, "{family}: {}", fitter.fine.len());
            }
        }
    }

    #[test]
    fn base_of_exponential_has_the_same_positions() {
        for k in [0.02, 1.0, 4.78, 40.0] {
            let exponential = SamplingFunction::new(Family::Exponential, k).unwrap();
            let base = base_of_exponential(k).unwrap();
            assert_eq!(base.family, Family::Base);
            for (a, b) in base
                .positions_deg(30)
                .iter()
                .zip(exponential.positions_deg(30))
            {
                assert!((a - b).abs() <= 1e-12 * b.max(1e-300), "k {k}: {a} vs {b}");
            }
        }
        assert!(base_of_exponential(0.0).is_err());
    }

    #[test]
    fn too_few_samples_is_an_error() {
        let column = dense_column(|x| x);
        assert_eq!(
            fit_k(&column, Family::Power, 1),
            Err(FitError::TooFewSamples(1))
        );
    }

    #[test]
    fn local_minima_are_ranked() {
        let scan: Vec<(f64, f64)> = [5.0, 3.0, 4.0, 1.0, 2.0, 2.0, 0.5]
            .iter()
            .enumerate()
            .map(|(i, &v)| (i as f64, v))
            .collect();
        assert_eq!(lowest_local_minima(&scan, 3), vec![6, 3, 1]);
        assert_eq!(lowest_local_minima(&scan, 1), vec![6]);
    }
}
