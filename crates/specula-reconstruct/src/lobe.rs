//! A microfacet lobe fitted to the samples, whose ratio to the measurement the `lobe` method
//! interpolates (see [`crate::domain`]). The lobe carries what the lattice resolves poorly:
//! the shape of the peak between theta_h nodes, the phi_d dependence of the foreshortening,
//! and the Fresnel rise towards grazing theta_d, where the device cannot reach.
//!
//! Model, per channel c (Cook-Torrance with a Student-t distribution of normals):
//!
//! ```text
//! f_c = kd_c / pi + D(theta_h) G / (4 cos_i cos_o) * (s_c + g_c (1 - cos theta_d)^5)
//! D   = (1 + tan^2 theta_h / ((gamma - 1) alpha^2))^-gamma / (pi alpha^2 cos^4 theta_h)
//! G   = G1(theta_i) G1(theta_o),  G1(theta) = 2 / (1 + sqrt(1 + alpha^2 tan^2 theta))
//! ```
//!
//! D is normalised for every gamma > 1; gamma = 2 is GGX and gamma -> infinity Beckmann.
//! `s_c + g_c (1 - cos theta_d)^5` is Schlick's Fresnel term scaled (`s = k F0`,
//! `g = k (1 - F0)`), G Smith's separable shadowing-masking term of GGX (Walter et al. 2007),
//! used for every gamma.
//!
//! **Through the instrument.** A capture integrates the BRDF over the instrument's response
//! (the light's disk, the camera's pupil, the measured area: `specula_acquisition::response`,
//! here any [`specula_core::capture::CaptureResponse`]). [`Lobe::fit_through`] fits the lobe
//! so that the lobe *integrated over the response* matches the samples (the forward model
//! of the measurement); the lobe itself is then the BRDF before the blur. Samples within
//! [`BLUR_THETA_H_DEG`] of the specular peak are integrated over the response's quadrature
//! nodes; beyond it the blur changes a lobe by less than 1 % and the nominal geometry is
//! used.
//!
//! Fit: for each (alpha, gamma) the six weights (kd, s, g per channel) come from a
//! non-negative least-squares fit with relative weights `1 / (f + eps)^2`; (alpha, gamma)
//! minimise the squared log error `sum (ln(model + eps) - ln(f + eps))^2`, found by a coarse
//! grid (scored on every fourth sample) and then a compass search in (ln alpha,
//! ln(gamma - 1)) on all samples.

use crate::domain::{log_of_measured, LOG_OFFSET};
use glam::DVec3;
use rayon::prelude::*;
use specula_core::capture::{self, orthonormal_basis, CaptureNode};
use specula_core::merl::{theta_h_centre_deg, Bin, PHI_D_BINS, THETA_D_BINS, THETA_H_BINS};
use specula_core::scattering::{fresnel, masking, ndf};
use specula_core::Sample;
use specula_core::{HalfDiff, Rgb};
use std::f64::consts::PI;

/// The angles of one configuration the lobe needs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geometry {
    /// cos theta_h, the half vector's angle from the normal.
    pub cos_theta_h: f64,
    /// cos theta_d, the angle between the light and the half vector.
    pub cos_theta_d: f64,
    /// cos of the light's angle from the normal.
    pub cos_i: f64,
    /// cos of the camera's angle from the normal.
    pub cos_o: f64,
}

impl Geometry {
    /// From the sines and cosines of theta_h, theta_d and phi_d (phi_h does not matter).
    pub fn from_trig(sin_h: f64, cos_h: f64, sin_d: f64, cos_d: f64, cos_phi_d: f64) -> Self {
        let cos_i = cos_h * cos_d - sin_h * sin_d * cos_phi_d;
        Self {
            cos_theta_h: cos_h,
            cos_theta_d: cos_d,
            cos_i,
            cos_o: 2.0 * cos_d * cos_h - cos_i,
        }
    }

    /// From the light's and the camera's directions (unit, sample frame).
    pub fn from_directions(wi: DVec3, wo: DVec3) -> Self {
        let h = (wi + wo).normalize();
        Self {
            cos_theta_h: h.z,
            cos_theta_d: wi.dot(h).clamp(-1.0, 1.0),
            cos_i: wi.z,
            cos_o: wo.z,
        }
    }

