//! The samples' camera noise taken out of the residual, as far as the noise explains it.
//!
//! The lattice holds each sample's log ratio to the fitted lobe ([`crate::domain`]), and the
//! table interpolates it, so every sample's camera noise (its HDR merge's shot, read and dark
//! noise through the colour matrix, [`Sample::noise_rel`]) goes into the table as captured.
//! Where a material is its lobe to within that noise (a near-diffuse fabric measured in an
//! hour: 0.05 % per sample), the noise is the table's error, and the paper's way, which
//! averages twelve captures at each of its 4,000 samples, does better than 700 samples
//! interpolated one by one.
//!
//! A sample's noise here is its camera noise and the light's positioning error through the
//! cosine of incidence the value is divided by ([`incidence_sigma`]): both are independent from
//! sample to sample, and both are what averaging takes out. Each channel is smoothed within its
//! own noise: a strongly coloured paint's bright channels are several times less noisy than
//! its dark one, and smoothed within the dark one's noise they would lose real structure.
//!
//! Among the residuals that depart from the measured values by what that noise explains, this
//! takes the smoothest. In each channel the node values `v` minimise
//!
//! `sum_i (v_i - y_i)^2 / sigma_i^2 + lambda sum_t (v_t - lin_t(v))^2`
//!
//! over the measured nodes `i` of the lattice (`y_i` the mean of its samples' values, `sigma_i`
//! the standard deviation of that mean), where `lin_t` is the value at node `t` of the straight
//! line through its two measured neighbours along one axis: a second difference in each axis's
//! own spacing, which lets any linear trend through. `lambda` is the largest for which the
//! departures `|v_i - y_i| / sigma_i` have the scale of a standard normal's (their median
//! 0.6745: the discrepancy principle, taken on the median so that a few nodes where the
//! residual has structure do not stop the smoothing of the rest), and no node moves by more than
//! [`MAX_MOVE_SIGMAS`] of its noise. A residual with structure far above the noise (a glossy
//! material's) keeps it: a departure of the noise's size does not smooth it. Samples without a
//! known noise (a samples CSV file) are left as measured, and so is a node that holds a lower
//! bound (a sample saturated in every capture).

use crate::consistency::POSITIONING_ACCURACY_DEG;
use crate::lattice::{Lattice, NodeStatus};
use argmin::core::{Error, Executor, Operator};
use argmin::solver::conjugategradient::ConjugateGradient;
use specula_core::statistics::{median, normal_scale_of_absolute};
use specula_core::Sample;

/// No node's value moves by more than this many of its standard deviations.
pub(crate) const MAX_MOVE_SIGMAS: f64 = 2.0;

/// `lambda` is searched between these powers of ten of the nodes' median weight.
const LOG10_LAMBDA_RANGE: (f64, f64) = (-6.0, 8.0);

/// Steps of the bisection of `log10 lambda`.
const BISECTIONS: usize = 20;

/// The conjugate gradients stop when the squared residual of the scaled system is below this
/// fraction of its right-hand side's.
const CG_TOLERANCE: f64 = 1e-16;

/// At most this many conjugate-gradient steps per solve.
const MAX_CG_ITERATIONS: u64 = 2_000;

/// `values` (one per sample, in a reconstruction's domain) with each sample moved by its
/// node's correction, channel by channel within that channel's noise (see the module
/// documentation); unchanged when no sample's noise is known.
pub(crate) fn smoothed(samples: &[Sample], values: &[[f64; 3]]) -> Vec<[f64; 3]> {
    if samples.iter().all(|s| s.noise_rel.is_none()) {
        return values.to_vec();
    }
    let lattice = Lattice::of_samples(samples, values);
    let nodes = MeasuredNodes::of(&lattice, samples);
    if nodes.index.is_empty() {
        return values.to_vec();
    }
    let corrections: [Vec<f64>; 3] = std::array::from_fn(|c| {
        let y: Vec<f64> = nodes.index.iter().map(|&n| lattice.values[c][n]).collect();
        nodes.channel(c).corrections(&y)
    });
    samples
        .iter()
        .zip(values)
        .map(|(s, v)| {
            let k = nodes.position[lattice.node_of(s)];
            std::array::from_fn(|c| v[c] + corrections[c][k])
        })
        .collect()
}

/// The relative standard deviation of a sample's value per channel from its camera noise and
/// the light's positioning ([`incidence_sigma`]), independent from sample to sample; `None`
/// in a channel whose camera noise is not known or not finite (a lower bound).
pub(crate) fn value_sigma(sample: &Sample) -> [Option<f64>; 3] {
    let Some(camera) = sample.noise_rel else {
        return [None; 3];
    };
    let incidence = incidence_sigma(sample);
    std::array::from_fn(|c| {
        let n = camera[c];
        (n > 0.0 && n.is_finite()).then(|| n.hypot(incidence))
    })
}

