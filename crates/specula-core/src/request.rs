//! What a user asks of a measurement grid and of the probe, as the front ends (the CLI's
//! options, the Python package's arguments) fill it in, with every range checked in one
//! place ([`GridRequest::validate`], [`ProbeRequest::validate`]): both front ends refuse
//! the same values with the same words. The errors name the Python argument
//! (`theta_h_samples`); the CLI's option parsers check the same ranges while the command line
//! is read and name the flag (`--theta-h-samples`).

use crate::grid::{GridOverrides, GridSpec, ThetaDSteps};
use crate::range::{CountRange, RangeError, RealRange};
use crate::sampling::{Family, InvalidK, SamplingFunction};
use crate::ProbeSpec;
use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// theta_h positions of a measurement's sampling function (the paper: 30; MERL has 90 bins).
pub const THETA_H_SAMPLES: CountRange = CountRange::from_to(2, 360);
/// Samples of a probe (the paper: 90).
pub const PROBE_SAMPLES: CountRange = CountRange::from_to(2, 10_000);
/// A sequential measurement's limit on the session's device time.
pub const MAX_HOURS: RealRange = RealRange::above(0.0, 1000.0, "hours");
/// A sequential measurement's limit on the main stage's samples.
pub const MAX_SAMPLES: CountRange = CountRange::from_to(10, 1_000_000);
/// A sequential measurement's target median relative uncertainty of the table.
pub const TARGET_UNCERTAINTY_PERCENT: RealRange = RealRange::above(0.0, 100.0, "percent");
/// A step of a grid in degrees (theta_d, phi_d).
pub const GRID_STEP_DEG: RealRange = RealRange::from_to(0.5, 90.0, "degrees");
/// Angles in degrees: a turntable or half-vector azimuth, either way round.
pub const AZIMUTH_DEG: RealRange = RealRange::from_to(-360.0, 360.0, "degrees");
/// The sample's tilt on the turntable (a misalignment to simulate).
pub const TILT_DEG: RealRange = RealRange::from_to(0.0, 10.0, "degrees");
/// phi_d of MERL's half-difference angles (folded by reciprocity to [0, 180]).
pub const PHI_D_DEG: RealRange = RealRange::from_to(0.0, 180.0, "degrees");
/// theta_d, from the half vector: below the horizon at 90.
pub const THETA_D_DEG: RealRange = RealRange::from_to(0.0, 89.5, "degrees");
/// A theta_h position.
pub const THETA_H_DEG: RealRange = RealRange::from_to(0.0, 90.0, "degrees");
/// An elevation from the normal that bounds the device's reach (the "within" figures).
pub const ELEVATION_DEG: RealRange = RealRange::above(0.0, 90.0, "degrees");
/// k of a theta_h sampling function (the family's own bound is checked as well: base-k
/// needs k above 1).
pub const SAMPLING_K: RealRange = RealRange::above(0.0, 100.0, "a number");
/// A scan step of phi_h.
pub const PHI_H_STEP_DEG: RealRange = RealRange::above(0.0, 45.0, "degrees");
/// An elevation of the light above the sample for the alignment check.
pub const LIGHT_ELEVATION_DEG: RealRange = RealRange::from_to(5.0, 75.0, "degrees");
/// A reflectance (a white reference).
pub const REFLECTANCE: RealRange = RealRange::above(0.0, 1.0, "a fraction");
/// Radiance factor of the simulated lens flare, 1/sr.
pub const FLARE_STRENGTH_SR: RealRange = RealRange::from_to(0.0, 10.0, "1/sr");
/// Seconds to wait (timeouts): up to a day.
pub const TIMEOUT_S: RealRange = RealRange::above(0.0, 86_400.0, "seconds");
/// How much faster than real time a rehearsal runs.
pub const SPEEDUP: RealRange = RealRange::above(0.0, 1e6, "a factor");
/// An instrument's angular resolution, e.g. the angular radius of its light source.
pub const RESOLUTION_DEG: RealRange = RealRange::above(0.0, 90.0, "degrees");
/// Exposure of a tone-mapped picture.
pub const EXPOSURE_STOPS: RealRange = RealRange::from_to(-20.0, 20.0, "stops");
/// Failures in a row on one request before giving up.
pub const FAILURES: CountRange = CountRange::from_to(1, 100);
/// Turntable rotations of the alignment check.
pub const ROTATIONS: CountRange = CountRange::from_to(3, 72);
/// The largest grid a plan may hold (the paper's: 6300 samples).
pub const MAX_GRID_SAMPLES: usize = 1_000_000;

