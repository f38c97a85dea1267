//! Exact unpolarised Fresnel reflectance of a conductor and of a dielectric interface.
//!
//! Both come from the complex Fresnel amplitudes (Born & Wolf, *Principles of Optics*,
//! section 1.5): with the relative index `n = eta + i k` of the second medium and the incident
//! angle `theta_i`, write `n cos_t = sqrt(n^2 - sin^2 theta_i)` (principal branch). Then
//! `r_s = (cos_i - n cos_t) / (cos_i + n cos_t)`, `r_p = (n^2 cos_i - n cos_t) / (n^2 cos_i + n cos_t)`
//! and the reflectance of unpolarised light is `(|r_s|^2 + |r_p|^2) / 2`. Total internal
//! reflection (a real `n < 1` beyond the critical angle) comes out as 1 without a special case.
//!
//! At normal incidence both reduce to `((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2)`
//! (`((n - 1) / (n + 1))^2` for a dielectric). [`schlick_weight`] is the `(1 - cos)^5` of
//! Schlick's approximation, which the published fits and the reconstruction's lobe use.

use crate::brdf::Rgb;

/// Unpolarised reflectance of a conductor with complex relative index `eta + i k` for light
/// arriving at `cos_theta_i` (cosine of the angle to the surface or microfacet normal, in
/// `[0, 1]`). Dimensionless, in `[0, 1]`.
///
/// Evaluated in real arithmetic (Moeller, *Optics*, 1988, as Mitsuba 3's `fresnel_conductor`;
/// cheaper than complex square roots): with `a^2 + b^2 = |n^2 - sin^2|` and
/// `a = Re sqrt(n^2 - sin^2)`,
/// `R_s = (a^2 + b^2 + cos^2 - 2 a cos) / (a^2 + b^2 + cos^2 + 2 a cos)` and
/// `R_p = R_s (t - 2 a cos sin^2) / (t + 2 a cos sin^2)`, `t = (a^2 + b^2) cos^2 + sin^4`;
/// their mean `(R_s + R_p) / 2 = R_s t / (t + 2 a cos sin^2)` takes one division (the
/// batched evaluations are bound by divisions and square roots).
/// The tests check it against the complex amplitudes of the module documentation.
pub fn conductor(cos_theta_i: f64, eta: f64, k: f64) -> f64 {
    let cos_i = cos_theta_i.clamp(0.0, 1.0);
    let cos2 = cos_i * cos_i;
    let sin2 = 1.0 - cos2;
    let temp = eta * eta - k * k - sin2;
    let a2_plus_b2 = (temp * temp + 4.0 * eta * eta * k * k).sqrt();
    let a = (0.5 * (a2_plus_b2 + temp)).max(0.0).sqrt();
    let term_1 = a2_plus_b2 + cos2;
    let term_2 = 2.0 * cos_i * a;
    let term_3 = a2_plus_b2 * cos2 + sin2 * sin2;
    let term_4 = term_2 * sin2;
    (term_1 - term_2) * term_3 / ((term_1 + term_2) * (term_3 + term_4))
}

/// [`conductor`] per RGB channel, with `eta` and `k` given per channel.
pub fn conductor_rgb(cos_theta_i: f64, eta: Rgb, k: Rgb) -> Rgb {
    Rgb::new(
        conductor(cos_theta_i, eta.x, k.x),
        conductor(cos_theta_i, eta.y, k.y),
        conductor(cos_theta_i, eta.z, k.z),
    )
}

/// The complex index `(eta, k)` of a conductor from its normal-incidence reflectance `r` in
/// `[0, 1)` and its edge tint `g` in `[0, 1]` (Gulbrandsen 2014, "Artist Friendly Metallic
/// Fresnel", JCGT 3(4), eq. 3-4):
/// `eta = g (1 - r) / (1 + r) + (1 - g) (1 + sqrt r) / (1 - sqrt r)`,
/// `k = sqrt((r (eta + 1)^2 - (eta - 1)^2) / (1 - r))`. [`conductor`] of the result at normal
/// incidence is `r`; `g` shapes the curve towards grazing. A well-conditioned
/// parameterisation for fitting, where `eta` and `k` themselves are nearly degenerate.
pub fn conductor_index_from_reflectivity(r: f64, g: f64) -> (f64, f64) {
    let sqrt_r = r.sqrt();
    let eta = g * (1.0 - r) / (1.0 + r) + (1.0 - g) * (1.0 + sqrt_r) / (1.0 - sqrt_r);
    let k_sq = (r * (eta + 1.0).powi(2) - (eta - 1.0).powi(2)) / (1.0 - r);
    (eta, k_sq.max(0.0).sqrt())
}

