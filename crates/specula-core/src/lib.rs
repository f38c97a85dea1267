//! Specula's core: the geometry of the half-difference parameterisation, the [`Brdf`]
//! abstraction, the MERL `.binary` table, reference materials, the theta_h sampling functions,
//! the measurement grid and probe specifications, the sample types and tabulation into the
//! MERL grid. Pure computation: no terminal, network or database.

pub mod atomic_file;
pub mod bounded_read;
pub mod brdf;
pub mod capture;
pub mod geometry;
pub mod grid;
pub mod merl;
mod probe;
pub mod progress;
pub mod range;
pub mod request;
mod sample;

pub use brdf::{Brdf, PhiDRow, Rgb};
pub use geometry::{HalfDiff, Spherical};
pub use grid::{GrazingStep, GridSpec, PhiDSpan, ThetaDSteps};
pub use merl::MerlBrdf;
pub use probe::ProbeSpec;
pub use sample::{ProbePoint, Sample};
pub mod compare;
pub mod materials;
pub mod sampling;
pub mod scattering;
pub mod shown;
pub mod statistics;
pub mod tabulate;
pub mod toml_error;
