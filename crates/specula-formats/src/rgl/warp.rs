//! The interpolants of the RGL adaptive parameterisation (Dupuy & Jakob 2018, section 5):
//! bilinear grids on the unit square, stacks of grids interpolated linearly in the incident
//! elevation, and the inverse of the continuous marginal-conditional warp that maps a
//! microfacet normal to the warped 2-D domain on which the RGB samples sit.
//!
//! The arithmetic follows the specification given by Mitsuba 3's `Marginal2D` with
//! `Continuous = true` (`include/mitsuba/core/distr_2d.h`), which the `measured` plugin uses;
//! it is rewritten here in `f64`.

use glam::DVec2;

/// Position of `value` among increasing `knots` for linear interpolation: the index `i` of the
/// left knot and the weight `w` of the right one, so that the value is
/// `(1 - w) * knots[i] + w * knots[i + 1]`, clamped to the end knots.
///
/// As Mitsuba's `find_interval`: `i` is the largest index in `[0, n - 2]` with
/// `knots[i] < value` (0 if there is none). A single knot gives `(0, 0.0)`.
pub(super) fn interval(knots: &[f64], value: f64) -> (usize, f64) {
    if knots.len() < 2 {
        return (0, 0.0);
    }
    let last_left = knots.len() - 2;
    let i = knots[1..=last_left].partition_point(|k| *k < value);
    let (k0, k1) = (knots[i], knots[i + 1]);
    (i, ((value - k0) / (k1 - k0)).clamp(0.0, 1.0))
}

/// A `width x height` grid of values over the unit square: node `(x, y)` sits at
/// `(x / (width - 1), y / (height - 1))`, row-major with `x` contiguous.
#[derive(Debug, Clone)]
pub(super) struct Grid {
    width: usize,
    height: usize,
    values: Vec<f64>,
}

/// The patch of a grid that holds a point: its lower-left node and the offsets inside it.
struct Patch {
    x: usize,
    y: usize,
    frac: DVec2,
}

impl Grid {
    /// A grid from row-major values; `width` and `height` are at least 2 (checked by the caller).
    pub(super) fn new(width: usize, height: usize, values: Vec<f64>) -> Self {
        debug_assert!(width >= 2 && height >= 2 && values.len() == width * height);
        Self {
            width,
            height,
            values,
        }
    }

    /// The node values, row-major.
    pub(super) fn values(&self) -> &[f64] {
        &self.values
    }

    fn at(&self, x: usize, y: usize) -> f64 {
        self.values[y * self.width + x]
    }

    fn patch(&self, u: DVec2) -> Patch {
        let pos = u.clamp(DVec2::ZERO, DVec2::ONE)
            * DVec2::new((self.width - 1) as f64, (self.height - 1) as f64);
        let x = (pos.x as usize).min(self.width - 2);
        let y = (pos.y as usize).min(self.height - 2);
        Patch {
            x,
            y,
            frac: pos - DVec2::new(x as f64, y as f64),
        }
    }

    /// Bilinear interpolation at `u` in the unit square (clamped into it).
    pub(super) fn eval(&self, u: DVec2) -> f64 {
        let p = self.patch(u);
        let bottom = lerp(self.at(p.x, p.y), self.at(p.x + 1, p.y), p.frac.x);
        let top = lerp(self.at(p.x, p.y + 1), self.at(p.x + 1, p.y + 1), p.frac.x);
        lerp(bottom, top, p.frac.y)
    }
}

/// Grids tabulated at several incident elevations, interpolated linearly between them.
#[derive(Debug, Clone)]
pub(super) struct GridStack {
    theta_i_rad: Vec<f64>,
    grids: Vec<Grid>,
}

impl GridStack {
    pub(super) fn new(theta_i_rad: Vec<f64>, grids: Vec<Grid>) -> Self {
        debug_assert_eq!(theta_i_rad.len(), grids.len());
        Self { theta_i_rad, grids }
    }

