//! Materials shared by the material tests.

use specula_core::materials::clearcoat::ClearCoat;
use specula_core::materials::scratch::ScratchLobe;
use specula_core::materials::{builtin_database, Base, Distribution, Material};
use specula_core::Rgb;

/// The database plus a scratched paint (the database's only scratched material is a metal).
pub(crate) fn all_materials() -> Vec<Material> {
    let coat = ClearCoat::new(Distribution::Beckmann, 0.02, 1.5, Rgb::new(0.5, 0.1, 0.1));
    let scratch = ScratchLobe::new(Distribution::Beckmann, 0.1, 0.003, 0.3, -40.0);
    let scratched_paint =
        Material::new("scratched-paint", Base::ClearCoat(coat)).with_scratch(scratch);
    let mut materials = builtin_database();
    materials.push(scratched_paint);
    materials
}
