//! The options of a measurement grid (paper 5.3 and issue 20): a preset, theta_h from a
//! sampling function, theta_d in steps (finer towards grazing), phi_d in steps over the
//! quarter or the half turn, at one phi_h. Shared by `plan`, `measure` and `evaluate`.

use crate::range;
use anyhow::Result;
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
    /// The grid the options describe ([`GridRequest::grid`]): starting from --grid-preset
    /// when given, else from `resumed` (the grid of the session a `measure` resumes), else
    /// from the recommended grid; each option given replaces the value it names.
    pub(crate) fn grid(&self, resumed: Option<GridSpec>) -> Result<GridSpec> {
        let request = GridRequest {
            preset: self.grid_preset,
            overrides: GridOverrides {
                theta_h_samples: self.theta_h_samples,
                theta_d: self.theta_d_step,
                phi_d_step_deg: self.phi_d_step,
                phi_d_span: self.phi_d_span,
                phi_h_deg: Some(self.phi_h),
            },
        };
        Ok(request.grid(resumed)?)
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

    fn args(argv: &[&str]) -> GridArgs {
        let mut all = vec!["test"];
        all.extend(argv);
        Cli::try_parse_from(all).unwrap().grid
    }

    fn grid(argv: &[&str]) -> GridSpec {
        args(argv).grid(None).unwrap()
    }

    #[test]
    fn the_preset_is_the_recommended_grid_and_options_override_it() {
        assert_eq!(grid(&[]), GridSpec::recommended());
        assert_eq!(grid(&["--grid-preset", "paper"]), GridSpec::paper());
        let graded = grid(&["--grid-preset", "paper", "--theta-d-step", "3:1@60"]);
        assert_eq!(graded.theta_d, GridSpec::recommended().theta_d);
        assert_eq!(graded.phi_d_span, PhiDSpan::Quarter);
        assert_eq!(graded.theta_h_samples, 30);
        // An even step given replaces the preset's graded one entirely.
        let even = grid(&["--theta-d-step", "2", "--phi-d-span", "quarter"]);
        assert_eq!(even.theta_d, ThetaDSteps::even(2.0));
        assert_eq!(even.phi_d_deg().last(), Some(&90.0));
        assert_eq!(even.theta_h_samples, 16);
        assert_eq!(even.unresolved_peak, None);
        // phi_d and phi_h options keep the rule for an unresolved peak; theta_h's count and
        // theta_d's steps replace what it would change, so they drop it.
        let turned = grid(&["--phi-d-step", "45", "--phi-h", "30"]);
        assert_eq!(
            turned.unresolved_peak,
            GridSpec::recommended().unresolved_peak
        );
        assert_eq!(grid(&["--theta-h-samples", "20"]).unresolved_peak, None);
    }

    #[test]
    fn a_resumed_session_keeps_its_grid_unless_a_preset_is_given() {
        let old = GridSpec {
            theta_h_samples: 8,
            ..GridSpec::paper()
        };
        assert_eq!(args(&[]).grid(Some(old)).unwrap(), old);
        let stepped = args(&["--phi-d-step", "45"]).grid(Some(old)).unwrap();
        assert_eq!((stepped.phi_d_step_deg, stepped.theta_h_samples), (45.0, 8));
        let preset = args(&["--grid-preset", "recommended"]);
        assert_eq!(preset.grid(Some(old)).unwrap(), GridSpec::recommended());
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

    #[test]
    fn the_size_check_counts_the_graded_theta_d_and_the_half_turn() {
        let huge = args(&[
            "--theta-h-samples",
            "360",
            "--theta-d-step",
            "3:0.5@0",
            "--phi-d-step",
            "0.5",
        ]);
        // 360 x (0, 0.5, ..., 89.5) x (0, 0.5, ..., 180): more than a million.
        let err = huge.grid(None).unwrap_err().to_string();
        assert!(err.contains("(360 x 180 x 361)"), "{err}");
        assert!(err.contains("theta_d_step_deg 3:0.5@0"), "{err}");
        assert!(err.contains("over the half-turn"), "{err}");
        let quarter = args(&[
            "--theta-h-samples",
            "30",
            "--theta-d-step",
            "3:0.5@0",
            "--phi-d-step",
            "0.5",
            "--phi-d-span",
            "quarter",
        ]);
        assert!(quarter.grid(None).is_ok());
    }
}
