//! One-dimensional interpolation along one lattice axis: piecewise linear (the paper's
//! baseline, 5.3) or monotone piecewise cubic (Fritsch-Carlson / PCHIP, as scipy's
//! `PchipInterpolator`), which follows a peak's curvature between nodes without overshoot.
//!
//! Outside the nodes both hold the end value. An end node on a symmetry point of the BRDF
//! (theta_d = 0, phi_d = 0 or 90 degrees, where it is even) gets slope zero. theta_h = 0 is
//! one too, but a mirror-like peak can be far narrower than the first theta_h interval, so
//! there the end slope comes from the data (the SGD fit of MERL's chrome falls by 30 % between
//! theta_h = 0 and 0.011 deg).

use crate::axis::Bracket;

/// How values are interpolated between the nodes of one axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kernel {
    /// Piecewise linear (the paper's baseline, 5.3).
    Linear,
    /// Monotone piecewise cubic (Fritsch-Carlson / PCHIP).
    MonotoneCubic,
}

/// An axis' nodes with what the kernel needs to know about its ends.
#[derive(Debug, Clone)]
pub(crate) struct Line<'a> {
    /// The node angles, deg, ascending.
    pub nodes: &'a [f64],
    /// Whether the first and the last node lie on a symmetry point (slope zero there).
    pub even_ends: [bool; 2],
}

impl Line<'_> {
    /// Node slopes of the monotone cubic through `values` (one per node).
    pub(crate) fn pchip_slopes(&self, values: &[f64], slopes: &mut [f64]) {
        let x = self.nodes;
        let n = x.len();
        match n {
            0 => return,
            1 => {
                slopes[0] = 0.0;
                return;
            }
            _ => {}
        }
        let h = |k: usize| x[k + 1] - x[k];
        let delta = |k: usize| (values[k + 1] - values[k]) / h(k);
        if n == 2 {
            let d = delta(0);
            slopes[0] = if self.even_ends[0] { 0.0 } else { d };
            slopes[1] = if self.even_ends[1] { 0.0 } else { d };
            return;
        }
        for (k, slope) in slopes.iter_mut().enumerate().take(n - 1).skip(1) {
            let (d0, d1) = (delta(k - 1), delta(k));
            *slope = if d0 * d1 <= 0.0 {
                0.0
            } else {
                let w1 = 2.0 * h(k) + h(k - 1);
                let w2 = h(k) + 2.0 * h(k - 1);
                (w1 + w2) / (w1 / d0 + w2 / d1)
            };
        }
        slopes[0] = if self.even_ends[0] {
            0.0
        } else {
            end_slope(h(0), h(1), delta(0), delta(1))
        };
        slopes[n - 1] = if self.even_ends[1] {
            0.0
        } else {
            end_slope(h(n - 2), h(n - 3), delta(n - 2), delta(n - 3))
        };
    }

    /// Interpolates `values` (one per node) at each bracket, into `out`.
    pub(crate) fn interpolate(
        &self,
        kernel: Kernel,
        values: &[f64],
        slopes: &mut [f64],
        brackets: &[Bracket],
        out: &mut [f64],
    ) {
        if self.nodes.len() == 1 {
            out.fill(values[0]);
            return;
        }
        match kernel {
            Kernel::Linear => {
                for (o, b) in out.iter_mut().zip(brackets) {
                    *o = values[b.lower] + b.t * (values[b.lower + 1] - values[b.lower]);
                }
            }
            Kernel::MonotoneCubic => {
                self.pchip_slopes(values, slopes);
                for (o, b) in out.iter_mut().zip(brackets) {
                    let k = b.lower;
                    let h = self.nodes[k + 1] - self.nodes[k];
                    let t = b.t;
                    let t2 = t * t;
                    let t3 = t2 * t;
                    *o = (2.0 * t3 - 3.0 * t2 + 1.0) * values[k]
                        + (t3 - 2.0 * t2 + t) * h * slopes[k]
                        + (3.0 * t2 - 2.0 * t3) * values[k + 1]
                        + (t3 - t2) * h * slopes[k + 1];
                }
            }
        }
    }
}

