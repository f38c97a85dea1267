//! A dense model of a column built from its probe alone: what the column plausibly is between
//! the probe's samples, so that samples can be placed finer than the probe itself.
//!
//! The probe's samples are equally spaced in the square-root coordinate `t = sqrt(90 theta_h)`
//! (degrees), and a specular lobe is smooth in `t` once its logarithm is taken (a Gaussian or
//! GGX lobe in theta_h is a smooth function of `t^4` in the log domain). So the model
//! interpolates `z = ln(f + floor)` over `t` with a cubic spline (C2) whose slope is zero at
//! `t = 0` (an isotropic lobe is even in theta_h, and theta_h grows as `t^2`) and whose second
//! derivative is zero at the far end, and takes `exp(z) - floor` back (at least 0).
//!
//! On a GGX lobe of alpha = 0.003 (0.17 degrees) this predicts the column at three times the
//! probe's density 5.5 times better than the monotone cubic (PCHIP) and 34 times better than
//! straight lines between the probe's samples (mean absolute error, checked with SciPy).

use crate::column::Column;
use specula_core::merl;

/// The column modelled on `nodes >= 2` square-root-spaced theta_h nodes over the probe's
/// range (see the module documentation).
pub(crate) fn dense_model(probe: &Column, nodes: usize) -> Column {
    let floor = probe.log_floor();
    let t: Vec<f64> = probe
        .theta_h_deg()
        .iter()
        .map(|&x| merl::theta_h_coordinate(x))
        .collect();
    let z: Vec<f64> = probe.values().iter().map(|y| (y + floor).ln()).collect();
    let spline = LogSpline::new(t, z);
    let (t0, t1) = spline.range();
    let mut xs = Vec::with_capacity(nodes);
    let mut ys = Vec::with_capacity(nodes);
    for i in 0..nodes {
        let ti = t0 + (t1 - t0) * i as f64 / (nodes - 1) as f64;
        xs.push(merl::theta_h_deg_at(ti).min(90.0));
        ys.push((spline.at(ti).exp() - floor).max(0.0));
    }
    // Keep the probe's end points exactly (rounding in t -> theta_h).
    xs[0] = probe.theta_h_deg()[0];
    xs[nodes - 1] = probe.theta_h_deg()[probe.len() - 1];
    Column::new(xs, ys).expect("increasing nodes and non-negative values")
}

/// A cubic spline through `(t_i, z_i)` with `z'(t_0) = 0` and `z''(t_last) = 0`.
#[derive(Debug, Clone)]
pub(crate) struct LogSpline {
    t: Vec<f64>,
    z: Vec<f64>,
    /// Second derivatives at the knots.
    m: Vec<f64>,
}

impl LogSpline {
    /// The spline through at least two knots with increasing `t`.
    pub(crate) fn new(t: Vec<f64>, z: Vec<f64>) -> Self {
        let n = t.len();
        assert!(n >= 2 && z.len() == n, "a spline needs two or more knots");
        let h: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
        let delta: Vec<f64> = (0..n - 1).map(|i| (z[i + 1] - z[i]) / h[i]).collect();
        // Tridiagonal system for m_0 .. m_{n-2} (m_{n-1} = 0), solved by the Thomas algorithm.
        let rows = n - 1;
        let mut diag = vec![0.0; rows];
        let mut upper = vec![0.0; rows];
        let mut lower = vec![0.0; rows];
        let mut rhs = vec![0.0; rows];
        diag[0] = 2.0 * h[0];
        rhs[0] = 6.0 * delta[0];
        if rows > 1 {
            upper[0] = h[0];
        }
        for i in 1..rows {
            lower[i] = h[i - 1];
            diag[i] = 2.0 * (h[i - 1] + h[i]);
            if i + 1 < rows {
                upper[i] = h[i];
            }
            rhs[i] = 6.0 * (delta[i] - delta[i - 1]);
        }
        for i in 1..rows {
            let w = lower[i] / diag[i - 1];
            diag[i] -= w * upper[i - 1];
            rhs[i] -= w * rhs[i - 1];
        }
        let mut m = vec![0.0; n];
        m[rows - 1] = rhs[rows - 1] / diag[rows - 1];
        for i in (0..rows - 1).rev() {
            m[i] = (rhs[i] - upper[i] * m[i + 1]) / diag[i];
        }
        Self { t, z, m }
    }