    /// The value at `u` for incident elevation `theta_i_rad`.
    pub(super) fn eval(&self, u: DVec2, theta_i_rad: f64) -> f64 {
        let (i, w) = interval(&self.theta_i_rad, theta_i_rad);
        let low = self.grids[i].eval(u);
        if w == 0.0 {
            low
        } else {
            lerp(low, self.grids[i + 1].eval(u), w)
        }
    }
}

/// One elevation slice of the visible-normal warp: the density normalised to integrate to 1
/// over the unit square, and its conditional (per row) and marginal (over rows) CDFs of the
/// bilinear interpolant.
#[derive(Debug, Clone)]
struct MarginalSlice {
    density: Vec<f64>,
    /// `height` rows of `width - 1` running integrals along x.
    conditional_cdf: Vec<f64>,
    /// `height - 1` running integrals over rows.
    marginal_cdf: Vec<f64>,
}

impl MarginalSlice {
    /// Builds the CDFs of a density grid; `None` when it integrates to zero.
    fn new(grid: &Grid) -> Option<Self> {
        let (w, h) = (grid.width, grid.height);
        let half_dx = 0.5 / (w - 1) as f64;
        let half_dy = 0.5 / (h - 1) as f64;
        let mut conditional_cdf = Vec::with_capacity(h * (w - 1));
        let mut row_totals = Vec::with_capacity(h);
        for y in 0..h {
            let mut total = 0.0;
            for x in 0..w - 1 {
                total += half_dx * (grid.at(x, y) + grid.at(x + 1, y));
                conditional_cdf.push(total);
            }
            row_totals.push(total);
        }
        let mut marginal_cdf = Vec::with_capacity(h - 1);
        let mut total = 0.0;
        for y in 0..h - 1 {
            total += half_dy * (row_totals[y] + row_totals[y + 1]);
            marginal_cdf.push(total);
        }
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        let norm = 1.0 / total;
        Some(Self {
            density: grid.values.iter().map(|v| v * norm).collect(),
            conditional_cdf: conditional_cdf.iter().map(|v| v * norm).collect(),
            marginal_cdf: marginal_cdf.iter().map(|v| v * norm).collect(),
        })
    }
}

/// The visible-normal (VNDF) warp of every incident elevation; its inverse takes a
/// microfacet normal in unit coordinates to the warped domain of the RGB samples.
#[derive(Debug, Clone)]
pub(super) struct VndfWarp {
    width: usize,
    height: usize,
    theta_i_rad: Vec<f64>,
    slices: Vec<MarginalSlice>,
}

impl VndfWarp {
    /// Builds the warp from one density grid per incident elevation. The error gives the
    /// index of a slice that integrates to zero.
    pub(super) fn new(theta_i_rad: Vec<f64>, grids: &[Grid]) -> Result<Self, usize> {
        let slices = grids
            .iter()
            .enumerate()
            .map(|(k, g)| MarginalSlice::new(g).ok_or(k))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            width: grids[0].width,
            height: grids[0].height,
            theta_i_rad,
            slices,
        })
    }

    /// Maps a point `u` of the unit square (microfacet normal coordinates) through the inverse
    /// of the continuous marginal-conditional warp at incident elevation `theta_i_rad`.
    /// Every table entry used is interpolated linearly between the two nearest elevations.
    pub(super) fn invert(&self, u: DVec2, theta_i_rad: f64) -> DVec2 {
        let (k, w) = interval(&self.theta_i_rad, theta_i_rad);
        let next = (k + 1).min(self.slices.len() - 1);
        let blend = |pick: &dyn Fn(&MarginalSlice) -> f64| {
            lerp(pick(&self.slices[k]), pick(&self.slices[next]), w)
        };
        let (wd, hd) = (self.width, self.height);
        let cells = DVec2::new((wd - 1) as f64, (hd - 1) as f64);
        let pos = u.clamp(DVec2::ZERO, DVec2::ONE) * cells;
        let px = (pos.x as usize).min(wd - 2);
        let py = (pos.y as usize).min(hd - 2);
        let mut s = pos - DVec2::new(px as f64, py as f64);

        // Invert along x within the bilinear patch, then add the CDF up to the patch.
        let density = |x: usize, y: usize| blend(&|m| m.density[y * wd + x]);
        let c0 = lerp(density(px, py), density(px, py + 1), s.y);
        let c1 = lerp(density(px + 1, py), density(px + 1, py + 1), s.y);
        s.x *= lerp(c0, c1, 0.5 * s.x) / cells.x;
        let cdf = |x: usize, y: usize| blend(&|m| m.conditional_cdf[y * (wd - 1) + x]);
        if px > 0 {
            s.x += lerp(cdf(px - 1, py), cdf(px - 1, py + 1), s.y);
        }
        let r0 = cdf(wd - 2, py);
        let r1 = cdf(wd - 2, py + 1);
        s.x /= lerp(r0, r1, s.y);

        // Invert along y with the row totals, then add the marginal CDF up to the row.
        s.y *= lerp(r0, r1, 0.5 * s.y) / cells.y;
        if py > 0 {
            s.y += blend(&|m| m.marginal_cdf[py - 1]);
        }
        s
    }
}

