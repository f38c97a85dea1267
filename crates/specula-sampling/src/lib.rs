//! Adaptive theta_h sampling (paper sections 5.1 and 5.2) and placements that go beyond it.
//!
//! - [`probe`]: the dense theta_h column at theta_d = 40, phi_d = 90 degrees that a
//!   measurement starts with, and its CSV file; [`adaptive`]: the adaptive samples drawn
//!   against it (Fig. 13), read from a CSV file;
//! - [`fit`]: k-hat of a sampling function (paper eq. 2-4) fitted to a probe;
//! - [`slice`](mod@slice), [`merl_slice`]: the characteristic slice (phi_d = 90) of a BRDF
//!   or of a MERL file read in one pass;
//! - [`analysis`], [`database`]: the database analysis of section 5.1, in parallel;
//! - `placement`, [`placement_study`]: the optimal placement of n samples for a known
//!   column (the oracle), a practical placement from the probe alone, and their comparison
//!   with the paper's functions.
//!
//! All values are the mean of R, G and B in 1/sr ([`column::scalar_of`]); angles are degrees.

pub mod adaptive;
pub mod analysis;
pub mod column;
pub mod database;
pub mod error;
pub mod fit;
pub mod merl_slice;
mod placement;
pub mod placement_study;
pub mod probe;
mod probe_model;
pub mod slice;

pub use column::{Column, Interpolation};
pub use fit::{fit_k, KFit};
pub use placement::{optimal_placement, place_theta_h, Placement};
pub use probe::Probe;
pub use slice::CharacteristicSlice;