    /// From half-difference angles (rad).
    pub(crate) fn of(hd: HalfDiff) -> Self {
        let (sin_h, cos_h) = hd.theta_h.sin_cos();
        let (sin_d, cos_d) = hd.theta_d.sin_cos();
        Self::from_trig(sin_h, cos_h, sin_d, cos_d, hd.phi_d.cos())
    }

    /// Both directions above the surface.
    pub fn above_surface(&self) -> bool {
        self.cos_i > 0.0 && self.cos_o > 0.0
    }

    /// `G / (4 cos_i cos_o)` for roughness `alpha`, zero below the surface.
    pub fn shadowing_over_foreshortening(&self, alpha: f64) -> f64 {
        if !self.above_surface() {
            return 0.0;
        }
        masking::ggx_g1_over_cos(self.cos_i, alpha) * masking::ggx_g1_over_cos(self.cos_o, alpha)
            / 4.0
    }

    /// Schlick's `(1 - cos theta_d)^5`.
    pub fn schlick_weight(&self) -> f64 {
        fresnel::schlick_weight(self.cos_theta_d)
    }

    /// `tan^2 theta_h`.
    pub fn tan2_theta_h(&self) -> f64 {
        let c2 = self.cos_theta_h * self.cos_theta_h;
        (1.0 - c2).max(0.0) / c2.max(1e-300)
    }
}

/// The shape of the distribution of normals.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shape {
    /// Roughness (width of the peak in tan theta_h).
    pub alpha: f64,
    /// Tail exponent, > 1 (2: GGX, large: Beckmann).
    pub gamma: f64,
}

impl Shape {
    /// The peak's half width at half maximum in theta_h, degrees: where
    /// `(1 + tan^2 / ((gamma - 1) alpha^2))^-gamma` is 1/2 (the `cos^4` is 1 to within the
    /// width's square).
    pub fn half_width_deg(&self) -> f64 {
        let tan2 =
            (self.gamma - 1.0) * self.alpha * self.alpha * (2f64.powf(1.0 / self.gamma) - 1.0);
        tan2.sqrt().atan().to_degrees()
    }

    /// D(theta_h) given `tan^2 theta_h` and `cos theta_h`.
    pub fn distribution(&self, tan2_h: f64, cos_h: f64) -> f64 {
        ndf::student_t_d(tan2_h, cos_h, self.alpha, self.gamma)
    }
}

/// A fitted lobe (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lobe {
    /// The shape of the distribution of normals.
    pub shape: Shape,
    /// kd per channel.
    pub diffuse: Rgb,
    /// `k F0` per channel.
    pub specular: Rgb,
    /// `k (1 - F0)` per channel.
    pub grazing: Rgb,
}

impl Lobe {
    /// f in 1/sr at a configuration; zero below the surface.
    pub fn eval(&self, g: &Geometry) -> Rgb {
        if !g.above_surface() {
            return Rgb::ZERO;
        }
        let d = self.shape.distribution(g.tan2_theta_h(), g.cos_theta_h);
        let s = d * g.shadowing_over_foreshortening(self.shape.alpha);
        self.diffuse / PI + s * (self.specular + g.schlick_weight() * self.grazing)
    }

    /// What a capture at `hd` measures of the lobe through the response's `nodes`
    /// ([`capture::measure`]); the lobe itself without nodes.
    pub fn measured(&self, nodes: &[CaptureNode], hd: HalfDiff) -> Rgb {
        if nodes.is_empty() {
            return self.eval(&Geometry::of(hd));
        }
        let (wi, wo) = hd.to_directions();
        capture::measure(nodes, wi, wo, |a, b| {
            self.eval(&Geometry::from_directions(a, b))
        })
    }

    /// The lobe that best fits the samples (see the module documentation); `None` when no
    /// sample lies above the surface.
    pub fn fit(samples: &[Sample]) -> Option<Lobe> {
        Self::fit_through(samples, &[])
    }

