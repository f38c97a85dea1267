//! Microfacet normal distributions `D(m)`: the density of microfacet normals `m` per unit
//! solid angle, in 1/sr, normalised in projected area,
//!
//! ```text
//! int_H D(m) cos(theta_m) dm = 1                     (Walter et al. 2007, eq. 4)
//! ```
//!
//! Each is written in terms of `x = tan^2(theta_m) / alpha^2`, with `alpha` the roughness
//! projected on `m`'s azimuth (`x = ((m.x / alpha_u)^2 + (m.y / alpha_v)^2) / m.z^2`,
//! [`scaled_tan2`]), and `cos^2 theta_m`, as Mitsuba 3's `MicrofacetDistribution::eval`:
//!
//! ```text
//! GGX       D = 1 / (pi alpha_u alpha_v cos^4 (1 + x)^2)          (Walter et al. eq. 33)
//! Beckmann  D = exp(-x) / (pi alpha_u alpha_v cos^4)              (Walter et al. eq. 25)
//! ```
//!
//! The Student-t family ([`student_t_d`], Ribardiere et al. 2017, "STD: Student's
//! t-Distribution of Slopes for Microfacet Based BSDFs", Computer Graphics Forum 36(2))
//! joins them: its tail exponent `gamma` = 2 is GGX and `gamma -> infinity` Beckmann.

use glam::DVec3;
use std::f64::consts::PI;

/// `tan^2(theta_m) / alpha^2` of a unit normal `m` (`m.z > 0`) with roughness `alpha_u`
/// along x and `alpha_v` along y: the slope of `m` scaled by the roughness projected on its
/// azimuth.
pub fn scaled_tan2(m: DVec3, alpha_u: f64, alpha_v: f64) -> f64 {
    let (su, sv) = (m.x / alpha_u, m.y / alpha_v);
    (su * su + sv * sv) / (m.z * m.z)
}

/// The GGX (Trowbridge-Reitz) `D` in 1/sr from `scaled_tan2 = tan^2(theta_m) / alpha^2`
/// and `cos2 = cos^2(theta_m)` (Walter et al. 2007, eq. 33).
pub fn ggx_d(scaled_tan2: f64, cos2: f64, alpha_u: f64, alpha_v: f64) -> f64 {
    let norm = PI * alpha_u * alpha_v * cos2 * cos2;
    1.0 / (norm * (1.0 + scaled_tan2) * (1.0 + scaled_tan2))
}

/// The Beckmann `D` in 1/sr from `scaled_tan2 = tan^2(theta_m) / alpha^2` and
/// `cos2 = cos^2(theta_m)` (Walter et al. 2007, eq. 25).
pub fn beckmann_d(scaled_tan2: f64, cos2: f64, alpha_u: f64, alpha_v: f64) -> f64 {
    let norm = PI * alpha_u * alpha_v * cos2 * cos2;
    (-scaled_tan2).exp() / norm
}

/// The GGX `D` in 1/sr of a unit microfacet normal `m`; zero for normals facing below the
/// surface.
pub fn ggx_d_of_normal(m: DVec3, alpha_u: f64, alpha_v: f64) -> f64 {
    if m.z <= 0.0 {
        return 0.0;
    }
    ggx_d(
        scaled_tan2(m, alpha_u, alpha_v),
        m.z * m.z,
        alpha_u,
        alpha_v,
    )
}

