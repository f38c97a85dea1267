//! The options of a measurement grid (paper 5.3 and issue 20): a preset, theta_h from a
//! sampling function, theta_d in steps (finer towards grazing), phi_d in steps over the
//! quarter or the half turn, at one phi_h. Shared by `plan`, `measure` and `evaluate`.

use crate::range;
use specula_core::grid::{GridOverrides, GridSpec, PhiDSpan, ThetaDSteps};
use specula_core::request::{GridPreset, GridRequest};
use specula_core::sampling::Family;

#[derive(clap::Args, Clone, Debug)]
pub(crate) struct GridArgs {
    /// The grid the other grid options start from: `recommended` (default) or `paper`.
    #[arg(long)]
    pub grid_preset: Option<GridPreset>,
    /// Sampling function family: exponential, power or base (paper eq. 2 to 4).
    #[arg(long, default_value = "exponential")]
    pub family: Family,
    /// Number of theta_h positions; default: the preset's. Range: a whole number from 2 to 360.
    #[arg(long, value_parser = range::THETA_H_SAMPLES)]
    pub theta_h_samples: Option<usize>,
    /// theta_d positions: STEP or STEP:GRAZING@FROM in degrees, e.g. 3:1@60.
    #[arg(long, value_parser = range::ThetaDStepsArg)]
    pub theta_d_step: Option<ThetaDSteps>,
    /// Step of phi_d; default: the preset's. Range: degrees from 0.5 to 90.
    #[arg(long, value_parser = range::GRID_STEP_DEG)]
    pub phi_d_step: Option<f64>,
    /// How far phi_d goes: `quarter` (0 to 90 deg) or `half-turn` (0 to 180 deg).
    #[arg(long)]
    pub phi_d_span: Option<PhiDSpan>,
    /// The sample's orientation phi_h. Range: degrees from -360 to 360.
    #[arg(long, default_value_t = GridSpec::recommended().phi_h_deg, allow_negative_numbers = true, value_parser = range::AZIMUTH_DEG)]
    pub phi_h: f64,
}

impl GridArgs {
    /// The grid request the options describe: each option given replaces the value it
    /// names in --grid-preset's grid (or the resumed session's, or the recommended one).
    pub(crate) fn request(&self) -> GridRequest {
        GridRequest {
            preset: self.grid_preset,
            overrides: GridOverrides {
                theta_h_samples: self.theta_h_samples,
                theta_d: self.theta_d_step,
                phi_d_step_deg: self.phi_d_step,
                phi_d_span: self.phi_d_span,
                phi_h_deg: Some(self.phi_h),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        grid: GridArgs,
    }

    #[test]
    fn bad_theta_d_steps_are_one_line_usage_errors() {
        for bad in ["0", "3:1", "3:0.1@60", "3:1@90", "x@y", "nan"] {
            let err = Cli::try_parse_from(["test", "--theta-d-step", bad])
                .err()
                .unwrap_or_else(|| panic!("{bad} was accepted"))
                .to_string();
            assert!(
                err.starts_with(&format!(
                    "error: --theta-d-step {bad}: expected degrees from 0.5 to 90, or"
                )),
                "{err}"
            );
            assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        }
    }
}
