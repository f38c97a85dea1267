//! The microfacet distribution of an arbitrary BRDF, from its retro-reflection by power
//! iteration (Dupuy, Heitz, Iehl, Poulin, Ostromoukhov, "Extracting Microfacet-based BRDF
//! Parameters from Arbitrary Materials with Power Iterations", EGSR 2015), the way the RGL
//! material database derives the `ndf` and `sigma` fields of its files (Dupuy & Jakob 2018,
//! section 5).
//!
//! For a microfacet BRDF `f = F D G / (4 cos_i cos_o)` seen in retro-reflection (`wi = wo =
//! w`, so `h = w` and, with correlated masking, `G = G1(w) = cos(theta) / sigma(w)`):
//!
//! `f(w, w) = F D(w) / (4 cos(theta) sigma(w))`, hence `D(w) ∝ f(w, w) cos(theta) sigma(w)`,
//!
//! where `sigma(w) = ∫ D(m) <m . w> dm` is the projected area of the microsurface. `sigma`
//! depends on `D`, so `D` is the dominant eigenvector of that linear map and power iteration
//! finds it: `D_{k+1} = f(w, w) cos(theta) sigma_k(w)`, normalised so that `∫ D cos = 1`
//! (that is `sigma(normal) = 1`). Fresnel at normal incidence (`theta_d = 0` for every
//! retro-reflection) is a constant factor that the normalisation removes. The BRDF's
//! luminance is used, read with [`Brdf::eval_smooth`] as the writer reads its samples: a
//! table's interpolant, not its nearest bin, whose steps `D` would otherwise carry into every
//! sample it divides (the writer stores `f_r cos / D`; a step of `D` that `f_r` does not share
//! reappears between the nodes as an error of the step's size).
//!
//! Both tables are tabulated, isotropic, at elevations `theta = u^2 pi / 2` for `u` evenly
//! spaced on `[0, 1]`, the unit coordinate of the RGL tables; between nodes `D` is linear in
//! `u`, as Mitsuba interpolates it.

use specula_core::brdf::luminance;
use specula_core::Brdf;
use std::f64::consts::PI;

/// Retro-reflection is evaluated at most this far from the normal: at 90 degrees both
/// directions lie on the horizon, where a BRDF is zero by definition.
const MAX_RETRO_ELEVATION_RAD: f64 = 89.5 * PI / 180.0;
/// Retro-reflection below this fraction of its maximum is raised to it, so that `D` is
/// positive everywhere and the RGL values `f cos(theta_o) 4 sigma / D` stay finite.
const RETRO_FLOOR: f64 = 1e-6;
/// Power iteration stops when no node of `D` changes by more than this, relative to the peak.
const CONVERGED: f64 = 1e-9;
/// At most this many power iterations (Dupuy et al. report convergence in a few).
const MAX_ITERATIONS: usize = 200;
/// Quadrature steps of the projected-area integral per interval of the `u` grid.
const STEPS_PER_CELL: usize = 8;

/// The tabulated distribution of normals and its projected area.
#[derive(Debug, Clone)]
pub(super) struct RetroNdf {
    /// `D` in 1/sr at the nodes, normalised so that `∫ D(m) cos(theta_m) dm = 1`.
    pub d: Vec<f64>,
    /// `sigma(theta) = ∫ D(m) <m . w> dm` at the same nodes (1 at the normal).
    pub sigma: Vec<f64>,
    /// Nodes whose retro-reflection the BRDF has not measured (filled from the nearest
    /// measured node).
    pub not_measured: usize,
    /// Power iterations done.
    pub iterations: usize,
}

/// The elevation, radians, of node `j` of `n` nodes: `theta = u^2 pi / 2`, `u = j / (n - 1)`.
pub(super) fn node_elevation_rad(j: usize, n: usize) -> f64 {
    let u = j as f64 / (n - 1) as f64;
    u * u * PI / 2.0
}

