//! The data-driven prior of the accuracy study ([`merl_prior`]): the principal-component
//! basis (`specula_reconstruct::prior`) of the 100 MERL materials as fitted by three
//! published models (neural `nbrdf:`, Bagher 2012 `sgd:`, Löw 2012 `abc:`), each channel one
//! training vector. No RGL material is in it, so the RGL files and their `nbrdf-rgl:` fits
//! are test data. The training set comes from `specula-formats`, which the reconstruction
//! does not depend on.

use crate::prior::{PriorBasis, PriorError};
use specula_core::Brdf;
use specula_formats::fits::{load_model, FitModel};
use specula_formats::input::FormatError;
use specula_formats::nbrdf::NbrdfSet;
use std::sync::{Arc, OnceLock};

/// Why the MERL-100 prior could not be derived.
#[derive(Debug, thiserror::Error)]
pub enum MerlPriorError {
    /// A training material could not be loaded.
    #[error("the prior's training set: {0}")]
    Training(#[from] FormatError),
    /// The basis could not be derived from the training set.
    #[error(transparent)]
    Basis(#[from] PriorError),
}

/// Principal components kept by [`merl_prior`].
pub const MERL_COMPONENTS: usize = 24;

/// The basis of the MERL-100 fits (see the module documentation), derived once per
/// process.
pub fn merl_prior() -> Result<Arc<PriorBasis>, MerlPriorError> {
    static MERL: OnceLock<Arc<PriorBasis>> = OnceLock::new();
    if let Some(basis) = MERL.get() {
        return Ok(basis.clone());
    }
    let training = merl_training_set()?;
    let basis = Arc::new(PriorBasis::derive(&training, MERL_COMPONENTS)?);
    Ok(MERL.get_or_init(|| basis).clone())
}

/// The training materials of [`merl_prior`]: MERL-100 as fitted by NBRDF, SGD and ABC.
fn merl_training_set() -> Result<Vec<Arc<dyn Brdf>>, FormatError> {
    let mut out: Vec<Arc<dyn Brdf>> = NbrdfSet::Merl100.load_all()?;
    out.extend(load_model(FitModel::Sgd)?);
    out.extend(load_model(FitModel::Abc)?);
    Ok(out)
}