    /// The lobe whose integral over the response's quadrature `nodes` best fits the samples
    /// (see the module documentation; no nodes: the lobe itself); `None` when no sample lies
    /// above the surface.
    pub fn fit_through(samples: &[Sample], nodes: &[CaptureNode]) -> Option<Lobe> {
        let points: Vec<FitPoint> = samples
            .par_iter()
            .filter_map(|s| FitPoint::of(s, nodes))
            .collect();
        if points.is_empty() {
            return None;
        }
        let grid: Vec<(f64, f64)> = ALPHA_GRID
            .iter()
            .flat_map(|&a| {
                GAMMA_MINUS_ONE_GRID
                    .iter()
                    .map(move |&g| (f64::ln(a), f64::ln(g)))
            })
            .collect();
        // The coarse grid only picks the basin: every GRID_STRIDE-th sample is enough for it.
        let coarse: Vec<FitPoint> = points.iter().step_by(GRID_STRIDE).cloned().collect();
        let (mut best, _) = grid
            .par_iter()
            .map(|&p| (p, fit_weights(&coarse, shape_of(p)).1))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .expect("grid is not empty");
        let mut best_cost = fit_weights(&points, shape_of(best)).1;
        let mut step = 0.5 * GRID_LOG_STEP;
        while step > MIN_LOG_STEP {
            let moves = [(step, 0.0), (-step, 0.0), (0.0, step), (0.0, -step)];
            let candidate = moves
                .par_iter()
                .map(|m| {
                    let p = (best.0 + m.0, best.1 + m.1);
                    (p, fit_weights(&points, shape_of(p)).1)
                })
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .expect("four moves");
            if candidate.1 < best_cost {
                (best, best_cost) = candidate;
            } else {
                step *= 0.5;
            }
        }
        Some(fit_weights(&points, shape_of(best)).0)
    }
}

/// A lobe evaluated at the MERL bin centres, with the factors that depend on one angle only
/// (the distribution on theta_h, Schlick's weight on theta_d) computed once per bin.
pub struct LobeOnGrid {
    lobe: Lobe,
    /// `(sin, cos, D)` per theta_h bin.
    theta_h: Vec<(f64, f64, f64)>,
    /// `(sin, cos, Schlick weight)` per theta_d bin.
    theta_d: Vec<(f64, f64, f64)>,
    cos_phi_d: Vec<f64>,
}

impl LobeOnGrid {
    /// Tabulates the lobe's factors at every MERL bin centre.
    pub(crate) fn new(lobe: Lobe) -> Self {
        let trig = |deg: f64| deg.to_radians().sin_cos();
        let theta_h = (0..THETA_H_BINS)
            .map(|i| {
                let (s, c) = trig(theta_h_centre_deg(i));
                let tan2 = (s / c) * (s / c);
                (s, c, lobe.shape.distribution(tan2, c))
            })
            .collect();
        let theta_d = (0..THETA_D_BINS)
            .map(|j| {
                let (s, c) = trig(j as f64 + 0.5);
                (s, c, fresnel::schlick_weight(c))
            })
            .collect();
        let cos_phi_d = (0..PHI_D_BINS).map(|k| trig(k as f64 + 0.5).1).collect();
        Self {
            lobe,
            theta_h,
            theta_d,
            cos_phi_d,
        }
    }

    /// The lobe at the centre of MERL cell `index`, as [`Lobe::eval`] gives it.
    pub fn at(&self, index: usize) -> Rgb {
        let bin = Bin::from_index(index);
        let (sin_h, cos_h, d) = self.theta_h[bin.theta_h_i];
        let (sin_d, cos_d, schlick) = self.theta_d[bin.theta_d_i];
        let g = Geometry::from_trig(sin_h, cos_h, sin_d, cos_d, self.cos_phi_d[bin.phi_d_i]);
        if !g.above_surface() {
            return Rgb::ZERO;
        }
        let l = &self.lobe;
        let s = d * g.shadowing_over_foreshortening(l.shape.alpha);
        l.diffuse / PI + s * (l.specular + schlick * l.grazing)
    }
}

/// Coarse grid of alpha for the fit.
const ALPHA_GRID: [f64; 14] = [
    0.0005, 0.001, 0.002, 0.004, 0.008, 0.016, 0.03, 0.06, 0.12, 0.2, 0.3, 0.45, 0.65, 0.9,
];
/// Coarse grid of gamma - 1 for the fit.
const GAMMA_MINUS_ONE_GRID: [f64; 5] = [0.3, 1.0, 3.0, 10.0, 50.0];
/// The coarse grid is scored on every this-many-th sample.
const GRID_STRIDE: usize = 4;
/// The first compass step in ln units (about the grid's spacing).
const GRID_LOG_STEP: f64 = 0.7;
const MIN_LOG_STEP: f64 = 0.002;

