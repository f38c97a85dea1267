//! `specula fit-k`: k-hat of a theta_h sampling function fitted to a probe (paper 5.2).

use anyhow::{bail, Result};
use specula_core::sampling::Family;
use specula_core::GridSpec;
use specula_formats::convert::FileFormat;
use specula_sampling::fit::fit_k;
use specula_sampling::probe::Probe;
use std::path::PathBuf;

/// Fit k of a theta_h sampling function to a probe (paper 5.2).
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The probe: a CSV file with the header theta_h,r,g,b (from `specula probe` or a device).
    pub probe: PathBuf,
    /// Sampling function family: exponential (paper eq. 3, the paper's choice), power (eq. 2,
    /// k = 2 is MERL's square root) or base (eq. 4).
    #[arg(long, default_value = "exponential")]
    pub family: Family,
    /// Number of theta_h samples the measurement will take: the paper's 30 by default; give 16 for
    /// the recommended grid of `plan` and `measure`. Range: a whole number from 2 to 360.
    #[arg(long, default_value_t = GridSpec::paper().theta_h_samples, value_parser = crate::range::THETA_H_SAMPLES)]
    pub theta_h_samples: usize,
}

pub(crate) fn run(args: Args) -> Result<()> {
    if let Some(format) = FileFormat::detect(&args.probe)? {
        if format != FileFormat::SamplesCsv {
            bail!(
                "{}: fit-k wants a probe CSV (header theta_h,r,g,b, from `specula probe`), not a {} file; `specula probe {}` takes the probe of a BRDF",
                args.probe.display(),
                format.label(),
                args.probe.display()
            );
        }
    }
    let probe = Probe::read_csv(&args.probe)?;
    let fit = fit_k(&probe.column(), args.family, args.theta_h_samples)?;
    outln!(
        "k={} error={}",
        crate::output::plain(fit.function.k),
        crate::output::plain(fit.error)
    );
    outln!(
        "family={} samples={} probe_samples={} evaluations={}",
        args.family,
        args.theta_h_samples,
        probe.len(),
        fit.evaluations
    );
    let positions: Vec<String> = fit
        .function
        .positions_deg(args.theta_h_samples)
        .iter()
        .map(|x| format!("{x:.6}"))
        .collect();
    outln!("theta_h_deg={}", positions.join(","));
    Ok(())
}