/// theta_d's steps in words: both steps in [`GRID_STEP_DEG`], the threshold below 90 deg.
pub fn theta_d_steps_words() -> String {
    format!(
        "{}, or STEP:GRAZING@FROM with both steps from {} to {} and FROM from 0 to below 90",
        GRID_STEP_DEG.words(),
        GRID_STEP_DEG.min,
        GRID_STEP_DEG.max
    )
}

/// `steps` when both its steps lie in [`GRID_STEP_DEG`] and its threshold below 90 deg, else
/// the error naming `option`.
pub fn check_theta_d_steps(option: &str, steps: ThetaDSteps) -> Result<ThetaDSteps, RangeError> {
    let in_range = GRID_STEP_DEG.contains(steps.step_deg)
        && steps
            .grazing
            .is_none_or(|g| GRID_STEP_DEG.contains(g.step_deg))
        && steps.check().is_ok();
    if in_range {
        Ok(steps)
    } else {
        Err(RangeError {
            option: option.to_string(),
            value: steps.to_string(),
            expected: theta_d_steps_words(),
        })
    }
}

/// The `family` sampling function with `k`, when k lies in [`SAMPLING_K`] (named `k`) and in
/// the family's own domain (base-k needs k above 1).
pub fn sampling_function(family: Family, k: f64) -> Result<SamplingFunction, RequestError> {
    Ok(SamplingFunction::new(family, SAMPLING_K.check("k", k)?)?)
}

/// Refuses an output path whose extension is not `.binary`, for the commands that write a
/// MERL table (`specula convert` writes the other formats).
pub fn check_merl_out(path: &Path) -> Result<(), RequestError> {
    let is_merl = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("binary"));
    if is_merl {
        Ok(())
    } else {
        Err(RequestError::NotMerlOut(path.to_path_buf()))
    }
}

/// A name that is none of a choice's: `WHAT 'VALUE': expected one of NAMES`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{what} '{value}': expected one of {}", names.join(", "))]
pub struct ChoiceError {
    /// What is chosen: `grid preset`, `order`, `hdr`.
    pub what: &'static str,
    /// The name given.
    pub value: String,
    /// The names accepted.
    pub names: &'static [&'static str],
}

/// The choice among `all` whose name (`name_of`) is `text`, else the error listing them.
pub fn parse_choice<T: Copy>(
    what: &'static str,
    text: &str,
    all: &[T],
    names: &'static [&'static str],
    name_of: impl Fn(T) -> &'static str,
) -> Result<T, ChoiceError> {
    all.iter()
        .copied()
        .find(|&choice| name_of(choice) == text)
        .ok_or_else(|| ChoiceError {
            what,
            value: text.to_string(),
            names,
        })
}

