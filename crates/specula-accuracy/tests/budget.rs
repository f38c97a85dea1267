//! The recommended grid ([`GridSpec::recommended`], the default of `plan`, `measure` and
//! `evaluate`) within the paper's sample budget: at most 4073 measured samples (the count the
//! paper's plan took on the UTIA device) on the default UTIA device model, whatever k the
//! fit of the sampling function to a probe produces and for every built-in material.

use specula_accuracy::{reached_by, GridPlan, Measurement, PlanSettings};
use specula_acquisition::device::Device;
use specula_core::materials::builtin_database;
use specula_core::sampling::{Family, SamplingFunction};
use specula_core::GridSpec;
use specula_sampling::fit::K_RANGE;

/// The paper's measured sample count (5.3).
const PAPER_BUDGET: usize = 4073;

#[test]
fn the_recommended_grid_stays_within_the_budget_for_every_k_the_fit_produces() {
    let device = Device::utia();
    let grid = GridSpec::recommended();
    let (low, high) = K_RANGE;
    let steps = 32;
    let mut counts = Vec::new();
    for i in 0..=steps {
        let k = low * (high / low).powf(f64::from(i) / f64::from(steps));
        let theta_h = SamplingFunction::new(Family::Exponential, k)
            .unwrap()
            .positions_deg(grid.theta_h_samples);
        let measured = reached_by(&GridPlan::on(theta_h, &grid), &device).len();
        assert!(measured <= PAPER_BUDGET, "k {k}: {measured} samples");
        counts.push(measured);
    }
    // The count grows with k (theta_h crowds towards 0, where more theta_d are reachable):
    // about 1600 at the smallest k, about 3600 at the largest.
    let most = counts.iter().copied().max().unwrap();
    assert!(most > 3 * PAPER_BUDGET / 4, "{counts:?}");
}

#[test]
fn the_recommended_plan_stays_within_the_budget_for_every_built_in_material() {
    let device = Device::utia();
    let settings = PlanSettings::recommended();
    let mut most = 0;
    for material in builtin_database() {
        let measured = Measurement::simulate(&material, &settings, &device)
            .unwrap()
            .samples
            .len();
        assert!(
            measured <= PAPER_BUDGET,
            "{}: {measured} samples",
            material.name
        );
        most = most.max(measured);
    }
    // The glossiest materials (k-hat near 6) take the most: about 3200 (docs/book/src/plan.md).
    assert!(most > 3 * PAPER_BUDGET / 4, "{most}");
}
