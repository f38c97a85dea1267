//! Exact unpolarised Fresnel reflectance of a conductor and of a dielectric interface.
//!
//! Both come from the complex Fresnel amplitudes (Born & Wolf, *Principles of Optics*,
//! section 1.5): with the relative index `n = eta + i k` of the second medium and the incident
//! angle `theta_i`, write `n cos_t = sqrt(n^2 - sin^2 theta_i)` (principal branch). Then
//! `r_s = (cos_i - n cos_t) / (cos_i + n cos_t)`, `r_p = (n^2 cos_i - n cos_t) / (n^2 cos_i + n cos_t)`
//! and the reflectance of unpolarised light is `(|r_s|^2 + |r_p|^2) / 2`. Total internal
//! reflection (a real `n < 1` beyond the critical angle) comes out as 1 without a special case.

use crate::brdf::Rgb;
use num_complex::Complex64;

/// Unpolarised reflectance of a conductor with complex relative index `eta + i k` for light
/// arriving at `cos_theta_i` (cosine of the angle to the surface or microfacet normal, in
/// `[0, 1]`). Dimensionless, in `[0, 1]`.
pub fn conductor(cos_theta_i: f64, eta: f64, k: f64) -> f64 {
    let cos_i = cos_theta_i.clamp(0.0, 1.0);
    let sin2_i = 1.0 - cos_i * cos_i;
    let n = Complex64::new(eta, k);
    let n2 = n * n;
    let n_cos_t = principal_sqrt(n2 - sin2_i);
    // |r|^2 = |numerator|^2 / |denominator|^2, without a complex division.
    let r_s2 = (cos_i - n_cos_t).norm_sqr() / (cos_i + n_cos_t).norm_sqr();
    let r_p2 = (n2 * cos_i - n_cos_t).norm_sqr() / (n2 * cos_i + n_cos_t).norm_sqr();
    0.5 * (r_s2 + r_p2)
}

/// The principal square root by the algebraic formula
/// `sqrt(a + ib) = sqrt((|z| + a)/2) + i sign(b) sqrt((|z| - a)/2)`: three real square roots
/// where the polar form (`Complex64::sqrt`) needs atan2, sin and cos (the dominant cost of
/// tabulating a conductor).
fn principal_sqrt(z: Complex64) -> Complex64 {
    // norm_sqr().sqrt() rather than norm(): hypot's overflow care is not needed here and costs.
    let modulus = z.norm_sqr().sqrt();
    let re = (0.5 * (modulus + z.re)).max(0.0).sqrt();
    let im = (0.5 * (modulus - z.re)).max(0.0).sqrt();
    Complex64::new(re, im.copysign(z.im))
}

/// [`conductor`] per RGB channel, with `eta` and `k` given per channel.
pub fn conductor_rgb(cos_theta_i: f64, eta: Rgb, k: Rgb) -> Rgb {
    Rgb::new(
        conductor(cos_theta_i, eta.x, k.x),
        conductor(cos_theta_i, eta.y, k.y),
        conductor(cos_theta_i, eta.z, k.z),
    )
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
    fn principal_sqrt_agrees_with_the_polar_form() {
        for (re, im) in [
            (3.0, 4.0),
            (-2.0, 0.5),
            (-2.0, -0.5),
            (0.3, -7.0),
            (-1.0, 0.0),
            (4.0, 0.0),
        ] {
            let z = Complex64::new(re, im);
            let (a, b) = (principal_sqrt(z), z.sqrt());
            assert!(
                (a - b).norm() < 1e-14 * b.norm().max(1.0),
                "{z}: {a} vs {b}"
            );
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
