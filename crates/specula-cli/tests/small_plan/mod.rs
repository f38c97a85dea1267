//! The small plan the command-line tests measure: the paper's grid shape cut down to 30
//! probe samples and 8 theta_h x 6 theta_d x 4 phi_d positions (0 to 90 deg), seed 3, no
//! checks: a few seconds on the simulated device.

use std::path::Path;

/// `measure`'s options for the small plan.
pub(crate) const SMALL_PLAN: [&str; 13] = [
    "--skip-checks",
    "--grid-preset",
    "paper",
    "--probe-samples",
    "30",
    "--theta-h-samples",
    "8",
    "--theta-d-step",
    "15",
    "--phi-d-step",
    "30",
    "--seed",
    "3",
];

/// `measure` with the small plan (its seed unless `extra` gives one) and `extra`, writing
/// `out`.
#[allow(dead_code)] // not every test crate that measures the small plan builds its arguments so
pub(crate) fn measure_args(out: &Path, extra: &[&str]) -> Vec<String> {
    let gives_seed = extra
        .iter()
        .any(|a| *a == "--seed" || a.starts_with("--seed="));
    // The plan's seed is its last option and value.
    let plan = if gives_seed {
        &SMALL_PLAN[..SMALL_PLAN.len() - 2]
    } else {
        &SMALL_PLAN[..]
    };
    let mut args: Vec<String> = std::iter::once("measure")
        .chain(plan.iter().copied())
        .chain(extra.iter().copied())
        .map(str::to_string)
        .collect();
    args.extend(["--out".to_string(), out.display().to_string()]);
    args
}