/// Why a request is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RequestError {
    /// A value outside its range.
    #[error(transparent)]
    Range(#[from] RangeError),
    /// k outside its sampling function's domain.
    #[error(transparent)]
    InvalidK(#[from] InvalidK),
    /// A file a MERL table is written to whose extension is not `.binary`.
    #[error("{}: this command writes a MERL table, so --out must end in .binary (`specula convert` turns it into .bin or .csv)", .0.display())]
    NotMerlOut(PathBuf),
    /// The grid is too large to plan.
    #[error(
        "theta_h_samples {theta_h_samples} x theta_d_step_deg {theta_d} x phi_d_step_deg {phi_d_step_deg} over the {span}: a grid of {samples} samples ({theta_h_samples} x {theta_d_count} x {phi_d_count}); at most {MAX_GRID_SAMPLES}: take fewer theta_h samples or larger steps"
    )]
    TooLarge {
        /// theta_h positions.
        theta_h_samples: usize,
        /// theta_d's steps.
        theta_d: ThetaDSteps,
        /// phi_d's step, degrees.
        phi_d_step_deg: f64,
        /// phi_d's span in words.
        span: String,
        /// theta_d positions.
        theta_d_count: usize,
        /// phi_d positions.
        phi_d_count: usize,
        /// Configurations of the grid.
        samples: usize,
    },
}

/// A named grid ([`GridSpec::recommended`], [`GridSpec::paper`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GridPreset {
    /// [`GridSpec::recommended`], the default.
    Recommended,
    /// [`GridSpec::paper`], the paper's (5.3).
    Paper,
}

impl GridPreset {
    const ALL: [GridPreset; 2] = [GridPreset::Recommended, GridPreset::Paper];
    const NAMES: &'static [&'static str] = &["recommended", "paper"];

    /// The preset's name: `recommended` or `paper`.
    pub fn name(self) -> &'static str {
        match self {
            GridPreset::Recommended => "recommended",
            GridPreset::Paper => "paper",
        }
    }

    /// The preset's grid.
    pub fn spec(self) -> GridSpec {
        match self {
            GridPreset::Recommended => GridSpec::recommended(),
            GridPreset::Paper => GridSpec::paper(),
        }
    }
}

impl FromStr for GridPreset {
    type Err = ChoiceError;

    /// [`GridPreset::name`].
    fn from_str(text: &str) -> Result<Self, ChoiceError> {
        parse_choice("grid preset", text, &Self::ALL, Self::NAMES, Self::name)
    }
}

impl fmt::Display for GridPreset {
    /// [`GridPreset::name`].
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The grid a user asks for: a preset (or, left `None`, a resumed session's grid or the
/// recommended one) whose values the overrides replace one by one.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct GridRequest {
    /// The grid to start from.
    pub preset: Option<GridPreset>,
    /// Values that replace the preset's.
    pub overrides: GridOverrides,
}

impl GridRequest {
    /// Checks every value given against its range: theta_h samples [`THETA_H_SAMPLES`],
    /// theta_d's steps ([`check_theta_d_steps`]), phi_d's step [`GRID_STEP_DEG`], phi_h
    /// [`AZIMUTH_DEG`].
    pub fn validate(&self) -> Result<(), RequestError> {
        let o = &self.overrides;
        if let Some(n) = o.theta_h_samples {
            THETA_H_SAMPLES.check("theta_h_samples", n)?;
        }
        if let Some(steps) = o.theta_d {
            check_theta_d_steps("theta_d_step_deg", steps)?;
        }
        if let Some(step) = o.phi_d_step_deg {
            GRID_STEP_DEG.check("phi_d_step_deg", step)?;
        }
        if let Some(phi_h) = o.phi_h_deg {
            AZIMUTH_DEG.check("phi_h_deg", phi_h)?;
        }
        Ok(())
    }

