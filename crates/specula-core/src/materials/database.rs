//! The built-in database of specular and glossy materials: the presets, eleven metals in five
//! finishes (`{metal}-{finish}`) and eight clear-coated paints in three coat finishes
//! (`paint-{colour}-{finish}`). Used to test sampling and reconstruction across the range of
//! highlights a measurement meets, from mirror-like (alpha 0.003) to matte (alpha 0.3).
//!
//! Optical constants: literature values linearly interpolated at 650, 550 and 450 nm (R, G,
//! B). Johnson & Christy 1972 (Phys. Rev. B 6, 4370) for Ag, Au, Cu; Johnson & Christy 1974
//! (Phys. Rev. B 9, 5056) for Fe, Ni, Ti, Pd, Co; Rakic 1995 (Appl. Opt. 34, 4755) for Al;
//! Rakic et al. 1998 (Appl. Opt. 37, 5271, Lorentz-Drude fit) for Cr and Pt.

use super::clearcoat::ClearCoat;
use super::conductor::RoughConductor;
use super::material::{Base, Material};
use super::microfacet::Distribution;
use super::presets::{self, all_presets};
use crate::brdf::Rgb;
use std::sync::OnceLock;

/// A metal: name, `eta` and `k` at 650/550/450 nm.
struct Metal {
    name: &'static str,
    eta: [f64; 3],
    k: [f64; 3],
}

// Platinum's blue extinction, 3.140, is a measurement that happens to look like pi.
#[allow(clippy::approx_constant)]
const METALS: [Metal; 11] = [
    Metal {
        name: "silver",
        eta: presets::SILVER_ETA,
        k: presets::SILVER_K,
    },
    Metal {
        name: "aluminium",
        eta: [1.558, 1.015, 0.633],
        k: [7.712, 6.627, 5.454],
    },
    Metal {
        name: "gold",
        eta: [0.156, 0.424, 1.383],
        k: [3.602, 2.472, 1.915],
    },
    Metal {
        name: "copper",
        eta: [0.238, 1.007, 1.240],
        k: [3.626, 2.582, 2.393],
    },
    Metal {
        name: "chromium",
        eta: presets::CHROMIUM_ETA,
        k: presets::CHROMIUM_K,
    },
    Metal {
        name: "iron",
        eta: presets::IRON_ETA,
        k: presets::IRON_K,
    },
    Metal {
        name: "nickel",
        eta: [1.990, 1.921, 1.729],
        k: [4.209, 3.616, 2.944],
    },
    Metal {
        name: "titanium",
        eta: [2.741, 2.542, 2.267],
        k: [3.814, 3.435, 3.038],
    },
    Metal {
        name: "platinum",
        eta: [2.370, 2.091, 1.851],
        k: [4.254, 3.704, 3.140],
    },
    Metal {
        name: "palladium",
        eta: [1.789, 1.641, 1.408],
        k: [4.375, 3.845, 3.254],
    },
    Metal {
        name: "cobalt",
        eta: [2.237, 2.052, 1.736],
        k: [4.236, 3.824, 3.274],
    },
];

/// Metal finishes: name, distribution, alpha.
const METAL_FINISHES: [(&str, Distribution, f64); 5] = [
    ("mirror", Distribution::Ggx, 0.003),
    ("polished", Distribution::Ggx, 0.01),
    ("fine", Distribution::Beckmann, 0.03),
    ("satin", Distribution::Ggx, 0.1),
    ("matte", Distribution::Beckmann, 0.3),
];

/// Paint base colours: name, linear-RGB albedo.
const PAINT_COLOURS: [(&str, [f64; 3]); 8] = [
    ("red", [0.45, 0.03, 0.03]),
    ("green", presets::GREEN_PAINT_BASE),
    ("blue", [0.02, 0.06, 0.35]),
    ("yellow", [0.65, 0.45, 0.02]),
    ("orange", [0.60, 0.15, 0.02]),
    ("white", [0.80, 0.80, 0.78]),
    ("grey", [0.20, 0.20, 0.20]),
    ("black", [0.02, 0.02, 0.02]),
];

/// Clear-coat finishes: name, distribution, alpha.
const COAT_FINISHES: [(&str, Distribution, f64); 3] = [
    ("high-gloss", Distribution::Ggx, 0.005),
    ("gloss", Distribution::Ggx, 0.02),
    ("satin", Distribution::Beckmann, 0.08),
];

/// Index of a polyurethane or acrylic automotive clear coat.
const CLEAR_COAT_IOR: f64 = 1.5;

/// Every built-in material: the presets first, then the metals, then the paints.
pub fn builtin_database() -> Vec<Material> {
    database().to_vec()
}

/// A preset by name ([`presets::paper_preset`]); other names of the built-in database
/// resolve too. `None` for an unknown name.
pub fn preset(name: &str) -> Option<Material> {
    presets::paper_preset(name).or_else(|| find(name))
}

/// A material of the database by name.
pub fn find(name: &str) -> Option<Material> {
    database().iter().find(|m| m.name == name).cloned()
}

/// The database, built once (each paint tabulates its coat's albedo).
fn database() -> &'static [Material] {
    static DATABASE: OnceLock<Vec<Material>> = OnceLock::new();
    DATABASE.get_or_init(build)
}

fn build() -> Vec<Material> {
    let metals = METALS.iter().flat_map(|metal| {
        METAL_FINISHES
            .iter()
            .map(move |&(finish, distribution, alpha)| {
                let base =
                    RoughConductor::new(distribution, alpha, metal.eta.into(), metal.k.into());
                Material::new(format!("{}-{finish}", metal.name), Base::Conductor(base))
            })
    });
    let paints = PAINT_COLOURS.iter().flat_map(|&(colour, albedo)| {
        COAT_FINISHES
            .iter()
            .map(move |&(finish, distribution, alpha)| {
                let coat = ClearCoat::new(distribution, alpha, CLEAR_COAT_IOR, Rgb::from(albedo));
                Material::new(format!("paint-{colour}-{finish}"), Base::ClearCoat(coat))
            })
    });
    all_presets()
        .into_iter()
        .chain(metals)
        .chain(paints)
        .collect()
}