/// The isotropic Student-t `D` in 1/sr from `tan^2(theta_m)` and `cos(theta_m)`, roughness
/// `alpha` and tail exponent `gamma > 1` (Ribardiere et al. 2017, eq. 9):
///
/// ```text
/// D = (1 + tan^2 / ((gamma - 1) alpha^2))^-gamma / (pi alpha^2 cos^4)
/// ```
///
/// normalised in projected area for every `gamma > 1`; `gamma = 2` is [`ggx_d`], and
/// `gamma -> infinity` tends to [`beckmann_d`].
pub fn student_t_d(tan2: f64, cos: f64, alpha: f64, gamma: f64) -> f64 {
    let a2 = alpha * alpha;
    let x = tan2 / ((gamma - 1.0) * a2);
    let c2 = cos * cos;
    (-gamma * x.ln_1p()).exp() / (PI * a2 * c2 * c2)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `int D(m) cos(theta_m) dm` over the hemisphere for an isotropic `D(theta_m)`, by the
    /// midpoint rule in `u = tan(theta_m)` mapped to `[0, 1)` (`t = u / (1 - u)`), which
    /// resolves narrow peaks and long tails alike: `dm = 2 pi sin dtheta` and
    /// `dtheta = dt / (1 + t^2)`.
    fn projected_area(d: impl Fn(f64, f64) -> f64) -> f64 {
        let n = 200_000;
        (0..n)
            .map(|i| {
                let u = (i as f64 + 0.5) / n as f64;
                let t = u / (1.0 - u);
                let dt = 1.0 / ((1.0 - u) * (1.0 - u)) / n as f64;
                let cos = 1.0 / (1.0 + t * t).sqrt();
                let sin = t * cos;
                d(t * t, cos) * cos * 2.0 * PI * sin * dt / (1.0 + t * t)
            })
            .sum()
    }

    #[test]
    fn every_distribution_is_normalised_in_projected_area() {
        for alpha in [0.01, 0.1, 0.5, 1.0] {
            let ggx = projected_area(|t2, c| ggx_d(t2 / (alpha * alpha), c * c, alpha, alpha));
            let beckmann =
                projected_area(|t2, c| beckmann_d(t2 / (alpha * alpha), c * c, alpha, alpha));
            assert!((ggx - 1.0).abs() < 1e-3, "GGX alpha {alpha}: {ggx}");
            assert!(
                (beckmann - 1.0).abs() < 1e-6,
                "Beckmann alpha {alpha}: {beckmann}"
            );
            for gamma in [1.5, 2.0, 4.0, 30.0] {
                let t = projected_area(|t2, c| student_t_d(t2, c, alpha, gamma));
                assert!(
                    (t - 1.0).abs() < 2e-3,
                    "Student-t alpha {alpha} gamma {gamma}: {t}"
                );
            }
        }
    }

    #[test]
    fn student_t_is_ggx_at_gamma_two_and_tends_to_beckmann() {
        let alpha = 0.2_f64;
        for theta_deg in [0.0, 3.0, 10.0, 25.0, 50.0] {
            let (s, c) = f64::to_radians(theta_deg).sin_cos();
            let tan2 = (s / c) * (s / c);
            let ggx = ggx_d(tan2 / (alpha * alpha), c * c, alpha, alpha);
            let beckmann = beckmann_d(tan2 / (alpha * alpha), c * c, alpha, alpha);
            let t2 = student_t_d(tan2, c, alpha, 2.0);
            // (1 + x / (gamma - 1))^-gamma = exp(-x) (1 + O(x^2 / (2 gamma))).
            let t_large = student_t_d(tan2, c, alpha, 1e9);
            assert!((t2 / ggx - 1.0).abs() < 1e-12, "{theta_deg}: {t2} vs {ggx}");
            assert!((t_large / beckmann - 1.0).abs() < 1e-5, "{theta_deg}");
        }
    }

    #[test]
    fn anisotropic_ggx_is_normalised_and_the_normal_form_agrees() {
        // Midpoint rule over the hemisphere in (theta, phi) for alpha_u 0.3, alpha_v 0.1.
        let (au, av) = (0.3, 0.1);
        let (nt, np) = (4000, 400);
        let mut total = 0.0;
        for i in 0..nt {
            let u = (i as f64 + 0.5) / nt as f64;
            let t = u / (1.0 - u);
            let dt = 1.0 / ((1.0 - u) * (1.0 - u)) / nt as f64;
            let theta = t.atan();
            for j in 0..np {
                let phi = (j as f64 + 0.5) / np as f64 * 2.0 * PI;
                let m = DVec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                );
                let d = ggx_d_of_normal(m, au, av);
                total += d * m.z * theta.sin() * dt / (1.0 + t * t) * 2.0 * PI / np as f64;
            }
        }
        assert!((total - 1.0).abs() < 2e-3, "{total}");
        assert_eq!(ggx_d_of_normal(DVec3::new(0.0, 0.6, -0.8), au, av), 0.0);
        assert!((ggx_d_of_normal(DVec3::Z, au, av) - 1.0 / (PI * au * av)).abs() < 1e-12);
    }
}
