//! Energy conservation of every built-in material and of worst-case clear coats: the
//! directional albedo `a(wi) = int f(wi, wo) cos(theta_o) dwo` must not exceed 1 at any
//! incident angle.
//!
//! The integral is taken by deterministic multiple importance sampling (Veach's balance
//! heuristic over stratified grids): one strategy per microfacet lobe (slopes drawn from the
//! lobe's own distribution, stretched by its roughness and turned into its frame) and one
//! cosine-weighted strategy for diffuse light. Each sample weighs `f cos_o / sum_k N_k p_k`.
//! The quadrature is checked first against albedos known independently.

use glam::DVec3;
use specula_core::geometry::{rotate_z, Spherical};
use specula_core::materials::clearcoat::{ClearCoat, MAX_BASE_ALBEDO};
use specula_core::materials::coat_albedo::CoatAlbedo;
use specula_core::materials::microfacet::Microfacet;
use specula_core::materials::{builtin_database, Base, Distribution, Material};
use specula_core::{Brdf, Rgb};
use std::f64::consts::PI;

/// Strata per axis for the database sweep (margins are wide there) and for the tight cases.
const COARSE: usize = 64;
const FINE: usize = 128;
const INCIDENT_DEG: [f64; 8] = [0.0, 20.0, 40.0, 60.0, 75.0, 82.0, 86.0, 89.0];

/// A microfacet lobe to sample: its distribution and the turn of its frame about the normal.
struct Lobe {
    microfacet: Microfacet,
    turn_rad: f64,
}

impl Lobe {
    /// The half vector at stratum `(u, v)`: a slope drawn from the unit-roughness
    /// distribution, stretched by `(alpha_u, alpha_v)`; its density is `D(h) cos theta_h`.
    fn half_vector(&self, u: f64, v: f64) -> DVec3 {
        let r = match self.microfacet.distribution {
            Distribution::Ggx => (u / (1.0 - u)).sqrt(),
            Distribution::Beckmann => (-(1.0 - u).ln()).sqrt(),
        };
        let (s, c) = (2.0 * PI * v).sin_cos();
        let slope = (
            self.microfacet.alpha_u * r * c,
            self.microfacet.alpha_v * r * s,
        );
        let h = DVec3::new(-slope.0, -slope.1, 1.0).normalize();
        rotate_z(h, self.turn_rad)
    }

    /// Density of `wo` under this strategy for incident `wi`.
    fn pdf(&self, wi: DVec3, wo: DVec3) -> f64 {
        let h = (wi + wo).normalize();
        let local = rotate_z(h, -self.turn_rad);
        self.microfacet.d(local) * local.z / (4.0 * wi.dot(h))
    }
}

fn lobes_of(material: &Material) -> Vec<Lobe> {
    let base = match &material.base {
        Base::Conductor(c) => Microfacet::isotropic(c.distribution(), c.alpha()),
        Base::ClearCoat(c) => Microfacet::isotropic(c.distribution(), c.alpha()),
    };
    let mut lobes = vec![Lobe {
        microfacet: base,
        turn_rad: 0.0,
    }];
    if let Some(s) = &material.scratch {
        lobes.push(Lobe {
            microfacet: Microfacet::anisotropic(
                s.distribution(),
                s.alpha_along(),
                s.alpha_across(),
            ),
            turn_rad: s.orientation_deg.to_radians(),
        });
    }
    lobes
}

/// Directional albedo per channel by the balance heuristic on `grid x grid` strata per
/// strategy.
fn albedo(material: &dyn Brdf, lobes: &[Lobe], wi: DVec3, grid: usize) -> Rgb {
    let n = (grid * grid) as f64;
    let pdf_sum = |wo: DVec3| {
        let cosine = wo.z / PI;
        n * (cosine + lobes.iter().map(|l| l.pdf(wi, wo)).sum::<f64>())
    };
    let contribution = |wo: DVec3| {
        if wo.z <= 0.0 {
            return Rgb::ZERO;
        }
        material.eval(wi, wo).expect("analytic") * wo.z / pdf_sum(wo)
    };
    let mut total = Rgb::ZERO;
    for i in 0..grid {
        for j in 0..grid {
            let (u, v) = (
                (i as f64 + 0.5) / grid as f64,
                (j as f64 + 0.5) / grid as f64,
            );
            for lobe in lobes {
                let h = lobe.half_vector(u, v);
                total += contribution(2.0 * wi.dot(h) * h - wi);
            }
            let (s, c) = (2.0 * PI * v).sin_cos();
            total += contribution(DVec3::new(u.sqrt() * c, u.sqrt() * s, (1.0 - u).sqrt()));
        }
    }
    total
}

fn incident(theta_deg: f64) -> DVec3 {
    Spherical::from_degrees(theta_deg, 20.0).to_vector()
}

/// The quadrature reproduces albedos computed independently: a black-based coat reflects
/// exactly its lobe, whose albedo `CoatAlbedo` tabulates by Gauss-Legendre in another
/// parameterisation.
#[test]
fn quadrature_reproduces_independent_albedos() {
    for (distribution, alpha) in [(Distribution::Ggx, 0.005), (Distribution::Beckmann, 0.3)] {
        let coat = ClearCoat::new(distribution, alpha, 1.5, Rgb::ZERO);
        let material = Material::new("black", Base::ClearCoat(coat));
        let lobes = lobes_of(&material);
        let table = CoatAlbedo::new(&Microfacet::isotropic(distribution, alpha), 1.5);
        for theta in [0.0, 40.0, 75.0, 86.0] {
            let wi = incident(theta);
            let a = albedo(&material, &lobes, wi, FINE).x;
            let expected = table.at(wi.z);
            assert!(
                (a - expected).abs() < 1e-3,
                "{distribution:?} {alpha} at {theta}: {a} vs {expected}"
            );
        }
    }
}

/// Every database material (including the scratched silver) keeps its albedo within 1.
#[test]
fn database_materials_conserve_energy() {
    for material in builtin_database() {
        let lobes = lobes_of(&material);
        for theta in INCIDENT_DEG {
            let a = albedo(&material, &lobes, incident(theta), COARSE);
            assert!(a.min_element() >= 0.0, "{} at {theta}: {a}", material.name);
            assert!(
                a.max_element() <= 1.0 + 1e-3,
                "{} at {theta}: albedo {a}",
                material.name
            );
        }
    }
}

/// The worst case of the coat model: the brightest base a material file accepts
/// (`MAX_BASE_ALBEDO`) under coats from mirror-like to very rough, at every angle up to
/// 89 degrees. Lobe plus base must stay within 1 (to the quadrature's 1e-3).
#[test]
fn brightest_base_clear_coats_conserve_energy() {
    for distribution in [Distribution::Ggx, Distribution::Beckmann] {
        for alpha in [0.003, 0.005, 0.08, 0.3, 1.0] {
            let coat = ClearCoat::new(distribution, alpha, 1.5, Rgb::splat(MAX_BASE_ALBEDO));
            let material = Material::new("white", Base::ClearCoat(coat));
            let lobes = lobes_of(&material);
            for theta in INCIDENT_DEG {
                let a = albedo(&material, &lobes, incident(theta), FINE).x;
                assert!(
                    a <= 1.0 + 1e-3,
                    "{distribution:?} {alpha} at {theta}: albedo {a}"
                );
                // A bright base returns most light: the quadrature sees the diffuse part too.
                assert!(a > 0.85, "{distribution:?} {alpha} at {theta}: albedo {a}");
            }
        }
    }
}
