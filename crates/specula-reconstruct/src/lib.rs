//! Reconstruction of sparse BRDF samples into the full MERL grid (paper 5.3's last step).
//! The accuracy harness that measures how good a plan and a method are against a known BRDF
//! is `specula-accuracy`.
//!
//! Pipeline ([`reconstruct::reconstruct`]): fold phi_d by reciprocity and the mirror symmetry
//! (`sample`), place the samples on their lattice (`lattice`) in the method's value domain
//! (`domain`, optionally relative to a fitted microfacet [`lobe`]), extrapolate the nodes
//! no sample reached (`extrapolate`), interpolate at the MERL bin centres (`grid` with a
//! `kernel`) and record each cell's [`provenance`].
//!
//! Of the Specula crates it depends on `specula-core` alone. The `prior` method's basis ([`PriorBasis`]) is
//! an input its caller derives from a training set (`specula_accuracy::merl_prior` for
//! MERL-100); a user's request is a [`ReconstructRequest`], served by [`run_reconstruct`].

mod axis;
pub mod breakdown;
pub mod consistency;
pub mod deblur;
mod denoise;
mod domain;
pub mod energy;
mod extrapolate;
mod grid;
mod kernel;
mod lattice;
pub mod lobe;
pub mod method;
pub mod phi_d_halves;
pub mod prior;
pub mod prior_reconstruct;
pub mod provenance;
pub mod reconstruct;
mod reconstruction;
mod request;
mod response_nodes;
pub mod safeguard;
mod sample;
pub mod uncertainty;

pub use deblur::{deblur_probe, DeblurredProbe};
pub use domain::Domain;
pub use kernel::Kernel;
pub use method::Method;
pub use prior::PriorBasis;
pub use reconstruct::{reconstruct, reconstruct_through};
pub use reconstruction::{ReconstructError, Reconstruction, ResidualModel};
pub use request::{run_reconstruct, ReconstructRequest, RunReconstructError};
