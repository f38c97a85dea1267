//! Piecewise-constant distributions for importance sampling (Pharr, Jakob, Humphreys,
//! *Physically Based Rendering*, 13.6): a 1-D one over `[0, 1)` and a 2-D one over the unit
//! square, sampled by inverting their cumulative sums.
//!
//! Built for the renderer's inner loop: each row is a cumulative sum in single precision and a
//! guide table (Chen and Asau's cut-point method) that finds the cell of a number in about one
//! step, all rows of a 2-D distribution in one flat array so that a lookup touches two or three
//! cache lines. The density of a cell is its width in the stored cumulative sum, so sampling
//! and [`Distribution2D::pdf`] agree exactly; the inversion is monotone, so stratified numbers
//! stay stratified.

/// One row's cumulative sums and guide, as slices of the flat arrays.
#[derive(Clone, Copy)]
struct Row<'a> {
    /// `n + 1` values from 0 to 1.
    cdf: &'a [f32],
    /// `n` cells: `guide[k]` holds `k / n`.
    guide: &'a [u32],
}

impl Row<'_> {
    fn cells(&self) -> usize {
        self.guide.len()
    }

    /// `(x, cell, density at x)` of `u` in `[0, 1)`.
    fn sample(&self, u: f64) -> (f64, usize, f64) {
        let n = self.cells();
        let u = u.clamp(0.0, 1.0);
        let mut cell = self.guide[((u * n as f64) as usize).min(n - 1)] as usize;
        while cell + 1 < n && (self.cdf[cell + 1] as f64) <= u {
            cell += 1;
        }
        let (start, end) = (self.cdf[cell] as f64, self.cdf[cell + 1] as f64);
        let width = end - start;
        let offset = if width > 0.0 {
            ((u - start) / width).clamp(0.0, 1.0)
        } else {
            0.5
        };
        let x = ((cell as f64 + offset) / n as f64).min(1.0 - f64::EPSILON);
        (x, cell, width * n as f64)
    }

    /// The density at `x` in `[0, 1)`.
    fn pdf(&self, x: f64) -> f64 {
        let n = self.cells();
        let cell = ((x * n as f64) as usize).min(n - 1);
        (self.cdf[cell + 1] as f64 - self.cdf[cell] as f64) * n as f64
    }
}

/// Appends the normalised cumulative sums of `func` (uniform when it has no mass) and their
/// guide table; returns the integral of `func` over `[0, 1)`.
fn push_row(func: &[f64], cdf: &mut Vec<f32>, guide: &mut Vec<u32>) -> f64 {
    let n = func.len();
    let clean = |v: f64| if v.is_finite() { v.max(0.0) } else { 0.0 };
    let total: f64 = func.iter().map(|v| clean(*v)).sum();
    let mut running = 0.0;
    let start = cdf.len();
    cdf.push(0.0);
    for (i, v) in func.iter().enumerate() {
        running += if total > 0.0 {
            clean(*v) / total
        } else {
            1.0 / n as f64
        };
        cdf.push(if i + 1 == n { 1.0 } else { running as f32 });
    }
    let row = &cdf[start..];
    let mut cell = 0usize;
    for k in 0..n {
        let u = k as f64 / n as f64;
        while cell + 1 < n && (row[cell + 1] as f64) <= u {
            cell += 1;
        }
        guide.push(cell as u32);
    }
    total / n as f64
}

/// A piecewise-constant density over `[0, 1)` with equal cells.
#[derive(Debug, Clone)]
pub struct Distribution1D {
    cdf: Vec<f32>,
    guide: Vec<u32>,
    integral: f64,
}

impl Distribution1D {
    /// The distribution proportional to the non-negative `func` (uniform when it is all 0).
    pub fn new(func: &[f64]) -> Self {
        let func = if func.is_empty() { &[1.0][..] } else { func };
        let (mut cdf, mut guide) = (Vec::new(), Vec::new());
        let integral = push_row(func, &mut cdf, &mut guide);
        Self {
            cdf,
            guide,
            integral,
        }
    }

