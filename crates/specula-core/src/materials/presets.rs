//! The paper's materials and its comparison materials as analytic presets, the ground truth of
//! the simulated device.
//!
//! Optical constants are the literature values linearly interpolated at 650, 550 and 450 nm
//! (the R, G and B channels). Roughness is chosen to match the paper's observations
//! (section 5.3, Fig. 13-17): the polished silver 925 has a wider highlight than the paint and
//! an order of magnitude more dynamic range; electroplated chrome and steel (MERL's `chrome`,
//! `steel`) are sharper than the mechanically polished silver.

use super::clearcoat::ClearCoat;
use super::conductor::RoughConductor;
use super::material::{Base, Material};
use super::microfacet::Distribution;
use super::scratch::ScratchLobe;
use crate::brdf::Rgb;

/// Silver, Johnson & Christy 1972 (Phys. Rev. B 6, 4370), at 650/550/450 nm.
pub const SILVER_ETA: [f64; 3] = [0.052, 0.060, 0.040];
/// Silver extinction, Johnson & Christy 1972.
pub const SILVER_K: [f64; 3] = [4.409, 3.597, 2.648];
/// Chromium, Rakic et al. 1998 (Appl. Opt. 37, 5271), Lorentz-Drude fit, at 650/550/450 nm.
pub const CHROMIUM_ETA: [f64; 3] = [3.535, 2.901, 2.145];
/// Chromium extinction, Rakic et al. 1998.
pub const CHROMIUM_K: [f64; 3] = [4.348, 4.231, 3.862];
/// Iron (for steel), Johnson & Christy 1974 (Phys. Rev. B 9, 5056), at 650/550/450 nm.
pub const IRON_ETA: [f64; 3] = [2.911, 2.950, 2.584];
/// Iron extinction, Johnson & Christy 1974.
pub const IRON_K: [f64; 3] = [3.089, 2.932, 2.767];
/// Refractive index of an acrylic (PMMA) clear coat at 589 nm.
pub const ACRYLIC_IOR: f64 = 1.49;
/// Linear-RGB albedo of the green paint's pigmented base.
pub const GREEN_PAINT_BASE: [f64; 3] = [0.03, 0.25, 0.06];

/// The preset names, in the order docs/book/src/materials.md lists them.
pub fn preset_names() -> Vec<&'static str> {
    vec![
        "silver-925",
        "silver-925-scratched",
        "green-paint",
        "chrome",
        "steel",
    ]
}

/// One of the paper's presets ([`preset_names`]) by name; `None` for any other name
/// (`materials::preset` resolves the built-in database's names too).
pub fn paper_preset(name: &str) -> Option<Material> {
    match name {
        "silver-925" => Some(silver_925()),
        "silver-925-scratched" => Some(silver_925_scratched()),
        "green-paint" => Some(green_paint()),
        "chrome" => Some(chrome()),
        "steel" => Some(steel()),
        _ => None,
    }
}

/// All presets, in [`preset_names`] order.
pub fn all_presets() -> Vec<Material> {
    preset_names()
        .into_iter()
        .filter_map(paper_preset)
        .collect()
}

fn conductor(
    name: &str,
    distribution: Distribution,
    alpha: f64,
    eta: [f64; 3],
    k: [f64; 3],
) -> Material {
    let base = RoughConductor::new(distribution, alpha, Rgb::from(eta), Rgb::from(k));
    Material::new(name, Base::Conductor(base))
}

/// Cast sterling silver (92.5 % Ag), mechanically polished: pure-silver optical constants
/// (the 7.5 % copper changes them little in the visible) and a GGX lobe of alpha 0.04, wider
/// than the paint's.
fn silver_925() -> Material {
    conductor("silver-925", Distribution::Ggx, 0.04, SILVER_ETA, SILVER_K)
}

/// [`silver_925`] with the polishing scratches of paper Fig. 6 and 7-c: 3 % of the surface
/// scratched along 30 degrees, alpha 0.005 along and 0.15 across.
fn silver_925_scratched() -> Material {
    Material {
        name: "silver-925-scratched".into(),
        ..silver_925()
    }
    .with_scratch(ScratchLobe::polishing(30.0))
}

/// Green paint under a thick acrylic clear coat: a very sharp coat (GGX alpha 0.008).
fn green_paint() -> Material {
    let coat = ClearCoat::new(
        Distribution::Ggx,
        0.008,
        ACRYLIC_IOR,
        Rgb::from(GREEN_PAINT_BASE),
    );
    Material::new("green-paint", Base::ClearCoat(coat))
}

/// Electroplated (bright) chrome: Rakic's chromium, GGX alpha 0.01.
fn chrome() -> Material {
    conductor("chrome", Distribution::Ggx, 0.01, CHROMIUM_ETA, CHROMIUM_K)
}

/// Polished steel: iron's optical constants, GGX alpha 0.02.
fn steel() -> Material {
    conductor("steel", Distribution::Ggx, 0.02, IRON_ETA, IRON_K)
}
