//! Analytic reference materials: rough conductors (polished metals, chrome) and
//! clear-coated paints, with an optional anisotropic scratch lobe (paper section 4.3), their
//! TOML material files, the paper's presets and a built-in database.
//!
//! Every value is a BRDF in 1/sr per RGB channel (R ~ 650 nm, G ~ 550 nm, B ~ 450 nm).

pub mod clearcoat;
pub mod coat_albedo;
pub mod conductor;
pub mod database;
pub mod material;
pub mod material_file;
pub mod microfacet;
pub mod presets;
pub mod scratch;

pub use database::{builtin_database, preset};
pub use material::{Base, Material};
pub use material_file::MaterialError;
pub use microfacet::Distribution;
pub use presets::preset_names;