fn shape_of((ln_alpha, ln_gamma_minus_one): (f64, f64)) -> Shape {
    Shape {
        alpha: ln_alpha.exp().clamp(1e-5, 2.0),
        gamma: 1.0 + ln_gamma_minus_one.exp().clamp(0.05, 1e4),
    }
}

/// Samples this close to the specular peak (theta_h, degrees) are fitted through the
/// response's nodes; beyond it the blur of a 1-degree response changes a microfacet lobe's
/// tail by under 1 %.
pub const BLUR_THETA_H_DEG: f64 = 20.0;

/// The shape-independent parts of the model at one pair of directions, with its weight in
/// the capture (`cos theta_i' / cos theta_i` over the node count; 1 at the nominal one).
#[derive(Clone, Copy)]
struct NodeGeometry {
    tan2_h: f64,
    cos_h: f64,
    cos_i: f64,
    cos_o: f64,
    schlick: f64,
    weight: f64,
}

impl NodeGeometry {
    fn of(g: &Geometry, weight: f64) -> Self {
        Self {
            tan2_h: g.tan2_theta_h(),
            cos_h: g.cos_theta_h,
            cos_i: g.cos_i,
            cos_o: g.cos_o,
            schlick: g.schlick_weight(),
            weight,
        }
    }

    /// The three basis functions of the linear weights (kd, s, g), times the weight.
    fn basis(&self, shape: Shape) -> [f64; 3] {
        if self.cos_i <= 0.0 || self.cos_o <= 0.0 {
            return [0.0; 3];
        }
        let geometric = masking::ggx_g1_over_cos(self.cos_i, shape.alpha)
            * masking::ggx_g1_over_cos(self.cos_o, shape.alpha)
            / 4.0;
        let s = shape.distribution(self.tan2_h, self.cos_h) * geometric * self.weight;
        [self.weight / PI, s, s * self.schlick]
    }
}

/// A sample prepared for the fit: the shape-independent parts of the model at the nominal
/// geometry or at every node of the response.
#[derive(Clone)]
struct FitPoint {
    geometry: Vec<NodeGeometry>,
    value: [f64; 3],
    /// The relative weight `1 / (f + eps)^2` per channel.
    weight: [f64; 3],
    /// `ln(f + eps)` per channel.
    log_value: [f64; 3],
}

impl FitPoint {
    fn of(sample: &Sample, nodes: &[CaptureNode]) -> Option<Self> {
        let g = Geometry::of(sample.hd);
        if !g.above_surface() {
            return None;
        }
        let blurred = !nodes.is_empty() && sample.hd.theta_h.to_degrees() < BLUR_THETA_H_DEG;
        let geometry = if blurred {
            let (wi, wo) = sample.hd.to_directions();
            let n = nodes.len() as f64;
            let (li, lj) = orthonormal_basis(wi);
            let (ci, cj) = orthonormal_basis(wo);
            nodes
                .iter()
                .map(|node| {
                    let a = (wi + node.light.x * li + node.light.y * lj).normalize();
                    let b = (wo + node.camera.x * ci + node.camera.y * cj).normalize();
                    NodeGeometry::of(&Geometry::from_directions(a, b), a.z / (wi.z * n))
                })
                .collect()
        } else {
            vec![NodeGeometry::of(&g, 1.0)]
        };
        Some(Self {
            geometry,
            value: sample.value.to_array(),
            weight: sample
                .value
                .to_array()
                .map(|f| (f.max(0.0) + LOG_OFFSET).powi(-2)),
            log_value: sample.value.to_array().map(log_of_measured),
        })
    }

    /// The three basis functions of the linear weights (kd, s, g) as the capture sees them.
    fn basis(&self, shape: Shape) -> [f64; 3] {
        self.geometry.iter().fold([0.0; 3], |acc, g| {
            let b = g.basis(shape);
            [acc[0] + b[0], acc[1] + b[1], acc[2] + b[2]]
        })
    }
}