/// The one-sided three-point end slope of PCHIP, limited to keep the shape monotone
/// (scipy's `PchipInterpolator._edge_case`).
fn end_slope(h0: f64, h1: f64, d0: f64, d1: f64) -> f64 {
    let d = ((2.0 * h0 + h1) * d0 - h0 * d1) / (h0 + h1);
    if d.signum() != d0.signum() || d0 == 0.0 {
        0.0
    } else if d0.signum() != d1.signum() && d.abs() > 3.0 * d0.abs() {
        3.0 * d0
    } else {
        d
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::axis::Axis;

    fn run(
        kernel: Kernel,
        nodes: &[f64],
        even: [bool; 2],
        values: &[f64],
        targets: &[f64],
    ) -> Vec<f64> {
        let axis = Axis {
            nodes: nodes.to_vec(),
        };
        let brackets: Vec<_> = targets.iter().map(|&u| axis.bracket(u)).collect();
        let mut out = vec![0.0; targets.len()];
        let mut slopes = vec![0.0; nodes.len()];
        Line {
            nodes,
            even_ends: even,
        }
        .interpolate(kernel, values, &mut slopes, &brackets, &mut out);
        out
    }

    /// Reference values from scipy.interpolate.PchipInterpolator, written by
    /// `tools/reconstruct_scipy.py --vectors` into tests/data/pchip_scipy.csv.
    #[test]
    fn monotone_cubic_matches_scipy_pchip() {
        let text = include_str!("../tests/data/pchip_scipy.csv");
        let mut lines = text.lines().filter(|l| !l.starts_with('#'));
        let parse = |l: &str| {
            l.split(',')
                .map(|v| v.trim().parse::<f64>().unwrap())
                .collect::<Vec<_>>()
        };
        let mut cases = 0;
        while let (Some(x), Some(y), Some(t), Some(r)) =
            (lines.next(), lines.next(), lines.next(), lines.next())
        {
            let (x, y, t, r) = (parse(x), parse(y), parse(t), parse(r));
            let got = run(Kernel::MonotoneCubic, &x, [false, false], &y, &t);
            for (g, e) in got.iter().zip(&r) {
                assert!(
                    (g - e).abs() <= 1e-9 * (1.0 + e.abs()),
                    "x {x:?} y {y:?}: {g} vs {e}"
                );
            }
            cases += 1;
        }
        assert!(cases >= 5, "only {cases} cases");
    }

    #[test]
    fn linear_is_exact_on_lines_and_both_kernels_hit_nodes() {
        let nodes = [0.0, 1.0, 4.0, 9.0];
        let values = [1.0, 3.0, 9.0, 19.0];
        let got = run(
            Kernel::Linear,
            &nodes,
            [false, false],
            &values,
            &[0.5, 2.5, 8.0, 12.0],
        );
        assert_eq!(got, vec![2.0, 6.0, 17.0, 19.0]);
        let cubic = run(
            Kernel::MonotoneCubic,
            &nodes,
            [true, false],
            &values,
            &nodes,
        );
        for (c, v) in cubic.iter().zip(values) {
            assert!((c - v).abs() < 1e-12);
        }
    }

    #[test]
    fn monotone_cubic_does_not_overshoot_a_peak() {
        let nodes = [0.0, 0.2, 0.5, 1.0, 3.0, 10.0];
        let values = [1000.0, 800.0, 100.0, 5.0, 1.0, 0.9];
        let targets: Vec<f64> = (0..=100).map(|i| i as f64 * 0.1).collect();
        let got = run(
            Kernel::MonotoneCubic,
            &nodes,
            [true, false],
            &values,
            &targets,
        );
        assert!(got.windows(2).all(|w| w[1] <= w[0] + 1e-12), "{got:?}");
        assert!(got.iter().all(|&v| (0.9..=1000.0).contains(&v)));
        // Even at theta_h = 0: the flat start stays above the chord (900 at 0.1).
        assert!(got[1] > 900.0, "{}", got[1]);
    }
}
