//! Piecewise-constant distributions for importance sampling (Pharr, Jakob, Humphreys,
//! *Physically Based Rendering*, 13.6): a 1-D one over `[0, 1)` and a 2-D one over the unit
//! square, sampled by inverting their cumulative sums. A guide table (Chen and Asau's
//! cut-point method) finds the cell of a number in about one step instead of a binary search
//! through memory, and keeps the inversion monotone so that stratified numbers stay
//! stratified.

/// A piecewise-constant density over `[0, 1)` with `n` equal cells.
#[derive(Debug, Clone)]
pub struct Distribution1D {
    func: Vec<f64>,
    /// `cdf[i]`: probability of the cells before `i`; `cdf[n] = 1`.
    cdf: Vec<f64>,
    /// Integral of `func` over `[0, 1)`.
    integral: f64,
    /// `guide[k]`: the cell holding `u = k / n` (the first cell whose cdf end exceeds it).
    guide: Vec<u32>,
}

impl Distribution1D {
    /// The distribution proportional to the non-negative `func` (uniform when it is all 0).
    pub fn new(func: &[f64]) -> Self {
        let n = func.len().max(1);
        let func: Vec<f64> = if func.is_empty() {
            vec![1.0]
        } else {
            func.iter()
                .map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 })
                .collect()
        };
        let mut cdf = Vec::with_capacity(n + 1);
        cdf.push(0.0);
        for v in &func {
            cdf.push(cdf.last().copied().unwrap_or(0.0) + v / n as f64);
        }
        let integral = cdf[n];
        let (func, integral) = if integral > 0.0 {
            for c in &mut cdf {
                *c /= integral;
            }
            (func, integral)
        } else {
            for (i, c) in cdf.iter_mut().enumerate() {
                *c = i as f64 / n as f64;
            }
            (vec![1.0; n], 1.0)
        };
        let guide = guide_table(&cdf);
        Self {
            func,
            cdf,
            integral,
            guide,
        }
    }

    pub fn len(&self) -> usize {
        self.func.len()
    }

    pub fn is_empty(&self) -> bool {
        self.func.is_empty()
    }

    pub fn integral(&self) -> f64 {
        self.integral
    }

    /// Maps `u` in `[0, 1)` to `(x, cell, density at x)`, `x` in `[0, 1)`.
    pub fn sample(&self, u: f64) -> (f64, usize, f64) {
        let n = self.func.len();
        let u = u.clamp(0.0, 1.0);
        let mut cell = self.guide[((u * n as f64) as usize).min(n - 1)] as usize;
        // The last cell whose cdf start is <= u: a few steps from the guide at most.
        while cell + 1 < n && self.cdf[cell + 1] <= u {
            cell += 1;
        }
        let width = self.cdf[cell + 1] - self.cdf[cell];
        let offset = if width > 0.0 {
            (u - self.cdf[cell]) / width
        } else {
            0.5
        };
        let x = ((cell as f64 + offset.clamp(0.0, 1.0)) / n as f64).min(1.0 - f64::EPSILON);
        (x, cell, self.func[cell] / self.integral)
    }

    /// The density at `x` in `[0, 1)`.
    pub fn pdf(&self, x: f64) -> f64 {
        let n = self.func.len();
        let cell = ((x * n as f64) as usize).min(n - 1);
        self.func[cell] / self.integral
    }
}

/// For each of `n` equal steps `k / n` of `[0, 1)`, the cell in which it falls.
fn guide_table(cdf: &[f64]) -> Vec<u32> {
    let n = cdf.len() - 1;
    let mut guide = Vec::with_capacity(n);
    let mut cell = 0usize;
    for k in 0..n {
        let u = k as f64 / n as f64;
        while cell + 1 < n && cdf[cell + 1] <= u {
            cell += 1;
        }
        guide.push(cell as u32);
    }
    guide
}

/// A piecewise-constant density over the unit square: `rows` conditional distributions
/// along u, one per cell of v, and a marginal along v.
#[derive(Debug, Clone)]
pub struct Distribution2D {
    conditionals: Vec<Distribution1D>,
    marginal: Distribution1D,
}

impl Distribution2D {
    /// The distribution proportional to `func` given row by row (`width` values per row).
    pub fn new(func: &[f64], width: usize) -> Self {
        let conditionals: Vec<_> = func.chunks(width.max(1)).map(Distribution1D::new).collect();
        let marginal = Distribution1D::new(
            &conditionals
                .iter()
                .map(|c| c.integral())
                .collect::<Vec<_>>(),
        );
        Self {
            conditionals,
            marginal,
        }
    }

    /// Maps `(u0, u1)` to a point `(u, v)` of the unit square and its density.
    pub fn sample(&self, u0: f64, u1: f64) -> ((f64, f64), f64) {
        let (v, row, pdf_v) = self.marginal.sample(u1);
        let (u, _, pdf_u) = self.conditionals[row].sample(u0);
        ((u, v), pdf_u * pdf_v)
    }

    /// The density at `(u, v)`.
    pub fn pdf(&self, u: f64, v: f64) -> f64 {
        let rows = self.conditionals.len();
        let row = ((v * rows as f64) as usize).min(rows - 1);
        self.conditionals[row].pdf(u) * self.marginal.pdf(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_d_sampling_inverts_the_cdf_and_matches_the_pdf() {
        let d = Distribution1D::new(&[1.0, 0.0, 3.0, 4.0]);
        assert!((d.integral() - 2.0).abs() < 1e-12);
        // Cell 1 has no mass: no sample lands there.
        let mut counts = [0usize; 4];
        for i in 0..8000 {
            let (x, cell, pdf) = d.sample((i as f64 + 0.5) / 8000.0);
            assert_eq!(cell, (x * 4.0) as usize);
            assert!((pdf - d.pdf(x)).abs() < 1e-12);
            counts[cell] += 1;
        }
        assert_eq!(counts, [1000, 0, 3000, 4000]);
        // The guided search lands where a binary search of the cdf does.
        for i in 0..1000 {
            let u = i as f64 / 1000.0;
            let (_, cell, _) = d.sample(u);
            let reference = d.cdf.partition_point(|c| *c <= u).saturating_sub(1).min(3);
            assert_eq!(cell, reference, "u {u}");
        }
        // Density integrates to 1.
        let total: f64 = (0..400)
            .map(|i| d.pdf((i as f64 + 0.5) / 400.0) / 400.0)
            .sum();
        assert!((total - 1.0).abs() < 1e-12);
    }

    #[test]
    fn two_d_density_integrates_to_one_and_sampling_agrees() {
        let func: Vec<f64> = (0..12).map(|i| (i % 5) as f64).collect();
        let d = Distribution2D::new(&func, 4);
        let mut total = 0.0;
        for j in 0..30 {
            for i in 0..40 {
                total += d.pdf((i as f64 + 0.5) / 40.0, (j as f64 + 0.5) / 30.0) / 1200.0;
            }
        }
        assert!((total - 1.0).abs() < 1e-9, "{total}");
        for k in 0..50 {
            let ((u, v), pdf) = d.sample((k as f64 * 0.37) % 1.0, (k as f64 * 0.61) % 1.0);
            assert!(pdf > 0.0 && (pdf - d.pdf(u, v)).abs() < 1e-9);
        }
        let zero = Distribution1D::new(&[0.0, 0.0]);
        assert!((zero.pdf(0.3) - 1.0).abs() < 1e-12);
    }
}