impl RetroNdf {
    /// The distribution of `brdf` at `n >= 2` nodes; `None` when the retro-reflection is
    /// zero or not measured at every node.
    pub(super) fn from_brdf(brdf: &dyn Brdf, n: usize) -> Option<Self> {
        let (retro, not_measured) = retro_reflection(brdf, n)?;
        let cosines: Vec<f64> = (0..n).map(|j| node_elevation_rad(j, n).cos()).collect();
        let mut d: Vec<f64> = retro.iter().zip(&cosines).map(|(f, c)| f * c).collect();
        normalise(&mut d);
        let mut iterations = 0;
        while iterations < MAX_ITERATIONS {
            iterations += 1;
            let sigma = projected_areas(&d);
            let mut next: Vec<f64> = (0..n).map(|j| retro[j] * cosines[j] * sigma[j]).collect();
            normalise(&mut next);
            let peak = next.iter().cloned().fold(0.0, f64::max);
            let change = next
                .iter()
                .zip(&d)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            d = next;
            if change <= CONVERGED * peak {
                break;
            }
        }
        let sigma = projected_areas(&d);
        Some(Self {
            d,
            sigma,
            not_measured,
            iterations,
        })
    }
}

/// Luminance of the retro-reflection (the source's interpolant) at each node, floored at
/// [`RETRO_FLOOR`] of its peak; unmeasured nodes take the nearest measured node's value. Also
/// returns how many were unmeasured; `None` if no node has a positive value.
fn retro_reflection(brdf: &dyn Brdf, n: usize) -> Option<(Vec<f64>, usize)> {
    let measured: Vec<Option<f64>> = (0..n)
        .map(|j| {
            let theta = node_elevation_rad(j, n).min(MAX_RETRO_ELEVATION_RAD);
            let w = glam::DVec3::new(theta.sin(), 0.0, theta.cos());
            brdf.eval_smooth(w, w).map(|rgb| luminance(rgb).max(0.0))
        })
        .collect();
    let not_measured = measured.iter().filter(|v| v.is_none()).count();
    let known: Vec<usize> = (0..n).filter(|j| measured[*j].is_some()).collect();
    let mut values: Vec<f64> = (0..n)
        .map(|j| {
            let nearest = known.iter().min_by_key(|k| k.abs_diff(j))?;
            measured[*nearest]
        })
        .collect::<Option<_>>()?;
    let peak = values.iter().cloned().fold(0.0, f64::max);
    if !(peak > 0.0 && peak.is_finite()) {
        return None;
    }
    for v in &mut values {
        *v = v.max(RETRO_FLOOR * peak);
    }
    Some((values, not_measured))
}

/// Scales `d` so that its projected area at the normal, `∫ D cos`, is 1.
fn normalise(d: &mut [f64]) {
    let total = projected_area(d, 0.0);
    for v in d.iter_mut() {
        *v /= total;
    }
}

/// `sigma` at every node of `d`'s grid.
fn projected_areas(d: &[f64]) -> Vec<f64> {
    (0..d.len())
        .map(|j| projected_area(d, node_elevation_rad(j, d.len())))
        .collect()
}

/// `sigma(theta) = ∫ D(m) max(0, m . w) dm` for `w` at elevation `theta_rad`, with `D` linear
/// in `u` between the nodes: midpoint rule in `u` (`dtheta = pi u du`), the azimuthal integral
/// in closed form ([`azimuthal_clamped_cosine`]).
fn projected_area(d: &[f64], theta_rad: f64) -> f64 {
    let cells = d.len() - 1;
    let steps = cells * STEPS_PER_CELL;
    let du = 1.0 / steps as f64;
    (0..steps)
        .map(|k| {
            let u = (k as f64 + 0.5) * du;
            let pos = u * cells as f64;
            let j = (pos as usize).min(cells - 1);
            let t = pos - j as f64;
            let density = d[j] + (d[j + 1] - d[j]) * t;
            let theta_m = u * u * PI / 2.0;
            density * theta_m.sin() * PI * u * azimuthal_clamped_cosine(theta_rad, theta_m) * du
        })
        .sum()
}

