//! The uncertainty of a measured table ([`specula_reconstruct::uncertainty`]) from the
//! session's own samples: their HDR noise as the journal holds it.

use crate::journal::{PlannedRow, SampleRecord};
use specula_core::Sample;
use specula_reconstruct::uncertainty::{self, CellUncertainty, UncertaintyInputs};
use specula_reconstruct::{Method, PriorBasis, ReconstructError, Reconstruction};
use std::collections::BTreeMap;

/// The uncertainty of `result`, reconstructed with `method` from
/// `samples`, the main stage's `records` in the order of `plan` (as
/// [`crate::workflow::measured_samples`] makes them).
pub fn of_measurement(
    plan: &[PlannedRow],
    records: &BTreeMap<u32, SampleRecord>,
    samples: &[Sample],
    method: Method,
    prior: Option<&PriorBasis>,
    result: &Reconstruction,
) -> Result<CellUncertainty, ReconstructError> {
    let noise = noise_in_plan_order(plan, records);
    let inputs = UncertaintyInputs {
        samples,
        noise_rel: Some(&noise),
        method,
        prior,
    };
    uncertainty::estimate(&inputs, result)
}

/// Each main sample's relative HDR noise ([`uncertainty::noise_rel`]) of the session at
/// `path` (opened read-only), in the order of [`crate::workflow::session_main_samples`].
pub fn session_main_noise(
    path: &std::path::Path,
) -> Result<Vec<f64>, crate::workflow_error::WorkflowError> {
    let journal = crate::journal::Journal::open_read_only(path)?;
    let plan = journal.plan(crate::journal::Stage::Main)?;
    let records = journal.samples(crate::journal::Stage::Main)?;
    Ok(noise_in_plan_order(&plan, &records))
}

/// The relative noise of the `records` in the order of `plan`.
fn noise_in_plan_order(plan: &[PlannedRow], records: &BTreeMap<u32, SampleRecord>) -> Vec<f64> {
    plan.iter()
        .filter_map(|row| records.get(&row.seq))
        .map(|s| uncertainty::noise_rel(s.rate_dn_s, s.sigma_dn_s))
        .collect()
}
