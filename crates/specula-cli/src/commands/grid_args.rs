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
    /// The grid the other grid options start from: `recommended` (the default) or `paper`.
    ///
    /// recommended: 16 theta_h x theta_d every 3 deg, every 1 deg from 60 (3:1@60) x phi_d
    /// every 30 deg over the half turn 0 to 180, phi_h 45: at most about 3200 samples on the
    /// UTIA device. On the five real RGL measurements it gives 0.18 of the paper pipeline's
    /// relative RMSE and 0.26 of its log RMSE (median; README, "Real measured truths
    /// first"): the fine grazing theta_d catches the Fresnel rise near the peak, and the half
    /// turn measures each configuration's light/camera swap, which a real material need not
    /// match (the two halves are reconstructed apart). Where `measure` finds the material's
    /// peak narrower than the instrument resolves (the deblurred probe; 1.09 deg on the
    /// default device), it takes up to 30 theta_h with theta_d every 3 deg instead, as many
    /// as keep the plan within 4073 measured samples: through the light's disk the theta_h
    /// positions pin the peak (green paint 0.055 -> 0.021 relative RMSE).
    ///
    /// paper: the paper's plan (5.3), 30 theta_h x theta_d every 3 deg x phi_d every 15 deg
    /// over 0 to 90, phi_h 45: 6300 samples, 4073 measured on the paper's device.
    ///
    /// The options below replace the preset's values one by one. `measure` resuming a
    /// session starts from the session's own grid instead.
    #[arg(long)]
    pub grid_preset: Option<GridPreset>,
    /// Sampling function family: exponential (paper eq. 3), power (eq. 2) or base (eq. 4).
    #[arg(long, default_value = "exponential")]
    pub family: Family,
    /// Number of theta_h positions of the sampling function; default: the preset's
    /// (recommended 16, or more for a peak the instrument does not resolve; paper 30).
    /// Giving it (or --theta-d-step) fixes the grid for every material. Range: a whole
    /// number from 2 to 360.
    ///
    /// On the real RGL measurements the count matters little from 12 to 30 (README); 10 were
    /// too few for the broad lobe of colodur_napoli_4f (k-hat 0.5).
    #[arg(long, value_parser = range::THETA_H_SAMPLES)]
    pub theta_h_samples: Option<usize>,
    /// theta_d positions: STEP (0, STEP, 2 STEP, ... below 90 deg) or STEP:GRAZING@FROM
    /// (every STEP deg, then every GRAZING deg from the first position at or above FROM);
    /// default: the preset's (recommended 3:1@60, paper 3). Range: degrees from 0.5 to 90,
    /// or STEP:GRAZING@FROM with both steps from 0.5 to 90 and FROM from 0 to below 90.
    ///
    /// The theta_d step dominates the error on real materials: every 1 deg instead of 3
    /// takes the paper pipeline's error on cc_iris_purple_gem from 0.141 to 0.059, and most
    /// of the gain sits at grazing theta_d (3:1@60 puts 30 of its 50 positions from 60 deg).
    #[arg(long, value_parser = range::ThetaDStepsArg)]
    pub theta_d_step: Option<ThetaDSteps>,
    /// Step of phi_d in degrees (0, step, ... to the end of --phi-d-span); default: the
    /// preset's (recommended 30, paper 15). Range: degrees from 0.5 to 90.
    #[arg(long, value_parser = range::GRID_STEP_DEG)]
    pub phi_d_step: Option<f64>,
    /// How far phi_d goes: `quarter`, 0 to 90 deg (the paper's: reciprocity and isotropy
    /// give the rest), or `half-turn`, 0 to 180 deg (each configuration and its light/camera
    /// swap, reconstructed apart: real measured materials are not reciprocal near grazing,
    /// and the half of the table they differ in holds 67 to 99 % of the folded error on the
    /// RGL files); default: the preset's (recommended half-turn, paper quarter).
    #[arg(long)]
    pub phi_d_span: Option<PhiDSpan>,
    /// phi_h in degrees: the sample's orientation, chosen to avoid anisotropic scratches
    /// (paper 4.3). Range: degrees from -360 to 360.
    ///
    /// It only turns the turntable; reachability does not depend on it. `measure` takes the
    /// orientation check's recommendation instead when the check finds a scratch lobe here.
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
