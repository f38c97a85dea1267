//! Smith's monodirectional masking `G1`: the fraction of the microfacets facing `m` that a
//! direction `v` sees, in `[0, 1]`. With the distribution's `Lambda`,
//!
//! ```text
//! G1(v) = 1 / (1 + Lambda(a)),   a = 1 / (alpha tan theta_v)      (Walter et al. 2007, eq. 23)
//! ```
//!
//! with `alpha` the roughness projected on `v`'s azimuth. Each function takes
//! `alpha2_tan2 = alpha^2 tan^2(theta_v) = 1 / a^2`, zero at normal incidence (where
//! `G1 = 1`). The caller checks that `v` sees the front of the microfacet (`v . m` and
//! `v . n` of one sign).
//!
//! ```text
//! GGX       Lambda = (sqrt(1 + alpha^2 tan^2) - 1) / 2
//!           G1     = 2 / (1 + sqrt(1 + alpha^2 tan^2))                 (Walter et al. eq. 34)
//! Beckmann  Lambda ~ (1 - 1.259 a + 0.396 a^2) / (3.535 a + 2.181 a^2),   0 for a >= 1.6
//!           G1     ~ (3.535 a + 2.181 a^2) / (1 + 2.276 a + 2.577 a^2)  (Walter et al. eq. 27)
//! ```
//!
//! The Beckmann form is Walter et al.'s rational approximation of the exact
//! `erf` expression (within 0.35 %), as Mitsuba 3 and pbrt-v4 use.

use glam::DVec3;

/// GGX's `Lambda` from `alpha2_tan2 = alpha^2 tan^2(theta_v)`.
pub fn ggx_lambda(alpha2_tan2: f64) -> f64 {
    ((1.0 + alpha2_tan2).sqrt() - 1.0) / 2.0
}

/// GGX's Smith masking `G1 = 1 / (1 + Lambda)` from `alpha2_tan2 = alpha^2 tan^2(theta_v)`
/// (Walter et al. 2007, eq. 34).
pub fn ggx_g1(alpha2_tan2: f64) -> f64 {
    if alpha2_tan2 == 0.0 {
        return 1.0;
    }
    2.0 / (1.0 + (1.0 + alpha2_tan2).sqrt())
}

/// GGX's `G1` of a unit direction `v` (isotropic roughness `alpha`, `v.z` the cosine to the
/// macro normal); zero at or below the horizon.
pub fn ggx_g1_of_direction(v: DVec3, alpha: f64) -> f64 {
    if v.z <= 0.0 {
        return 0.0;
    }
    let cos2 = v.z * v.z;
    let tan2 = (1.0 - cos2).max(0.0) / cos2;
    ggx_g1(alpha * alpha * tan2)
}

/// GGX's `G1(theta) / cos(theta)` for `cos theta > 0` and isotropic roughness `alpha`:
/// [`ggx_g1`] divided by the cosine and written as
/// `2 / (cos + sqrt(cos^2 + alpha^2 (1 - cos^2)))`, which stays finite at grazing angles.
pub fn ggx_g1_over_cos(cos: f64, alpha: f64) -> f64 {
    let c2 = cos * cos;
    2.0 / (cos + (c2 + alpha * alpha * (1.0 - c2)).sqrt())
}

/// Beckmann's `Lambda` from `alpha2_tan2 = alpha^2 tan^2(theta_v)` (the rational
/// approximation of Walter et al. 2007 under eq. 27).
pub fn beckmann_lambda(alpha2_tan2: f64) -> f64 {
    if alpha2_tan2 == 0.0 {
        return 0.0;
    }
    let a = 1.0 / alpha2_tan2.sqrt();
    if a >= 1.6 {
        0.0
    } else {
        (1.0 - 1.259 * a + 0.396 * a * a) / (3.535 * a + 2.181 * a * a)
    }
}

/// Beckmann's Smith masking `G1` from `alpha2_tan2 = alpha^2 tan^2(theta_v)` (Walter et al.
/// 2007, eq. 27, the rational approximation).
pub fn beckmann_g1(alpha2_tan2: f64) -> f64 {
    if alpha2_tan2 == 0.0 {
        return 1.0;
    }
    let a = 1.0 / alpha2_tan2.sqrt();
    if a >= 1.6 {
        1.0
    } else {
        (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn masking_is_one_at_normal_incidence() {
        assert_eq!(ggx_g1(0.0), 1.0);
        assert_eq!(beckmann_g1(0.0), 1.0);
        assert_eq!(ggx_lambda(0.0), 0.0);
        assert_eq!(beckmann_lambda(0.0), 0.0);
        for alpha in [0.01, 0.3, 1.0] {
            assert_eq!(ggx_g1_of_direction(DVec3::Z, alpha), 1.0);
            assert!((ggx_g1_over_cos(1.0, alpha) - 1.0).abs() < 1e-15);
        }
    }

    #[test]
    fn g1_is_one_over_one_plus_lambda() {
        for k in 1..200 {
            let x = (k as f64 * 0.05).powi(3);
            let ggx = 1.0 / (1.0 + ggx_lambda(x));
            let beckmann = 1.0 / (1.0 + beckmann_lambda(x));
            assert!((ggx_g1(x) / ggx - 1.0).abs() < 1e-14, "GGX {x}");
            assert!(
                (beckmann_g1(x) / beckmann - 1.0).abs() < 1e-14,
                "Beckmann {x}"
            );
        }
    }

    #[test]
    fn masking_falls_from_one_to_zero_towards_grazing() {
        for g1 in [ggx_g1, beckmann_g1] {
            let values: Vec<f64> = (0..=89)
                .map(|t| {
                    let tan = f64::to_radians(t as f64).tan();
                    g1(0.25 * tan * tan)
                })
                .collect();
            // Walter's rational form reaches 1 + 5.7e-5 at a = 1.6, where it is clamped to 1.
            assert!(values.windows(2).all(|w| w[1] <= w[0] + 1e-4));
            assert!(values[89] < 0.2 && values[89] > 0.0, "{}", values[89]);
        }
    }

    #[test]
    fn the_cosine_forms_agree() {
        for alpha in [0.01, 0.3, 1.0] {
            for k in 1..90 {
                let (s, c) = f64::to_radians(k as f64).sin_cos();
                let v = DVec3::new(s, 0.0, c);
                let over = ggx_g1_over_cos(c, alpha);
                assert!((over * c / ggx_g1_of_direction(v, alpha) - 1.0).abs() < 1e-12);
            }
        }
    }
}