    /// The grid asked for, validated: from the preset when given, else from `resumed` (the
    /// grid of the session a measurement resumes), else the recommended grid; each override
    /// replaces the value it names; at most [`MAX_GRID_SAMPLES`] configurations.
    pub fn grid(&self, resumed: Option<GridSpec>) -> Result<GridSpec, RequestError> {
        self.validate()?;
        let base = match (self.preset, resumed) {
            (Some(preset), _) => preset.spec(),
            (None, Some(grid)) => grid,
            (None, None) => GridSpec::recommended(),
        };
        let grid = base.with(&self.overrides);
        let samples = grid.configurations();
        if samples > MAX_GRID_SAMPLES {
            return Err(RequestError::TooLarge {
                theta_h_samples: grid.theta_h_samples,
                theta_d: grid.theta_d,
                phi_d_step_deg: grid.phi_d_step_deg,
                span: grid.phi_d_span.to_string(),
                theta_d_count: grid.theta_d_deg().len(),
                phi_d_count: grid.phi_d_deg().len(),
                samples,
            });
        }
        Ok(grid)
    }
}

/// The probe's samples and the simulated sample's tilt a measurement asks for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProbeRequest {
    /// Probe samples along theta_h ([`PROBE_SAMPLES`]).
    pub samples: usize,
    /// The simulated sample's tilt on the turntable, degrees ([`TILT_DEG`]).
    pub tilt_deg: f64,
    /// The azimuth of that tilt, degrees ([`AZIMUTH_DEG`]).
    pub tilt_azimuth_deg: f64,
}

impl ProbeRequest {
    /// Checks every value against its range.
    pub fn validate(&self) -> Result<(), RequestError> {
        PROBE_SAMPLES.check("probe_samples", self.samples)?;
        TILT_DEG.check("tilt_deg", self.tilt_deg)?;
        AZIMUTH_DEG.check("tilt_azimuth_deg", self.tilt_azimuth_deg)?;
        Ok(())
    }
}