/// The best non-negative weights for a shape, and the squared log error they leave.
fn fit_weights(points: &[FitPoint], shape: Shape) -> (Lobe, f64) {
    let bases: Vec<[f64; 3]> = points.iter().map(|p| p.basis(shape)).collect();
    let mut normal = [[[0.0; 3]; 3]; 3];
    let mut rhs = [[0.0; 3]; 3];
    for (p, phi) in points.iter().zip(&bases) {
        for c in 0..3 {
            let w = p.weight[c];
            for a in 0..3 {
                rhs[c][a] += w * phi[a] * p.value[c];
                for b in a..3 {
                    normal[c][a][b] += w * phi[a] * phi[b];
                }
            }
        }
    }
    for matrix in &mut normal {
        for (a, b) in [(1, 0), (2, 0), (2, 1)] {
            matrix[a][b] = matrix[b][a];
        }
    }
    let weights: [[f64; 3]; 3] =
        std::array::from_fn(|c| nonnegative_least_squares(&normal[c], &rhs[c]));
    let lobe = Lobe {
        shape,
        diffuse: Rgb::new(weights[0][0], weights[1][0], weights[2][0]),
        specular: Rgb::new(weights[0][1], weights[1][1], weights[2][1]),
        grazing: Rgb::new(weights[0][2], weights[1][2], weights[2][2]),
    };
    let cost = points
        .iter()
        .zip(&bases)
        .map(|(p, phi)| {
            (0..3)
                .map(|c| {
                    let m =
                        weights[c][0] * phi[0] + weights[c][1] * phi[1] + weights[c][2] * phi[2];
                    ((m + LOG_OFFSET).ln() - p.log_value[c]).powi(2)
                })
                .sum::<f64>()
        })
        .sum();
    (lobe, cost)
}

/// Minimises `x' A x - 2 b' x` over `x >= 0` for a 3 x 3 positive semi-definite `A`, by
/// trying every set of free variables, smaller sets first; a larger set must do better by
/// more than rounding, so that data one term explains exactly (a constant) keep the others 0.
fn nonnegative_least_squares(a: &[[f64; 3]; 3], b: &[f64; 3]) -> [f64; 3] {
    let mut best: ([f64; 3], f64) = ([0.0; 3], 0.0);
    for set in [1u8, 2, 4, 3, 5, 6, 7] {
        let free: Vec<usize> = (0..3).filter(|i| set & (1 << i) != 0).collect();
        let Some(sol) = solve_subset(a, b, &free) else {
            continue;
        };
        if sol.iter().any(|v| *v < 0.0) {
            continue;
        }
        let mut x = [0.0; 3];
        for (k, &i) in free.iter().enumerate() {
            x[i] = sol[k];
        }
        let quad: f64 = (0..3)
            .map(|i| (0..3).map(|j| x[i] * a[i][j] * x[j]).sum::<f64>())
            .sum();
        let objective = quad - 2.0 * (0..3).map(|i| b[i] * x[i]).sum::<f64>();
        if objective < best.1 - 1e-9 * best.1.abs() {
            best = (x, objective);
        }
    }
    best.0
}

