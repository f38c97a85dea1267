//! The data-driven prior the front ends reconstruct with ([`merl_prior`]): the
//! principal-component basis (`specula_reconstruct::prior`) of the 100 MERL materials as
//! fitted by three published models (neural `nbrdf:`, Bagher 2012 `sgd:`, Löw 2012 `abc:`),
//! each channel one training vector. No RGL material is in it, so the RGL files and their
//! `nbrdf-rgl:` fits are test data. The training set is loaded through `specula-formats`;
//! the reconstruction takes the basis as a value and reads no training data itself.

use specula_core::Brdf;
use specula_formats::fits::{load_model, FitModel};
use specula_formats::input::FormatError;
use specula_formats::nbrdf::NbrdfSet;
use specula_reconstruct::prior::PriorError;
use specula_reconstruct::{Method, PriorBasis};
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
/// process: the one cache of it.
pub fn merl_prior() -> Result<Arc<PriorBasis>, MerlPriorError> {
    static MERL: OnceLock<Arc<PriorBasis>> = OnceLock::new();
    if let Some(basis) = MERL.get() {
        return Ok(basis.clone());
    }
    let training = merl_training_set()?;
    let basis = Arc::new(PriorBasis::derive(&training, MERL_COMPONENTS)?);
    Ok(MERL.get_or_init(|| basis).clone())
}

/// The basis `method` blends in: the MERL-100 prior ([`merl_prior`]) for `Method::Prior`,
/// none for the methods without a prior (which then cost nothing to derive).
pub fn basis_for(method: Method) -> Result<Option<Arc<PriorBasis>>, MerlPriorError> {
    method.uses_prior().then(merl_prior).transpose()
}

/// The training materials of [`merl_prior`]: MERL-100 as fitted by NBRDF, SGD and ABC.
fn merl_training_set() -> Result<Vec<Arc<dyn Brdf>>, FormatError> {
    let mut out: Vec<Arc<dyn Brdf>> = NbrdfSet::Merl100.load_all()?;
    out.extend(load_model(FitModel::Sgd)?);
    out.extend(load_model(FitModel::Abc)?);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_prior_method_has_a_basis() {
        for method in Method::ALL {
            let basis = basis_for(method).unwrap();
            assert_eq!(basis.is_some(), method.uses_prior(), "{method}");
        }
        let basis = merl_prior().unwrap();
        assert_eq!(basis.components.len(), MERL_COMPONENTS);
        // Three models of the 100 materials, three channels each.
        assert_eq!(basis.training_vectors, 3 * 100 * 3);
        assert!(Arc::ptr_eq(&basis, &merl_prior().unwrap()), "derived once");
    }
}