impl MarginalSlice {
    /// The forward warp of this slice: the point of the unit square (microfacet normal
    /// coordinates) that [`VndfWarp::invert`] maps to the sample `s`, found by inverting the
    /// piecewise-quadratic marginal CDF along y, then the conditional one along x.
    fn sample(&self, width: usize, height: usize, s: DVec2) -> DVec2 {
        let s = s.clamp(DVec2::ZERO, DVec2::ONE);
        let (cells_x, cells_y) = ((width - 1) as f64, (height - 1) as f64);
        let row_total = |y: usize| self.conditional_cdf[y * (width - 1) + width - 2];

        // Row interval: the first whose cumulative marginal reaches s.y.
        let py = self
            .marginal_cdf
            .partition_point(|c| *c < s.y)
            .min(height - 2);
        let below = if py > 0 {
            self.marginal_cdf[py - 1]
        } else {
            0.0
        };
        let (r0, r1) = (row_total(py), row_total(py + 1));
        let ty = solve_linear_density(r0, r1, (s.y - below) * cells_y);

        // Column interval along the row blended at ty, then the offset inside it.
        let cdf = |x: usize| {
            lerp(
                self.conditional_cdf[py * (width - 1) + x],
                self.conditional_cdf[(py + 1) * (width - 1) + x],
                ty,
            )
        };
        let target = s.x * lerp(r0, r1, ty);
        let mut px = 0;
        while px < width - 2 && cdf(px) < target {
            px += 1;
        }
        let left = if px > 0 { cdf(px - 1) } else { 0.0 };
        let density = |x: usize| {
            lerp(
                self.density[py * width + x],
                self.density[(py + 1) * width + x],
                ty,
            )
        };
        let tx = solve_linear_density(density(px), density(px + 1), (target - left) * cells_x);
        DVec2::new((px as f64 + tx) / cells_x, (py as f64 + ty) / cells_y)
    }
}

