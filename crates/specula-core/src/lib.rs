//! Specula's core: the geometry of the half-difference parameterisation, the [`Brdf`]
//! abstraction, the MERL `.binary` table, reference materials, the theta_h sampling functions
//! and tabulation into the MERL grid. Pure computation: no terminal, network or database.

pub mod atomic_file;
pub mod bounded_read;
pub mod brdf;
pub mod capture;
pub mod geometry;
pub mod merl;

pub use brdf::{Brdf, PhiDRow, Rgb};
pub use geometry::{HalfDiff, Spherical};
pub use merl::MerlBrdf;
pub mod compare;
pub mod materials;
pub mod sampling;
pub mod scattering;
pub mod shown;
pub mod tabulate;
