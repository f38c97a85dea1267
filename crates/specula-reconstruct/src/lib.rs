//! Reconstruction of sparse BRDF samples into the full MERL grid (paper 5.3's last step).
//! The accuracy harness that measures how good a plan and a method are against a known BRDF
//! is `specula-accuracy`.
//!
//! Pipeline ([`reconstruct::reconstruct`]): fold phi_d by reciprocity and the mirror symmetry
//! ([`sample`]), place the samples on their lattice ([`lattice`]) in the method's value domain
//! ([`domain`], optionally relative to a fitted microfacet [`lobe`]), extrapolate the nodes
//! no sample reached ([`extrapolate`]), interpolate at the MERL bin centres ([`grid`] with a
//! [`kernel`]) and record each cell's [`provenance`].

pub mod axis;
pub mod breakdown;
pub mod consistency;
pub mod deblur;
pub mod domain;
pub mod extrapolate;
pub mod grid;
pub mod kernel;
pub mod lattice;
pub mod lobe;
pub mod merl_prior;
pub mod method;
pub mod phi_d_halves;
pub mod prior;
pub mod prior_reconstruct;
pub mod provenance;
pub mod reconstruct;
pub mod reconstruction;
pub mod response_nodes;
pub mod safeguard;
pub mod sample;

pub use deblur::{deblur_probe, DeblurredProbe};
pub use method::Method;
pub use reconstruct::{reconstruct, reconstruct_through};
pub use reconstruction::{ReconstructError, Reconstruction};