/// Solves the normal equations restricted to the `free` variables by Gauss-Jordan
/// elimination with partial pivoting; `None` when (numerically) singular.
fn solve_subset(a: &[[f64; 3]; 3], b: &[f64; 3], free: &[usize]) -> Option<Vec<f64>> {
    let n = free.len();
    let mut m: Vec<Vec<f64>> = free
        .iter()
        .map(|&i| free.iter().map(|&j| a[i][j]).chain([b[i]]).collect())
        .collect();
    let size = free.iter().map(|&i| a[i][i]).fold(0.0, f64::max);
    for col in 0..n {
        let pivot = (col..n).max_by(|&x, &y| m[x][col].abs().total_cmp(&m[y][col].abs()))?;
        if m[pivot][col].abs() <= 1e-12 * size {
            return None;
        }
        m.swap(col, pivot);
        let pivot_row = m[col].clone();
        for (r, row) in m.iter_mut().enumerate() {
            if r != col {
                let f = row[col] / pivot_row[col];
                for (x, p) in row.iter_mut().zip(&pivot_row).skip(col) {
                    *x -= f * p;
                }
            }
        }
    }
    Some((0..n).map(|i| m[i][n] / m[i][i]).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geometry_matches_the_directions() {
        for (h, d, p) in [
            (0.0, 40.0, 90.0),
            (10.0, 30.0, 0.0),
            (25.0, 50.0, 130.0),
            (3.0, 80.0, 200.0),
        ] {
            let hd = HalfDiff::from_degrees(h, 45.0, d, p);
            let (wi, wo) = hd.to_directions();
            let g = Geometry::of(hd);
            assert!(
                (g.cos_i - wi.z).abs() < 1e-12 && (g.cos_o - wo.z).abs() < 1e-12,
                "{h} {d} {p}"
            );
        }
    }

    #[test]
    fn the_distribution_is_normalised_for_every_tail() {
        for shape in [
            Shape {
                alpha: 0.05,
                gamma: 1.5,
            },
            Shape {
                alpha: 0.2,
                gamma: 2.0,
            },
            Shape {
                alpha: 0.3,
                gamma: 60.0,
            },
        ] {
            // Projected area: integral of D cos theta_h over the hemisphere is 1.
            let n = 200_000;
            let integral: f64 = (0..n)
                .map(|i| {
                    let t = (i as f64 + 0.5) / n as f64 * PI / 2.0;
                    let (s, c) = t.sin_cos();
                    shape.distribution(s * s / (c * c), c)
                        * c
                        * s
                        * 2.0
                        * PI
                        * (PI / 2.0 / n as f64)
                })
                .sum();
            // The heavy tail (gamma 1.5, alpha 0.05) loses a little past 90 degrees of tan.
            assert!((integral - 1.0).abs() < 0.01, "{shape:?}: {integral}");
        }
        // gamma = 2 is GGX.
        let (a, t2, c): (f64, f64, f64) = (0.1, 0.04, 1.0 / 1.04f64.sqrt());
        let ggx = a * a / (PI * c.powi(4) * (a * a + t2).powi(2));
        assert!(
            (Shape {
                alpha: a,
                gamma: 2.0
            }
            .distribution(t2, c)
                - ggx)
                .abs()
                < 1e-9 * ggx
        );
    }

    #[test]
    fn a_lobe_is_recovered_from_its_own_samples() {
        let truth = Lobe {
            shape: Shape {
                alpha: 0.03,
                gamma: 3.0,
            },
            diffuse: Rgb::new(0.05, 0.1, 0.02),
            specular: Rgb::new(0.9, 0.8, 0.5),
            grazing: Rgb::new(0.1, 0.2, 0.5),
        };
        let mut samples = Vec::new();
        for h in [0.0, 0.3, 0.8, 1.5, 3.0, 6.0, 12.0, 25.0, 45.0] {
            for d in [0.0, 20.0, 40.0, 60.0, 70.0] {
                for p in [0.0, 45.0, 90.0] {
                    let hd = HalfDiff::from_degrees(h, 45.0, d, p);
                    let g = Geometry::of(hd);
                    if g.above_surface() {
                        samples.push(Sample::new(hd, truth.eval(&g)));
                    }
                }
            }
        }
        let fit = Lobe::fit(&samples).unwrap();
        assert!(
            (fit.shape.alpha / truth.shape.alpha - 1.0).abs() < 0.03,
            "{fit:?}"
        );
        for s in &samples {
            let m = fit.eval(&Geometry::of(s.hd));
            let rel = ((m - s.value) / (s.value + Rgb::splat(LOG_OFFSET)))
                .abs()
                .max_element();
            assert!(rel < 0.05, "{:?}: {m} vs {}", s.hd, s.value);
        }
    }

    #[test]
    fn a_sample_noise_took_below_zero_does_not_derail_the_fit() {
        // A lobe with no diffuse red and its samples, plus one dark configuration whose red
        // camera noise left it below zero (-3e-4 1/sr after the dark frame, as the simulated
        // device measures the RGL clear coats). Its logarithm once made every cost NaN, and the
        // search then kept whichever shape of its grid the reduction met first (on a real
        // clear coat alpha 0.0005: a spike of 4000 1/sr where the material has 3).
        let truth = Lobe {
            shape: Shape {
                alpha: 0.045,
                gamma: 2.5,
            },
            diffuse: Rgb::new(0.0, 0.1, 0.02),
            specular: Rgb::new(0.05, 0.8, 0.5),
            grazing: Rgb::new(1.0, 0.2, 0.5),
        };
        let mut samples = Vec::new();
        for h in [0.0, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 30.0, 50.0] {
            for d in [0.0, 20.0, 40.0, 60.0, 70.0] {
                let hd = HalfDiff::from_degrees(h, 45.0, d, 90.0);
                let g = Geometry::of(hd);
                if g.above_surface() {
                    samples.push(Sample::new(hd, truth.eval(&g)));
                }
            }
        }
        let dark = HalfDiff::from_degrees(60.0, 45.0, 5.0, 90.0);
        samples.push(Sample::new(dark, Rgb::new(-3e-4, 1e-3, 1e-3)));
        let fit = Lobe::fit(&samples).unwrap();
        assert!(
            (fit.shape.alpha / truth.shape.alpha - 1.0).abs() < 0.05,
            "{fit:?}"
        );
    }

    #[test]
    fn the_grid_evaluation_matches_the_direct_one() {
        let lobe = Lobe {
            shape: Shape {
                alpha: 0.02,
                gamma: 2.5,
            },
            diffuse: Rgb::new(0.05, 0.1, 0.02),
            specular: Rgb::new(0.9, 0.8, 0.5),
            grazing: Rgb::new(0.1, 0.2, 0.5),
        };
        let grid = LobeOnGrid::new(lobe);
        for index in (0..specula_core::merl::CELLS).step_by(1013) {
            let direct = lobe.eval(&Geometry::of(Bin::from_index(index).centre(0.0)));
            let fast = grid.at(index);
            assert!(
                (direct - fast).abs().max_element() <= 1e-9 * (1.0 + direct.max_element()),
                "{index}"
            );
        }
    }

    #[test]
    fn the_half_width_halves_the_distribution() {
        for shape in [
            Shape {
                alpha: 0.01,
                gamma: 2.0,
            },
            Shape {
                alpha: 0.05,
                gamma: 30.0,
            },
        ] {
            let t = shape.half_width_deg().to_radians();
            let tan2 = t.tan().powi(2);
            let ratio = shape.distribution(tan2, 1.0) / shape.distribution(0.0, 1.0);
            assert!((ratio - 0.5).abs() < 1e-9, "{shape:?}: {ratio}");
        }
        // GGX: tan = alpha sqrt(sqrt 2 - 1).
        let ggx = Shape {
            alpha: 0.02,
            gamma: 2.0,
        };
        let expected = (0.02 * (2f64.sqrt() - 1.0).sqrt()).atan().to_degrees();
        assert!((ggx.half_width_deg() - expected).abs() < 1e-12);
    }

    #[test]
    fn a_lobe_is_recovered_through_the_instrument() {
        // Samples of a GGX-like lobe (alpha 0.01, narrower than the 1.8-degree disk resolves)
        // as the instrument measures them, integrated over 2048 nodes of the response; the
        // fit through 256 other nodes recovers the lobe before the blur, the plain fit
        // does not.
        let response = specula_acquisition::device::Device::utia().response();
        let world = response.capture_nodes(2048);
        let truth = Lobe {
            shape: Shape {
                alpha: 0.01,
                gamma: 2.0,
            },
            diffuse: Rgb::splat(0.01),
            specular: Rgb::new(0.9, 0.8, 0.6),
            grazing: Rgb::new(0.1, 0.2, 0.4),
        };
        let mut samples = Vec::new();
        for h in [0.0, 0.2, 0.4, 0.7, 1.0, 1.4, 2.0, 3.0, 5.0, 8.0, 15.0, 30.0] {
            for d in [10.0, 30.0, 50.0, 70.0] {
                for p in [0.0, 45.0, 90.0] {
                    let hd = HalfDiff::from_degrees(h, 45.0, d, p);
                    if Geometry::of(hd).above_surface() {
                        samples.push(Sample::new(hd, truth.measured(&world, hd)));
                    }
                }
            }
        }
        let nodes = response.capture_nodes(256);
        let through = Lobe::fit_through(&samples, &nodes).unwrap();
        let plain = Lobe::fit(&samples).unwrap();
        let alpha_error = |l: &Lobe| (l.shape.alpha / truth.shape.alpha - 1.0).abs();
        assert!(alpha_error(&through) < 0.1, "{through:?}");
        assert!(alpha_error(&plain) > 0.5, "{plain:?}");
        let peak = Geometry::of(HalfDiff::from_degrees(0.0, 45.0, 30.0, 90.0));
        let ratio = through.eval(&peak).y / truth.eval(&peak).y;
        assert!((ratio - 1.0).abs() < 0.15, "peak ratio {ratio}");
    }

    #[test]
    fn nnls_clamps_negative_weights() {
        // Unconstrained solution of diag(1,1,1) x = (1, -2, 3) is (1, -2, 3).
        let a = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        assert_eq!(
            nonnegative_least_squares(&a, &[1.0, -2.0, 3.0]),
            [1.0, 0.0, 3.0]
        );
    }
}
