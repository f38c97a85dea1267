//! The scattering formulas every BRDF of the workspace is built from, each written once (as
//! pbrt-v4's `util/scattering.h` and Mitsuba 3's `render/microfacet.h` and `render/fresnel.h`
//! keep one implementation):
//!
//! - [`ndf`]: microfacet normal distributions `D(m)`: GGX / Trowbridge-Reitz, Beckmann and
//!   the Student-t family between them (Walter et al. 2007, "Microfacet Models for
//!   Refraction through Rough Surfaces", EGSR, eq. 33 and 25; Ribardiere et al. 2017);
//! - [`masking`]: Smith's monodirectional masking `G1` and its `Lambda` for GGX and Beckmann
//!   (Walter et al. 2007, eq. 34 and 27);
//! - [`fresnel`]: the exact Fresnel reflectance of conductors and dielectrics, and Schlick's
//!   weight `(1 - cos)^5`.
//!
//! The materials of [`crate::materials`], the published fits of `specula-formats`, the
//! renderer's proxy lobe in `specula-visual` and the reconstruction's lobe in
//! `specula-reconstruct` call these functions; none writes its own.

pub mod fresnel;
pub mod masking;
pub mod ndf;