impl ProbeSpec {
    /// Checks every value against its range, named as the Python arguments of `probe`:
    /// theta_d [`THETA_D_DEG`], phi_d [`PHI_D_DEG`], phi_h [`AZIMUTH_DEG`], the samples
    /// [`PROBE_SAMPLES`].
    pub fn validate(&self) -> Result<(), RequestError> {
        THETA_D_DEG.check("theta_d_deg", self.theta_d_deg)?;
        PHI_D_DEG.check("phi_d_deg", self.phi_d_deg)?;
        AZIMUTH_DEG.check("phi_h_deg", self.phi_h_deg)?;
        PROBE_SAMPLES.check("samples", self.samples)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::PhiDSpan;

    fn refused(request: GridRequest) -> String {
        request.grid(None).unwrap_err().to_string()
    }

    #[test]
    fn every_grid_range_is_checked_and_named() {
        let with = |overrides| GridRequest {
            preset: None,
            overrides,
        };
        assert_eq!(
            refused(with(GridOverrides {
                theta_h_samples: Some(1),
                ..GridOverrides::default()
            })),
            "theta_h_samples 1: expected a whole number from 2 to 360"
        );
        assert_eq!(
            refused(with(GridOverrides {
                phi_d_step_deg: Some(0.1),
                ..GridOverrides::default()
            })),
            "phi_d_step_deg 0.1: expected degrees from 0.5 to 90"
        );
        assert_eq!(
            refused(with(GridOverrides {
                phi_h_deg: Some(-400.0),
                ..GridOverrides::default()
            })),
            "phi_h_deg -400: expected degrees from -360 to 360"
        );
        let bad_steps = "3:0.1@60".parse::<ThetaDSteps>().unwrap();
        assert!(refused(with(GridOverrides {
            theta_d: Some(bad_steps),
            ..GridOverrides::default()
        }))
        .starts_with("theta_d_step_deg 3:0.1@60: expected degrees from 0.5 to 90, or"));
        // 360 x (0, 0.5, ..., 89.5) x (0, 0.5, ..., 180): more than a million.
        let huge = refused(with(GridOverrides {
            theta_h_samples: Some(360),
            theta_d: Some("3:0.5@0".parse().unwrap()),
            phi_d_step_deg: Some(0.5),
            ..GridOverrides::default()
        }));
        assert!(huge.contains("(360 x 180 x 361)"), "{huge}");
        assert!(huge.contains("over the half-turn"), "{huge}");
        let quarter = with(GridOverrides {
            theta_h_samples: Some(30),
            theta_d: Some("3:0.5@0".parse().unwrap()),
            phi_d_step_deg: Some(0.5),
            phi_d_span: Some(PhiDSpan::Quarter),
            ..GridOverrides::default()
        });
        assert!(quarter.grid(None).is_ok());
    }

    #[test]
    fn each_override_replaces_the_value_it_names() {
        let grid = |preset: Option<&str>, overrides: GridOverrides| {
            let preset = preset.map(|p| p.parse().unwrap());
            GridRequest { preset, overrides }.grid(None).unwrap()
        };
        let none = GridOverrides::default();
        let graded = grid(
            Some("paper"),
            GridOverrides {
                theta_d: Some("3:1@60".parse().unwrap()),
                ..none
            },
        );
        assert_eq!(graded.theta_d, GridSpec::recommended().theta_d);
        assert_eq!(graded.phi_d_span, PhiDSpan::Quarter);
        assert_eq!(graded.theta_h_samples, 30);
        // An even step given replaces the preset's graded one entirely.
        let even = grid(
            None,
            GridOverrides {
                theta_d: Some(ThetaDSteps::even(2.0)),
                phi_d_span: Some(PhiDSpan::Quarter),
                ..none
            },
        );
        assert_eq!(even.theta_d, ThetaDSteps::even(2.0));
        assert_eq!(even.phi_d_deg().last(), Some(&90.0));
        assert_eq!(even.theta_h_samples, 16);
        assert_eq!(even.unresolved_peak, None);
        // phi_d and phi_h keep the rule for an unresolved peak; theta_h's count and
        // theta_d's steps replace what it would change, so they drop it.
        let turned = grid(
            None,
            GridOverrides {
                phi_d_step_deg: Some(45.0),
                phi_h_deg: Some(30.0),
                ..none
            },
        );
        let rule = GridSpec::recommended().unresolved_peak;
        assert_eq!(turned.unresolved_peak, rule);
        let fewer = GridOverrides {
            theta_h_samples: Some(20),
            ..none
        };
        assert_eq!(grid(None, fewer).unresolved_peak, None);
    }

    #[test]
    fn the_preset_or_the_resumed_grid_is_the_base() {
        let paper = GridRequest {
            preset: Some("paper".parse().unwrap()),
            ..GridRequest::default()
        };
        assert_eq!(paper.grid(None), Ok(GridSpec::paper()));
        let resumed = GridSpec {
            theta_h_samples: 8,
            ..GridSpec::paper()
        };
        assert_eq!(GridRequest::default().grid(Some(resumed)), Ok(resumed));
        assert_eq!(
            GridRequest::default().grid(None),
            Ok(GridSpec::recommended())
        );
        assert_eq!(
            "fine".parse::<GridPreset>().unwrap_err().to_string(),
            "grid preset 'fine': expected one of recommended, paper"
        );
        assert_eq!(GridPreset::Paper.to_string(), "paper");
    }

    #[test]
    fn probe_and_tilt_ranges_are_checked() {
        let steep = ProbeSpec {
            theta_d_deg: 95.0,
            ..ProbeSpec::paper()
        };
        assert_eq!(
            steep.validate().unwrap_err().to_string(),
            "theta_d_deg 95: expected degrees from 0 to 89.5"
        );
        assert_eq!(ProbeSpec::paper().validate(), Ok(()));
        let ok = ProbeRequest {
            samples: 90,
            tilt_deg: 0.0,
            tilt_azimuth_deg: -30.0,
        };
        assert_eq!(ok.validate(), Ok(()));
        let many = ProbeRequest {
            samples: 20_000,
            ..ok
        };
        assert_eq!(
            many.validate().unwrap_err().to_string(),
            "probe_samples 20000: expected a whole number from 2 to 10000"
        );
        let tilted = ProbeRequest {
            tilt_deg: 20.0,
            ..ok
        };
        assert_eq!(
            tilted.validate().unwrap_err().to_string(),
            "tilt_deg 20: expected degrees from 0 to 10"
        );
    }
}