/// The offset `t` in `[0, 1]` at which a density varying linearly from `a` to `b` over a unit
/// interval has accumulated `mass`: the root of `a t + (b - a) t^2 / 2 = mass`, in the form
/// that stays accurate when `b - a` is small.
fn solve_linear_density(a: f64, b: f64, mass: f64) -> f64 {
    let mass = mass.max(0.0);
    let half_slope = 0.5 * (b - a);
    let root = (a * a + 4.0 * half_slope * mass).max(0.0).sqrt();
    let denominator = a + root;
    if denominator > 0.0 {
        (2.0 * mass / denominator).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

impl VndfWarp {
    /// The forward warp of elevation slice `k` at the sample `s` of the unit square: the
    /// microfacet normal, in unit coordinates, whose inverse warp ([`Self::invert`] at the
    /// slice's own elevation) is `s`.
    pub(super) fn sample_slice(&self, k: usize, s: DVec2) -> DVec2 {
        self.slices[k].sample(self.width, self.height, s)
    }
}

fn lerp(a: f64, b: f64, t: f64) -> f64 {
    a + (b - a) * t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interval_matches_find_interval() {
        let knots = [0.0, 0.5, 1.0, 1.5];
        assert_eq!(interval(&knots, -1.0), (0, 0.0));
        assert_eq!(interval(&knots, 0.25), (0, 0.5));
        assert_eq!(interval(&knots, 0.5), (0, 1.0));
        assert_eq!(interval(&knots, 0.75), (1, 0.5));
        assert_eq!(interval(&knots, 9.0), (2, 1.0));
        assert_eq!(interval(&[3.0], 9.0), (0, 0.0));
    }

    #[test]
    fn bilinear_grid_reproduces_nodes_and_planes() {
        // f(x, y) = 1 + 2x + 3y is reproduced exactly by bilinear interpolation.
        let (w, h) = (5, 4);
        let values = (0..h)
            .flat_map(|y| (0..w).map(move |x| 1.0 + 2.0 * x as f64 / 4.0 + 3.0 * y as f64 / 3.0))
            .collect();
        let g = Grid::new(w, h, values);
        for u in [
            DVec2::new(0.1, 0.7),
            DVec2::new(1.0, 1.0),
            DVec2::new(0.0, 0.33),
        ] {
            assert!((g.eval(u) - (1.0 + 2.0 * u.x + 3.0 * u.y)).abs() < 1e-12);
        }
        assert!(
            (g.eval(DVec2::new(2.0, -1.0)) - 3.0).abs() < 1e-12,
            "clamped into the square"
        );
    }

    /// For a uniform density the warp, and so its inverse, is the identity.
    #[test]
    fn inverse_warp_of_uniform_density_is_identity() {
        let g = Grid::new(3, 4, vec![2.0; 12]);
        let warp = VndfWarp::new(vec![0.0], &[g]).unwrap();
        for u in [DVec2::new(0.2, 0.9), DVec2::new(0.77, 0.01), DVec2::ONE] {
            let s = warp.invert(u, 0.3);
            assert!((s - u).length() < 1e-12, "{u} -> {s}");
        }
    }

    #[test]
    fn inverse_warp_is_the_cdf_of_a_linear_density() {
        // Density 1 + x along x (constant in y): the normalised CDF is (x + x^2/2) / 1.5.
        let g = Grid::new(2, 2, vec![1.0, 2.0, 1.0, 2.0]);
        let warp = VndfWarp::new(vec![0.0, 1.0], &[g.clone(), g]).unwrap();
        for x in [0.0, 0.3, 0.5, 0.9, 1.0] {
            let s = warp.invert(DVec2::new(x, 0.4), 0.5);
            assert!((s.x - (x + x * x / 2.0) / 1.5).abs() < 1e-12, "{x}: {s}");
            assert!((s.y - 0.4).abs() < 1e-12);
        }
        assert_eq!(
            VndfWarp::new(vec![0.0], &[Grid::new(2, 2, vec![0.0; 4])]).unwrap_err(),
            0
        );
    }

    /// The forward warp undoes the inverse: invert(sample(s)) = s on a skewed density.
    #[test]
    fn forward_warp_inverts_the_inverse() {
        let values: Vec<f64> = (0..5 * 4)
            .map(|i| 0.1 + ((i * 7919) % 13) as f64 + if i % 5 == 0 { 0.0 } else { 2.0 })
            .collect();
        let g = Grid::new(5, 4, values);
        let warp = VndfWarp::new(vec![0.0, 1.0], &[g.clone(), g]).unwrap();
        for k in 0..2 {
            for i in 0..=20 {
                for j in 0..=20 {
                    let s = DVec2::new(i as f64 / 20.0, j as f64 / 20.0);
                    let u = warp.sample_slice(k, s);
                    let back = warp.invert(u, k as f64);
                    assert!((back - s).length() < 1e-10, "{s} -> {u} -> {back}");
                }
            }
        }
    }

    #[test]
    fn stacks_interpolate_between_elevations() {
        let a = Grid::new(2, 2, vec![1.0; 4]);
        let b = Grid::new(2, 2, vec![3.0; 4]);
        let stack = GridStack::new(vec![0.0, 1.0], vec![a, b]);
        assert!((stack.eval(DVec2::splat(0.5), 0.25) - 1.5).abs() < 1e-12);
        assert!((stack.eval(DVec2::splat(0.5), 7.0) - 3.0).abs() < 1e-12);
    }
}