/// The relative standard deviation of a sample's value from the light's positioning: the
/// value divides the capture by the cosine of the incidence the light was commanded to, while
/// the light stood within [`POSITIONING_ACCURACY_DEG`] of it (one standard deviation), and
/// `d ln cos(theta_i) = -tan(theta_i) d theta_i`: 0.05 % at 45 deg, 0.2 % at 75 deg.
fn incidence_sigma(sample: &Sample) -> f64 {
    let (to_light, _) = sample.directions();
    let cos = to_light.z.clamp(MIN_COS_INCIDENCE, 1.0);
    (1.0 - cos * cos).sqrt() / cos * POSITIONING_ACCURACY_DEG.to_radians()
}

/// The incidence's cosine is taken as at least this (88 deg), where a sample still holds a
/// value.
const MIN_COS_INCIDENCE: f64 = 0.035;

/// A measured node and its two measured neighbours along one axis: `v_node - (before_weight
/// v_before + after_weight v_after)` is its departure from the straight line through them.
#[derive(Debug, Clone, Copy)]
struct Triple {
    node: usize,
    before: usize,
    before_weight: f64,
    after: usize,
    after_weight: f64,
}

/// The measured nodes of a lattice with their noise in each channel, and the triples of the
/// smoothness penalty; nodes are numbered by their position among the measured ones.
struct MeasuredNodes {
    /// Each measured node's index in the lattice.
    index: Vec<usize>,
    /// The position in `index` of each lattice node (`usize::MAX` where not measured).
    position: Vec<usize>,
    /// Each measured node's weight `1 / sigma^2` per channel; zero for a node kept as
    /// measured in that channel.
    weight: [Vec<f64>; 3],
    triples: Vec<Triple>,
}

impl MeasuredNodes {
    fn of(lattice: &Lattice, samples: &[Sample]) -> Self {
        let index: Vec<usize> = (0..lattice.status.len())
            .filter(|&n| lattice.status[n] == NodeStatus::Measured)
            .collect();
        let mut position = vec![usize::MAX; lattice.status.len()];
        for (k, &n) in index.iter().enumerate() {
            position[n] = k;
        }
        // The variance of a node's mean: the sum of its samples' variances over n^2; a node
        // with a sample of unknown or infinite noise in a channel is kept as measured there.
        let mut variance_sum = vec![[0.0; 3]; index.len()];
        let mut count = vec![0usize; index.len()];
        for s in samples {
            let k = position[lattice.node_of(s)];
            for (sum, sigma) in variance_sum[k].iter_mut().zip(value_sigma(s)) {
                *sum += sigma.unwrap_or(f64::INFINITY).powi(2);
            }
            count[k] += 1;
        }
        let weight = std::array::from_fn(|c| {
            variance_sum
                .iter()
                .zip(&count)
                .map(|(v, &n)| {
                    if v[c].is_finite() {
                        (n * n) as f64 / v[c]
                    } else {
                        0.0
                    }
                })
                .collect()
        });
        Self {
            triples: triples(lattice, &position),
            index,
            position,
            weight,
        }
    }

    /// The smoothing of one channel.
    fn channel(&self, channel: usize) -> Channel<'_> {
        Channel {
            weight: &self.weight[channel],
            triples: &self.triples,
        }
    }
}

/// The measured nodes' weights in one channel and the penalty's triples.
struct Channel<'a> {
    weight: &'a [f64],
    triples: &'a [Triple],
}