/// `∫_0^{2 pi} max(0, cos(theta) cos(theta_m) + sin(theta) sin(theta_m) cos(phi)) dphi`:
/// the clamped cosine between a direction at elevation `theta` and the normals of elevation
/// `theta_m`, integrated over their azimuth.
fn azimuthal_clamped_cosine(theta_rad: f64, theta_m_rad: f64) -> f64 {
    let a = theta_rad.cos() * theta_m_rad.cos();
    let b = theta_rad.sin() * theta_m_rad.sin();
    if a >= b {
        2.0 * PI * a
    } else if a <= -b {
        0.0
    } else {
        let phi0 = (-a / b).acos();
        2.0 * (a * phi0 + b * phi0.sin())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::materials::microfacet::{Distribution, Microfacet};

    #[test]
    fn clamped_cosine_matches_quadrature() {
        for (theta, theta_m) in [(0.3, 0.2), (1.2, 0.9), (1.5, 0.1), (0.0, 1.0), (1.4, 1.3)] {
            let n = 20_000;
            let numeric: f64 = (0..n)
                .map(|k| {
                    let phi = (k as f64 + 0.5) * 2.0 * PI / n as f64;
                    let c = f64::cos(theta) * f64::cos(theta_m)
                        + f64::sin(theta) * f64::sin(theta_m) * phi.cos();
                    c.max(0.0) * 2.0 * PI / n as f64
                })
                .sum();
            let closed = azimuthal_clamped_cosine(theta, theta_m);
            assert!(
                (numeric - closed).abs() < 1e-7,
                "{theta} {theta_m}: {numeric} {closed}"
            );
        }
    }

    /// A GGX microfacet BRDF (Fresnel 1) whose masking in retro-reflection is `G1` (as for
    /// height-correlated Smith masking, the method's assumption): power iteration recovers its
    /// D and its projected area `cos(theta) / G1`, both known in closed form.
    #[test]
    fn power_iteration_recovers_ggx() {
        struct Ggx(Microfacet);
        impl Brdf for Ggx {
            fn eval(&self, wi: glam::DVec3, wo: glam::DVec3) -> Option<specula_core::Rgb> {
                let h = (wi + wo).normalize();
                let f = self.0.d(h) * self.0.g1(wi, h) / (4.0 * wi.z * wo.z);
                Some(specula_core::Rgb::splat(f))
            }
            fn name(&self) -> String {
                "ggx".into()
            }
        }
        for alpha in [0.05, 0.3] {
            let model = Microfacet::isotropic(Distribution::Ggx, alpha);
            let n = 128;
            let model_copy = Microfacet::isotropic(Distribution::Ggx, alpha);
            let ndf = RetroNdf::from_brdf(&Ggx(model_copy), n).unwrap();
            assert!(ndf.iterations > 1 && ndf.iterations < MAX_ITERATIONS);
            assert!((ndf.sigma[0] - 1.0).abs() < 1e-9);
            for j in (0..n).step_by(9) {
                let theta = node_elevation_rad(j, n);
                let m = glam::DVec3::new(theta.sin(), 0.0, theta.cos());
                let exact = model.d(m);
                if exact > 1e-3 * model.d(glam::DVec3::Z) && theta < MAX_RETRO_ELEVATION_RAD {
                    let rel = (ndf.d[j] - exact).abs() / exact;
                    assert!(
                        rel < 5e-3,
                        "alpha {alpha} theta {theta}: {} vs {exact}",
                        ndf.d[j]
                    );
                }
                if theta < 1.4 {
                    let sigma = theta.cos() / model.g1(m, glam::DVec3::Z);
                    let rel = (ndf.sigma[j] - sigma).abs() / sigma;
                    assert!(
                        rel < 5e-3,
                        "alpha {alpha} theta {theta}: sigma {} vs {sigma}",
                        ndf.sigma[j]
                    );
                }
            }
        }
    }
}
