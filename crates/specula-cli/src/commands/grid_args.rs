//! The options of the paper's sparse measurement grid (section 5.3): theta_h from a sampling
//! function, theta_d and phi_d in even steps, at one phi_h. Shared by `plan`, `measure` and
//! `evaluate`.

use anyhow::{bail, Result};
use specula_core::sampling::Family;

#[derive(clap::Args, Clone, Debug)]
pub struct GridArgs {
    /// Sampling function family: exponential (paper eq. 3), power (eq. 2) or base (eq. 4).
    #[arg(long, default_value = "exponential")]
    pub family: Family,
    /// Number of theta_h positions of the sampling function (paper: 30).
    #[arg(long, default_value_t = 30)]
    pub theta_h_samples: usize,
    /// Step of theta_d in degrees (0, step, ... below 90).
    #[arg(long, default_value_t = 3.0)]
    pub theta_d_step: f64,
    /// Step of phi_d in degrees (0, step, ... up to 90).
    #[arg(long, default_value_t = 15.0)]
    pub phi_d_step: f64,
    /// phi_h in degrees: the sample's orientation, chosen to avoid anisotropic scratches
    /// (paper 4.3). It only turns the turntable; reachability does not depend on it.
    /// `measure` takes the orientation check's recommendation instead when the check finds
    /// a scratch lobe here.
    #[arg(long, default_value_t = 45.0, allow_negative_numbers = true)]
    pub phi_h: f64,
}

impl GridArgs {
    /// Rejects what the parser lets through: fewer than 2 theta_h, a step outside
    /// (0, 90] degrees, a phi_h that is not a number.
    pub fn check(&self) -> Result<()> {
        if self.theta_h_samples < 2 {
            bail!("--theta-h-samples must be at least 2");
        }
        for (flag, step) in [
            ("--theta-d-step", self.theta_d_step),
            ("--phi-d-step", self.phi_d_step),
        ] {
            if !(step.is_finite() && step > 0.0 && step <= 90.0) {
                bail!("{flag} must be a number of degrees in (0, 90], got {step}");
            }
        }
        if !self.phi_h.is_finite() {
            bail!("--phi-h must be a number of degrees");
        }
        Ok(())
    }
}