impl Channel<'_> {
    /// The corrections `u = v - y` of the node values `y` (see the module documentation).
    fn corrections(&self, y: &[f64]) -> Vec<f64> {
        let free: Vec<f64> = self.weight.iter().copied().filter(|w| *w > 0.0).collect();
        if free.is_empty() || self.triples.is_empty() {
            return vec![0.0; y.len()];
        }
        let scale = median(&mut free.clone());
        let within_noise = |u: &[f64]| self.departure_scale(u) <= 1.0;
        let (mut lo, mut hi) = LOG10_LAMBDA_RANGE;
        let mut best = vec![0.0; y.len()];
        let strongest = self.solve(y, scale * 10f64.powf(hi), &best);
        if within_noise(&strongest) {
            best = strongest;
        } else {
            let mut start = vec![0.0; y.len()];
            for _ in 0..BISECTIONS {
                let mid = 0.5 * (lo + hi);
                let u = self.solve(y, scale * 10f64.powf(mid), &start);
                if within_noise(&u) {
                    lo = mid;
                    best.clone_from(&u);
                } else {
                    hi = mid;
                }
                start = u;
            }
        }
        best.iter()
            .zip(self.weight)
            .map(|(u, w)| {
                let limit = MAX_MOVE_SIGMAS / w.sqrt();
                if *w > 0.0 {
                    u.clamp(-limit, limit)
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// The scale of the departures `|u_i| / sigma_i` of the free nodes, as a standard
    /// deviation from their median ([`normal_scale_of_absolute`]).
    fn departure_scale(&self, u: &[f64]) -> f64 {
        let mut standardised: Vec<f64> = u
            .iter()
            .zip(self.weight)
            .filter(|(_, w)| **w > 0.0)
            .map(|(u, w)| u.abs() * w.sqrt())
            .collect();
        normal_scale_of_absolute(&mut standardised)
    }

    /// `u` solving `(W + lambda D^T D) u = -lambda D^T D y`, with `u = 0` at the nodes kept as
    /// measured, by conjugate gradients from `start`. The system is scaled symmetrically by
    /// its diagonal (a Jacobi preconditioner), as the weights span orders of magnitude.
    fn solve(&self, y: &[f64], lambda: f64, start: &[f64]) -> Vec<f64> {
        let system = Smoothing {
            channel: self,
            lambda,
            scaling: self.scaling(lambda),
        };
        let mut b = system.penalty(y);
        for (b, s) in b.iter_mut().zip(&system.scaling) {
            *b *= -lambda * s;
        }
        let start: Vec<f64> = start
            .iter()
            .zip(&system.scaling)
            .map(|(u, s)| if *s > 0.0 { u / s } else { 0.0 })
            .collect();
        let tolerance = CG_TOLERANCE * b.iter().map(|b| b * b).sum::<f64>();
        let solver: ConjugateGradient<Vec<f64>, f64> = ConjugateGradient::new(b);
        let scaling = system.scaling.clone();
        let solved = Executor::new(system, solver)
            .configure(|state| {
                state
                    .param(start)
                    .max_iters(MAX_CG_ITERATIONS)
                    .target_cost(tolerance)
            })
            .run();
        let scaled = solved
            .ok()
            .and_then(|mut result| result.state.take_param())
            .unwrap_or_else(|| vec![0.0; y.len()]);
        scaled.iter().zip(&scaling).map(|(x, s)| x * s).collect()
    }

    /// `1 / sqrt` of the system's diagonal at each free node, zero at a node kept as measured.
    fn scaling(&self, lambda: f64) -> Vec<f64> {
        let mut diagonal = self.weight.to_vec();
        for t in self.triples {
            diagonal[t.node] += lambda;
            diagonal[t.before] += lambda * t.before_weight.powi(2);
            diagonal[t.after] += lambda * t.after_weight.powi(2);
        }
        diagonal
            .iter()
            .zip(self.weight)
            .map(|(d, w)| if *w > 0.0 { d.sqrt().recip() } else { 0.0 })
            .collect()
    }
}

/// The system of [`Channel::solve`], scaled: `S (W + lambda D^T D) S`.
struct Smoothing<'a> {
    channel: &'a Channel<'a>,
    lambda: f64,
    scaling: Vec<f64>,
}

impl Smoothing<'_> {
    /// `D^T D x`: the penalty's normal operator.
    fn penalty(&self, x: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; x.len()];
        for t in self.channel.triples {
            let r = x[t.node] - t.before_weight * x[t.before] - t.after_weight * x[t.after];
            out[t.node] += r;
            out[t.before] -= t.before_weight * r;
            out[t.after] -= t.after_weight * r;
        }
        out
    }
}

impl Operator for Smoothing<'_> {
    type Param = Vec<f64>;
    type Output = Vec<f64>;

    fn apply(&self, x: &Vec<f64>) -> Result<Vec<f64>, Error> {
        let unscaled: Vec<f64> = x.iter().zip(&self.scaling).map(|(x, s)| x * s).collect();
        let penalty = self.penalty(&unscaled);
        Ok(unscaled
            .iter()
            .zip(self.channel.weight)
            .zip(penalty)
            .zip(&self.scaling)
            .map(|(((u, w), p), s)| s * (w * u + self.lambda * p))
            .collect())
    }
}