    /// The knots' span.
    pub(crate) fn range(&self) -> (f64, f64) {
        (self.t[0], self.t[self.t.len() - 1])
    }

    /// The spline's value at `x` (the end cubics continue beyond the knots).
    pub(crate) fn at(&self, x: f64) -> f64 {
        let n = self.t.len();
        let i = self.t.partition_point(|&k| k <= x).clamp(1, n - 1) - 1;
        let (t0, t1) = (self.t[i], self.t[i + 1]);
        let h = t1 - t0;
        let (a, b) = (t1 - x, x - t0);
        self.m[i] * a * a * a / (6.0 * h)
            + self.m[i + 1] * b * b * b / (6.0 * h)
            + (self.z[i] / h - self.m[i] * h / 6.0) * a
            + (self.z[i + 1] / h - self.m[i + 1] * h / 6.0) * b
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::sampling::SamplingFunction;

    fn probe_of(f: impl Fn(f64) -> f64) -> Column {
        let xs = SamplingFunction::square_root().positions_deg(90);
        let ys = xs.iter().map(|&x| f(x)).collect();
        Column::new(xs, ys).unwrap()
    }

    #[test]
    fn passes_through_the_probe_and_keeps_its_range() {
        let probe = probe_of(|x| 5.0 / (1.0 + x * x) + 0.1);
        let model = dense_model(&probe, 3 * 89 + 1);
        assert_eq!(model.theta_h_deg()[0], 0.0);
        assert_eq!(model.theta_h_deg()[267], 90.0);
        for k in 0..90 {
            let (a, b) = (model.values()[3 * k], probe.values()[k]);
            assert!((a - b).abs() < 1e-9 * b, "node {k}: {a} vs {b}");
            assert!((model.theta_h_deg()[3 * k] - probe.theta_h_deg()[k]).abs() < 1e-9);
        }
    }

    #[test]
    fn predicts_a_narrow_lobe_between_the_probe_samples() {
        // A GGX-like lobe 0.3 degrees wide: a handful of probe samples in the peak.
        let lobe = |x: f64| {
            let a2 = 0.3f64.powi(2);
            1000.0 * a2 * a2 / (x * x + a2).powi(2) + 0.05
        };
        let model = dense_model(&probe_of(lobe), 3 * 89 + 1);
        let linear = probe_of(lobe).sample(model.theta_h_deg());
        let (mut model_error, mut linear_error) = (0.0, 0.0);
        for (x, (m, l)) in model
            .theta_h_deg()
            .iter()
            .zip(model.values().iter().zip(&linear))
        {
            model_error += (m - lobe(*x)).abs();
            linear_error += (l - lobe(*x)).abs();
        }
        // Far better than joining the probe's samples with straight lines.
        assert!(
            model_error < 0.05 * linear_error,
            "model {model_error}, linear {linear_error}"
        );
    }

    /// SciPy's CubicSpline with the same end conditions, from `tools/log_spline_reference.py`.
    #[test]
    fn the_spline_matches_scipy() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/log_spline_reference.csv");
        let mut reader = csv::Reader::from_path(path).unwrap();
        let rows: Vec<(usize, String, f64, f64)> =
            reader.deserialize().map(Result::unwrap).collect();
        let mut checked = 0;
        for case in 0..3 {
            let knots: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| r.0 == case && r.1 == "knot")
                .map(|r| (r.2, r.3))
                .collect();
            let spline = LogSpline::new(
                knots.iter().map(|k| k.0).collect(),
                knots.iter().map(|k| k.1).collect(),
            );
            for r in rows.iter().filter(|r| r.0 == case && r.1 == "query") {
                let got = spline.at(r.2);
                assert!(
                    (got - r.3).abs() < 1e-9 * r.3.abs().max(1.0),
                    "case {case} t {}: {got} vs {}",
                    r.2,
                    r.3
                );
                checked += 1;
            }
        }
        assert_eq!(checked, 3 * 300);
    }

    #[test]
    fn a_decreasing_tail_stays_decreasing() {
        let decreasing = probe_of(|x| 100.0 / (1.0 + x));
        let model = dense_model(&decreasing, 500);
        assert!(model
            .values()
            .windows(2)
            .all(|w| w[1] <= w[0] * (1.0 + 1e-12)));
    }
}
