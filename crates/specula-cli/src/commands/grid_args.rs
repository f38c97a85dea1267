//! The options of the paper's sparse measurement grid (section 5.3): theta_h from a sampling
//! function, theta_d and phi_d in even steps, at one phi_h. Shared by `plan`, `measure` and
//! `evaluate`.

use crate::range;
use anyhow::{bail, Result};
use specula_core::sampling::Family;
use specula_core::GridSpec;

/// The largest grid a plan may hold (the paper's: 6300 samples).
pub(crate) const MAX_GRID_SAMPLES: usize = 1_000_000;

#[derive(clap::Args, Clone, Debug)]
pub(crate) struct GridArgs {
    /// Sampling function family: exponential (paper eq. 3), power (eq. 2) or base (eq. 4).
    #[arg(long, default_value = "exponential")]
    pub family: Family,
    /// Number of theta_h positions of the sampling function (paper: 30). Range: a whole
    /// number from 2 to 360.
    #[arg(long, default_value_t = GridSpec::paper().theta_h_samples, value_parser = range::THETA_H_SAMPLES)]
    pub theta_h_samples: usize,
    /// Step of theta_d in degrees (0, step, ... below 90). Range: degrees from 0.5 to 90.
    #[arg(long, default_value_t = GridSpec::paper().theta_d_step_deg, value_parser = range::GRID_STEP_DEG)]
    pub theta_d_step: f64,
    /// Step of phi_d in degrees (0, step, ... up to 90). Range: degrees from 0.5 to 90.
    #[arg(long, default_value_t = GridSpec::paper().phi_d_step_deg, value_parser = range::GRID_STEP_DEG)]
    pub phi_d_step: f64,
    /// phi_h in degrees: the sample's orientation, chosen to avoid anisotropic scratches
    /// (paper 4.3). Range: degrees from -360 to 360.
    ///
    /// It only turns the turntable; reachability does not depend on it. `measure` takes the
    /// orientation check's recommendation instead when the check finds a scratch lobe here.
    #[arg(long, default_value_t = GridSpec::paper().phi_h_deg, allow_negative_numbers = true, value_parser = range::AZIMUTH_DEG)]
    pub phi_h: f64,
}

impl GridArgs {
    /// The grid the options describe.
    pub(crate) fn spec(&self) -> GridSpec {
        GridSpec {
            theta_h_samples: self.theta_h_samples,
            theta_d_step_deg: self.theta_d_step,
            phi_d_step_deg: self.phi_d_step,
            phi_h_deg: self.phi_h,
        }
    }

    /// Rejects a grid too large to plan: the ranges of the single options are checked as
    /// they are parsed ([`crate::range`]); their product is checked here.
    pub(crate) fn check(&self) -> Result<()> {
        let spec = self.spec();
        let [_, theta_d, phi_d] = spec.shape();
        let samples = spec.sample_count();
        if samples > MAX_GRID_SAMPLES {
            bail!(
                "--theta-h-samples {} x --theta-d-step {} x --phi-d-step {}: a grid of {samples} samples ({} x {theta_d} x {phi_d}); at most {MAX_GRID_SAMPLES}: take fewer theta_h samples or larger steps",
                self.theta_h_samples,
                self.theta_d_step,
                self.phi_d_step,
                self.theta_h_samples,
            );
        }
        Ok(())
    }
}