    fn row(&self) -> Row<'_> {
        Row {
            cdf: &self.cdf,
            guide: &self.guide,
        }
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.guide.len()
    }

    /// Whether the distribution has no cell.
    pub fn is_empty(&self) -> bool {
        self.guide.is_empty()
    }

    /// Integral of the function over `[0, 1)`.
    pub fn integral(&self) -> f64 {
        self.integral
    }

    /// Maps `u` in `[0, 1)` to `(x, cell, density at x)`, `x` in `[0, 1)`.
    pub fn sample(&self, u: f64) -> (f64, usize, f64) {
        self.row().sample(u)
    }

    /// The density at `x` in `[0, 1)`.
    pub fn pdf(&self, x: f64) -> f64 {
        self.row().pdf(x)
    }
}

/// A piecewise-constant density over the unit square: one conditional row along u per cell of
/// v, and a marginal along v.
#[derive(Debug, Clone)]
pub struct Distribution2D {
    width: usize,
    /// The rows' cumulative sums, `width + 1` each, one after the other.
    cdf: Vec<f32>,
    /// The rows' guides, `width` each.
    guide: Vec<u32>,
    marginal: Distribution1D,
}

impl Distribution2D {
    /// The distribution proportional to `func` given row by row (`width` values per row).
    pub fn new(func: &[f64], width: usize) -> Self {
        let width = width.max(1);
        let (mut cdf, mut guide) = (Vec::new(), Vec::new());
        let integrals: Vec<f64> = func
            .chunks(width)
            .map(|row| push_row(row, &mut cdf, &mut guide))
            .collect();
        Self {
            width,
            cdf,
            guide,
            marginal: Distribution1D::new(&integrals),
        }
    }

    fn row(&self, index: usize) -> Row<'_> {
        Row {
            cdf: &self.cdf[index * (self.width + 1)..(index + 1) * (self.width + 1)],
            guide: &self.guide[index * self.width..(index + 1) * self.width],
        }
    }

    /// Maps `(u0, u1)` to a point `(u, v)` of the unit square and its density.
    pub fn sample(&self, u0: f64, u1: f64) -> ((f64, f64), f64) {
        let (v, row, pdf_v) = self.marginal.sample(u1);
        let (u, _, pdf_u) = self.row(row).sample(u0);
        ((u, v), pdf_u * pdf_v)
    }

    /// The density at `(u, v)`.
    pub fn pdf(&self, u: f64, v: f64) -> f64 {
        let rows = self.marginal.len();
        let row = ((v * rows as f64) as usize).min(rows - 1);
        self.row(row).pdf(u) * self.marginal.pdf(v)
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
        assert!((d.pdf(0.9) - 4.0 / 8.0 * 4.0).abs() < 1e-6);
        // The guided search lands where a binary search of the cdf does.
        for i in 0..1000 {
            let u = i as f64 / 1000.0;
            let (_, cell, _) = d.sample(u);
            let reference = d
                .cdf
                .partition_point(|c| (*c as f64) <= u)
                .saturating_sub(1)
                .min(3);
            assert_eq!(cell, reference, "u {u}");
        }
        // Density integrates to 1.
        let total: f64 = (0..400)
            .map(|i| d.pdf((i as f64 + 0.5) / 400.0) / 400.0)
            .sum();
        assert!((total - 1.0).abs() < 1e-6);
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
        assert!((total - 1.0).abs() < 1e-6, "{total}");
        for k in 0..50 {
            let ((u, v), pdf) = d.sample((k as f64 * 0.37) % 1.0, (k as f64 * 0.61) % 1.0);
            assert!(pdf > 0.0 && (pdf - d.pdf(u, v)).abs() < 1e-9);
        }
        let zero = Distribution1D::new(&[0.0, 0.0]);
        assert!((zero.pdf(0.3) - 1.0).abs() < 1e-12);
    }
}