/// Unpolarised reflectance of a dielectric interface with real relative index `eta`
/// (transmitted over incident medium, e.g. 1.5 for air to lacquer, 1/1.5 from inside the
/// lacquer) at `cos_theta_i` in `[0, 1]`. Beyond the critical angle it is 1.
pub fn dielectric(cos_theta_i: f64, eta: f64) -> f64 {
    let cos_i = cos_theta_i.clamp(0.0, 1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let r_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let r_p = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (r_s * r_s + r_p * r_p)
}

/// Schlick's weight `(1 - cos theta)^5` (Schlick 1994, "An Inexpensive BRDF Model for
/// Physically-based Rendering", eq. 15): `F ~ F0 + (1 - F0) (1 - cos)^5`. Zero for
/// `cos_theta >= 1`.
pub fn schlick_weight(cos_theta: f64) -> f64 {
    (1.0 - cos_theta).max(0.0).powi(5)
}

/// Hemispherical (cosine-weighted) average of [`dielectric`]:
/// `F_dr = 2 int_0^1 F(mu) mu dmu`, the reflectance of the interface under uniform diffuse
/// light. Midpoint rule on 1024 nodes in `mu`: accurate to about
/// 1e-7 for `eta > 1`; from inside (`eta < 1`) the square-root kink at the critical angle
/// limits it to about 1e-4.
pub fn dielectric_diffuse_reflectance(eta: f64) -> f64 {
    const NODES: usize = 1024;
    let sum: f64 = (0..NODES)
        .map(|i| {
            let mu = (i as f64 + 0.5) / NODES as f64;
            dielectric(mu, eta) * mu
        })
        .sum();
    2.0 * sum / NODES as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_complex::Complex64;

    #[test]
    fn reflectivity_parameters_give_their_normal_reflectance() {
        for r in [0.02, 0.3, 0.6, 0.95, 0.99] {
            for g in [0.0, 0.3, 0.7, 1.0] {
                let (eta, k) = conductor_index_from_reflectivity(r, g);
                assert!(
                    (conductor(1.0, eta, k) - r).abs() < 1e-9,
                    "{r} {g}: {eta} {k}"
                );
            }
        }
    }

    /// The reflectance from the complex Fresnel amplitudes (module documentation).
    fn conductor_by_amplitudes(cos_i: f64, eta: f64, k: f64) -> f64 {
        let n = Complex64::new(eta, k);
        let n2 = n * n;
        let n_cos_t = (n2 - (1.0 - cos_i * cos_i)).sqrt();
        let r_s = (cos_i - n_cos_t) / (cos_i + n_cos_t);
        let r_p = (n2 * cos_i - n_cos_t) / (n2 * cos_i + n_cos_t);
        0.5 * (r_s.norm_sqr() + r_p.norm_sqr())
    }

    #[test]
    fn real_form_equals_the_complex_amplitudes() {
        for (eta, k) in [
            (0.052, 4.409),
            (3.535, 4.348),
            (1.5, 0.0),
            (0.156, 3.602),
            (2.9, 0.3),
        ] {
            for i in 0..=100 {
                let cos_i = i as f64 / 100.0;
                let a = conductor(cos_i, eta, k);
                let b = conductor_by_amplitudes(cos_i, eta, k);
                assert!(
                    (a - b).abs() < 1e-13,
                    "eta {eta} k {k} cos {cos_i}: {a} vs {b}"
                );
            }
        }
    }

    #[test]
    fn normal_incidence_has_the_closed_form() {
        for (eta, k) in [(0.05, 4.4), (3.1, 3.3), (1.5, 0.0), (0.2, 3.6)] {
            let expected =
                ((eta - 1.0) * (eta - 1.0) + k * k) / ((eta + 1.0) * (eta + 1.0) + k * k);
            assert!((conductor(1.0, eta, k) - expected).abs() < 1e-14);
        }
        assert!((dielectric(1.0, 1.5) - 0.04).abs() < 1e-14);
    }

    #[test]
    fn a_dielectric_at_normal_incidence_reflects_the_squared_index_ratio() {
        for n in [1.0_f64, 1.33, 1.49, 1.5, 2.4, 1.0 / 1.5] {
            let expected = ((n - 1.0) / (n + 1.0)).powi(2);
            assert!((dielectric(1.0, n) - expected).abs() < 1e-15, "{n}");
        }
    }

    #[test]
    fn schlick_weight_runs_from_zero_to_one() {
        assert_eq!(schlick_weight(1.0), 0.0);
        assert_eq!(schlick_weight(0.0), 1.0);
        assert!((schlick_weight(0.5) - 1.0 / 32.0).abs() < 1e-15);
        // Schlick's approximation with the dielectric's own F0 is exact at normal and grazing
        // incidence and within 0.04 of the exact reflectance of glass (eta 1.5) at every
        // angle between (its largest error is 0.036).
        let f0 = dielectric(1.0, 1.5);
        for k in 0..=900 {
            let c = f64::to_radians(k as f64 / 10.0).cos();
            let schlick = f0 + (1.0 - f0) * schlick_weight(c);
            assert!((schlick - dielectric(c, 1.5)).abs() < 0.04, "{k}");
        }
    }

    #[test]
    fn grazing_incidence_reflects_everything() {
        assert!((conductor(0.0, 3.1, 3.3) - 1.0).abs() < 1e-12);
        assert!((dielectric(0.0, 1.5) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn dielectric_is_the_lossless_conductor() {
        for eta in [1.33, 1.5, 2.4, 1.0 / 1.5] {
            for i in 0..=50 {
                let cos_i = i as f64 / 50.0;
                let a = dielectric(cos_i, eta);
                let b = conductor(cos_i, eta, 0.0);
                assert!((a - b).abs() < 1e-12, "eta {eta} cos {cos_i}: {a} vs {b}");
            }
        }
    }

    #[test]
    fn brewster_angle_cancels_p_polarisation() {
        // At tan(theta_B) = eta, r_p = 0 and R = r_s^2 / 2 with r_s = (1 - eta^2)/(1 + eta^2).
        let eta = 1.5_f64;
        let cos_b = eta.atan().cos();
        let r_s = (1.0 - eta * eta) / (1.0 + eta * eta);
        assert!((dielectric(cos_b, eta) - 0.5 * r_s * r_s).abs() < 1e-14);
    }

    #[test]
    fn total_internal_reflection_beyond_the_critical_angle() {
        let eta = 1.0 / 1.5_f64;
        let cos_critical = (1.0 - eta * eta).sqrt();
        assert_eq!(dielectric(cos_critical * 0.99, eta), 1.0);
        assert!(dielectric(cos_critical * 1.01, eta) < 1.0);
    }

    #[test]
    fn diffuse_reflectances_inside_and_outside_are_related() {
        // Reciprocity: light entering and leaving the lacquer under diffuse illumination obeys
        // 1 - F_dr(1/eta) = (1 - F_dr(eta)) / eta^2 (radiance scales by eta^2 across the
        // interface, so the transmitted fractions are in that ratio). Both sides here
        // come from independent quadratures, one of them through total internal reflection.
        let eta = 1.5;
        let outside = dielectric_diffuse_reflectance(eta);
        let inside = dielectric_diffuse_reflectance(1.0 / eta);
        assert!(((1.0 - inside) - (1.0 - outside) / (eta * eta)).abs() < 1e-4);
        // The commonly quoted value for eta = 1.5 is F_dr = 0.0918.
        assert!((outside - 0.0918).abs() < 1e-4, "{outside}");
    }
}