/// Every three measured nodes next to each other along a line of one axis (nodes that were
/// not measured between them skipped), numbered by their `position` among the measured ones.
fn triples(lattice: &Lattice, position: &[usize]) -> Vec<Triple> {
    let shape = lattice.shape();
    let axes = [&lattice.theta_h, &lattice.theta_d, &lattice.phi_d];
    let mut triples = Vec::new();
    for (a, axis) in axes.iter().enumerate() {
        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
        for i in 0..shape[b] {
            for j in 0..shape[c] {
                let line: Vec<(f64, usize)> = (0..shape[a])
                    .filter_map(|k| {
                        let mut at = [0; 3];
                        (at[a], at[b], at[c]) = (k, i, j);
                        let node = position[lattice.index(at[0], at[1], at[2])];
                        (node != usize::MAX).then_some((axis.nodes[k], node))
                    })
                    .collect();
                triples.extend(line.windows(3).map(|w| {
                    let [(x0, before), (x1, node), (x2, after)] = [w[0], w[1], w[2]];
                    Triple {
                        node,
                        before,
                        before_weight: (x2 - x1) / (x2 - x0),
                        after,
                        after_weight: (x1 - x0) / (x2 - x0),
                    }
                }));
            }
        }
    }
    triples
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};
    use specula_core::{HalfDiff, Rgb};

    /// One sample per node of a 12 x 10 x 4 lattice (theta_h unevenly spaced), each with the
    /// camera noise `noise`, and its position `(theta_h, theta_d, phi_d)` in degrees.
    fn lattice_samples(noise: Option<f64>) -> (Vec<Sample>, Vec<[f64; 3]>) {
        let mut samples = Vec::new();
        let mut at = Vec::new();
        for h in 0..12 {
            let theta_h = 0.5 + (h as f64).powf(1.5) * 1.5;
            for d in 0..10 {
                let theta_d = 5.0 + 6.0 * d as f64;
                for p in 0..4 {
                    let phi_d = 30.0 * p as f64;
                    let sample = Sample::new(
                        HalfDiff::from_degrees(theta_h, 0.0, theta_d, phi_d),
                        Rgb::ONE,
                    );
                    samples.push(match noise {
                        Some(n) => sample.with_noise_rel(Rgb::splat(n)),
                        None => sample,
                    });
                    at.push([theta_h, theta_d, phi_d]);
                }
            }
        }
        (samples, at)
    }

    fn linear(at: &[f64; 3]) -> f64 {
        0.3 + 0.01 * at[0] - 0.004 * at[1] + 0.002 * at[2]
    }

    /// The samples' standard deviations, camera noise and incidence together.
    fn sigmas(samples: &[Sample]) -> Vec<f64> {
        samples.iter().map(|s| value_sigma(s)[0].unwrap()).collect()
    }

    #[test]
    fn the_incidence_term_is_the_tangent_times_the_positioning_accuracy() {
        let at = |theta_i_deg: f64| {
            // theta_h 0: light and camera both at theta_d from the normal.
            let hd = HalfDiff::from_degrees(0.0, 0.0, theta_i_deg, 90.0);
            incidence_sigma(&Sample::new(hd, Rgb::ONE))
        };
        let accuracy = POSITIONING_ACCURACY_DEG.to_radians();
        assert!((at(45.0) - accuracy).abs() < 1e-12 * accuracy);
        let expected = 75f64.to_radians().tan() * accuracy;
        assert!((at(75.0) - expected).abs() < 1e-9 * expected);
        assert!(at(0.0).abs() < 1e-15);
    }

    #[test]
    fn without_a_known_noise_the_values_are_as_measured() {
        let (samples, at) = lattice_samples(None);
        let values: Vec<[f64; 3]> = at
            .iter()
            .map(|a| [linear(a) + 0.1 * a[0].sin(); 3])
            .collect();
        assert_eq!(smoothed(&samples, &values), values);
    }

    #[test]
    fn a_residual_linear_along_every_axis_is_left_as_it_is() {
        let (samples, at) = lattice_samples(Some(0.01));
        let values: Vec<[f64; 3]> = at.iter().map(|a| [linear(a); 3]).collect();
        for (s, v) in smoothed(&samples, &values).iter().zip(&values) {
            for c in 0..3 {
                assert!((s[c] - v[c]).abs() < 1e-9, "{s:?} {v:?}");
            }
        }
    }

    #[test]
    fn noise_on_a_smooth_residual_is_taken_out_within_the_noise() {
        let (samples, at) = lattice_samples(Some(0.01));
        let sigma = sigmas(&samples);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let truth: Vec<f64> = at
            .iter()
            .map(|a| linear(a) + 0.02 * (a[1] / 20.0).sin())
            .collect();
        let values: Vec<[f64; 3]> = truth
            .iter()
            .zip(&sigma)
            .map(|(t, s)| {
                std::array::from_fn(|_| t + Normal::new(0.0, *s).unwrap().sample(&mut rng))
            })
            .collect();
        let out = smoothed(&samples, &values);
        let rms = |of: &dyn Fn(usize) -> f64| {
            ((0..truth.len()).map(|i| of(i).powi(2)).sum::<f64>() / truth.len() as f64).sqrt()
        };
        for c in 0..3 {
            let before = rms(&|i| values[i][c] - truth[i]);
            let after = rms(&|i| out[i][c] - truth[i]);
            // About one sample's noise before; the smoothing averages over its neighbours.
            assert!(after < 0.5 * before, "channel {c}: {before} -> {after}");
            let mut departures: Vec<f64> = (0..truth.len())
                .map(|i| (out[i][c] - values[i][c]).abs() / sigma[i])
                .collect();
            assert!(departures.iter().all(|d| *d <= MAX_MOVE_SIGMAS + 1e-9));
            assert!(normal_scale_of_absolute(&mut departures) <= 1.0 + 1e-9);
        }
    }

    #[test]
    fn structure_far_above_the_noise_is_kept() {
        let (samples, at) = lattice_samples(Some(1e-3));
        let sigma = sigmas(&samples);
        // A ridge of 0.5 along theta_h 4 to 8 deg: five hundred times the noise.
        let values: Vec<[f64; 3]> = at
            .iter()
            .map(|a| [linear(a) + if (4.0..8.0).contains(&a[0]) { 0.5 } else { 0.0 }; 3])
            .collect();
        let out = smoothed(&samples, &values);
        for ((o, v), s) in out.iter().zip(&values).zip(&sigma) {
            assert!(
                (o[0] - v[0]).abs() <= MAX_MOVE_SIGMAS * s + 1e-12,
                "{o:?} {v:?}"
            );
        }
        let moved: f64 = out
            .iter()
            .zip(&values)
            .map(|(o, v)| (o[0] - v[0]).abs())
            .sum();
        assert!(moved / (out.len() as f64) < 2.0 * 1e-3, "{moved}");
    }

    #[test]
    fn each_channel_is_smoothed_within_its_own_noise() {
        let (samples, at) = lattice_samples(None);
        let samples: Vec<Sample> = samples
            .iter()
            .map(|s| s.with_noise_rel(Rgb::new(0.01, 1e-4, 0.01)))
            .collect();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let normal = Normal::new(0.0, 0.01).unwrap();
        let truth: Vec<f64> = at.iter().map(linear).collect();
        let values: Vec<[f64; 3]> = truth
            .iter()
            .map(|t| std::array::from_fn(|_| t + normal.sample(&mut rng)))
            .collect();
        let out = smoothed(&samples, &values);
        let rms = |c: usize, of: &[[f64; 3]]| {
            let sum: f64 = of.iter().zip(&truth).map(|(v, t)| (v[c] - t).powi(2)).sum();
            (sum / truth.len() as f64).sqrt()
        };
        // Red's scatter is its noise: smoothed. Green's is far above its stated noise (0.01 %
        // and the incidence's 0.05 % at 45 deg: structure, as far as the noise says), so each
        // node moves by at most 2 of its sigmas, a fraction of what red's move.
        assert!(rms(0, &out) < 0.5 * rms(0, &values));
        for (s, (o, v)) in samples.iter().zip(out.iter().zip(&values)) {
            let sigma = value_sigma(s)[1].unwrap();
            assert!((o[1] - v[1]).abs() <= MAX_MOVE_SIGMAS * sigma + 1e-12);
        }
        let moved = |c: usize| -> f64 {
            out.iter()
                .zip(&values)
                .map(|(o, v)| (o[c] - v[c]).abs())
                .sum()
        };
        assert!(moved(1) < 0.25 * moved(0), "{} {}", moved(1), moved(0));
    }

    #[test]
    fn a_node_holding_a_lower_bound_keeps_its_value() {
        let (mut samples, at) = lattice_samples(Some(0.01));
        samples[200] = samples[200].with_noise_rel(Rgb::splat(f64::INFINITY));
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let normal = Normal::new(0.0, 0.01).unwrap();
        let values: Vec<[f64; 3]> = at
            .iter()
            .map(|a| std::array::from_fn(|_| linear(a) + normal.sample(&mut rng)))
            .collect();
        let out = smoothed(&samples, &values);
        assert_eq!(out[200], values[200]);
        assert_ne!(out[201], values[201]);
    }
}
