//! The measurement grid of paper 5.3: theta_h positions from a sampling function (paper
//! eq. 2-4), theta_d and phi_d in steps, all at one phi_h. [`GridSpec`] holds the numbers
//! that choose a grid; the theta_h positions themselves come from the sampling function
//! fitted to the probe ([`crate::sampling`], [`crate::probe`]).
//!
//! Two shapes beyond the paper's even steps (issue 20, README "Real measured truths first"):
//! a finer theta_d step towards grazing ([`ThetaDSteps`] with a [`GrazingStep`]), where the
//! Fresnel rise and the foreshortening change fastest and where most of the error on real
//! measured materials sits, and phi_d over the half turn ([`PhiDSpan::HalfTurn`]), a
//! configuration and its light/camera swap, which the reconstruction keeps apart for
//! measured materials that are not reciprocal (`specula_reconstruct::phi_d_halves`).

use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// Angles closer than this (degrees) count as equal when positions are stepped.
const STEP_TOLERANCE_DEG: f64 = 1e-9;

/// The numbers of a measurement grid (paper 5.3); [`GridSpec::paper`] is the paper's,
/// [`GridSpec::recommended`] the default of the front ends (see [`Default`] below).
///
/// Serialized flat (the session journal keeps it so): `theta_h_samples`, `theta_d_step_deg`,
/// `theta_d_grazing`, `phi_d_step_deg`, `phi_d_span`, `phi_h_deg`. A record written before
/// the grazing step and the span existed reads as the paper's shape: no grazing step, phi_d
/// over the quarter.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GridSpec {
    /// Number of theta_h positions of the sampling function.
    pub theta_h_samples: usize,
    /// Where the theta_d positions go.
    #[serde(flatten)]
    pub theta_d: ThetaDSteps,
    /// Step of phi_d in degrees: 0, step, 2 step, ... over [`GridSpec::phi_d_span`].
    pub phi_d_step_deg: f64,
    /// How far phi_d goes: to 90 deg (the paper's; the rest follows by reciprocity and
    /// isotropy) or to 180 deg (both halves, a configuration and its light/camera swap).
    #[serde(default = "PhiDSpan::before_issue_20")]
    pub phi_d_span: PhiDSpan,
    /// phi_h in degrees: the sample's orientation on the turntable, chosen away from
    /// scratch directions (paper 4.3).
    pub phi_h_deg: f64,
    /// The grid a material gets when the instrument does not resolve its peak, if this grid
    /// changes then ([`UnresolvedPeak`]); `None` (and absent from records written before it
    /// existed): the grid is the same for every material.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unresolved_peak: Option<UnresolvedPeak>,
}

/// Values that replace a grid's own one by one ([`GridSpec::with`]; `None` keeps the
/// grid's): what the grid options of the front ends give.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct GridOverrides {
    /// Number of theta_h positions.
    pub theta_h_samples: Option<usize>,
    /// theta_d's positions.
    pub theta_d: Option<ThetaDSteps>,
    /// Step of phi_d, degrees.
    pub phi_d_step_deg: Option<f64>,
    /// How far phi_d goes.
    pub phi_d_span: Option<PhiDSpan>,
    /// phi_h, degrees.
    pub phi_h_deg: Option<f64>,
}

/// The paper's measured sample count on the UTIA device (5.3: 4073 of its 6300 samples), the
/// budget every grid of Specula's stays within.
pub const PAPER_MEASURED_SAMPLES: usize = 4073;

/// How the grid changes for a material whose specular peak the instrument does not resolve
/// (issue 14): the half width of the lobe fitted through the response to the probe is below
/// the instrument's resolution (`specula_acquisition::response`). The lobe before the blur
/// is then pinned by its theta_h positions, not by the grazing theta_d rows, which the
/// light's disk blurs: measured through the simulated UTIA disk (README, "The instrument's
/// response"), a Beckmann chrome (alpha 0.015) scores 0.25 relative RMSE with 16 theta_h and
/// 0.006 with 30, the green paint 0.055 and 0.022. The plan takes the most theta_h positions
/// up to `theta_h_samples` that keep the measured samples within `budget_samples`, with
/// theta_d as `theta_d` says; the rest of the grid is unchanged.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct UnresolvedPeak {
    /// The most theta_h positions.
    pub theta_h_samples: usize,
    /// theta_d's positions for such a material.
    pub theta_d: ThetaDSteps,
    /// The most samples the device may measure.
    pub budget_samples: usize,
}

/// theta_d's positions: every `step_deg` from 0, and, with a [`GrazingStep`], every
/// `grazing.step_deg` once `grazing.from_deg` is reached. Written `STEP` or
/// `STEP:GRAZING@FROM` (e.g. `3:1@60`: 0, 3, ..., 57, then 60, 61, ..., 89), the notation of
/// `--theta-d-step` and of README's plan tables.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ThetaDSteps {
    /// Step of theta_d in degrees below the grazing threshold (everywhere without one).
    #[serde(rename = "theta_d_step_deg")]
    pub step_deg: f64,
    /// The finer step towards grazing theta_d, if any.
    #[serde(rename = "theta_d_grazing", default)]
    pub grazing: Option<GrazingStep>,
}

/// A finer theta_d step towards grazing angles (issue 20): every `step_deg` degrees from the
/// first coarse position at or above `from_deg`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GrazingStep {
    /// The step in degrees from `from_deg` on.
    pub step_deg: f64,
    /// Where the finer step starts, degrees of theta_d.
    pub from_deg: f64,
}

/// How far the phi_d positions go.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PhiDSpan {
    /// 0 to 90 deg inclusive, the paper's (5.3): reciprocity and the mirror symmetry of an
    /// isotropic surface give the rest.
    Quarter,
    /// 0 to 180 deg inclusive: a configuration (phi_d below 90) and its light/camera swap
    /// (180 - phi_d), reconstructed apart when the material is not reciprocal; 180 is the
    /// swap of 0.
    HalfTurn,
}

/// Why a grid's notation or numbers are refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GridError {
    /// theta_d's steps are not written `STEP` or `STEP:GRAZING@FROM`.
    #[error(
        "theta_d steps '{0}': expected STEP or STEP:GRAZING@FROM in degrees, e.g. 3 or 3:1@60"
    )]
    ThetaDNotation(String),
    /// A theta_d step or threshold is out of its range.
    #[error("theta_d steps '{text}': {problem}")]
    ThetaDRange {
        /// The notation as given.
        text: String,
        /// What is out of range.
        problem: &'static str,
    },
    /// Another number of the grid is out of its range.
    #[error("{what} {value}: expected {expected}")]
    Range {
        /// The number: `theta_h samples`, `phi_d step`, `phi_h`.
        what: &'static str,
        /// Its value.
        value: f64,
        /// Its range in words.
        expected: &'static str,
    },
    /// An unknown phi_d span.
    #[error("phi_d span '{0}': expected quarter (0 to 90 deg) or half-turn (0 to 180 deg)")]
    PhiDSpan(String),
}

impl GridSpec {
    /// The paper's grid (5.3): 30 theta_h positions, theta_d step 3 deg (0 to 87), phi_d
    /// step 15 deg (0 to 90), phi_h 45 deg: 30 x 30 x 7 = 6300 samples.
    pub const fn paper() -> Self {
        Self {
            theta_h_samples: 30,
            theta_d: ThetaDSteps {
                step_deg: 3.0,
                grazing: None,
            },
            phi_d_step_deg: 15.0,
            phi_d_span: PhiDSpan::Quarter,
            phi_h_deg: 45.0,
            unresolved_peak: None,
        }
    }

    /// The recommended grid (issue 20): 16 theta_h positions, theta_d every 3 deg below 60
    /// and every 1 deg from 60 (`3:1@60`: 50 positions), phi_d every 30 deg over the half
    /// turn 0 to 180 (7 positions), phi_h 45 deg: 16 x 50 x 7 = 5600 samples, of which the
    /// UTIA device takes at most about 3200 (the paper's took 4073).
    ///
    /// On the five real RGL measurements, measured without noise and reconstructed by
    /// halves of phi_d with `lobe`, it gives 0.18 (relative RMSE) and 0.26 (log RMSE) of the
    /// paper pipeline's error on the paper's plan (median; worst file 0.39 / 0.37), with at
    /// most 2785 samples there and 3162 on the built-in materials. On reciprocal truths (the
    /// built-in database, the MERL-100 fits) the second half repeats the first and the gain
    /// is the graded theta_d's. README, "Real measured truths first (issue 20)", "The two
    /// halves of phi_d".
    pub const fn recommended() -> Self {
        Self {
            theta_h_samples: 16,
            theta_d: ThetaDSteps {
                step_deg: 3.0,
                grazing: Some(GrazingStep {
                    step_deg: 1.0,
                    from_deg: 60.0,
                }),
            },
            phi_d_step_deg: 30.0,
            phi_d_span: PhiDSpan::HalfTurn,
            phi_h_deg: 45.0,
            unresolved_peak: Some(UnresolvedPeak {
                theta_h_samples: 30,
                theta_d: ThetaDSteps::even(3.0),
                budget_samples: PAPER_MEASURED_SAMPLES,
            }),
        }
    }

    /// The grids to try, in order, for a material whose peak the instrument does not
    /// resolve ([`UnresolvedPeak`]): from the most theta_h positions down to one more than
    /// this grid's, each with the rule's theta_d and no rule of its own. Empty without a
    /// rule; the first whose plan stays within [`UnresolvedPeak::budget_samples`] is taken,
    /// this grid ([`GridSpec::fixed`]) when none does.
    pub fn unresolved_peak_grids(&self) -> Vec<GridSpec> {
        let Some(rule) = self.unresolved_peak else {
            return Vec::new();
        };
        (self.theta_h_samples + 1..=rule.theta_h_samples)
            .rev()
            .map(|theta_h_samples| GridSpec {
                theta_h_samples,
                theta_d: rule.theta_d,
                unresolved_peak: None,
                ..*self
            })
            .collect()
    }

    /// The grid a material gets: this grid for every material ([`GridSpec::fixed`]), or,
    /// where `peak_unresolved` and the grid has an [`UnresolvedPeak`] rule, the first of
    /// [`GridSpec::unresolved_peak_grids`] whose plan stays within the rule's budget;
    /// `measured` gives the samples a candidate's plan takes on the device (its errors pass
    /// through).
    pub fn for_material<E>(
        &self,
        peak_unresolved: bool,
        mut measured: impl FnMut(&GridSpec) -> Result<usize, E>,
    ) -> Result<GridSpec, E> {
        if let (true, Some(rule)) = (peak_unresolved, self.unresolved_peak) {
            for grid in self.unresolved_peak_grids() {
                if measured(&grid)? <= rule.budget_samples {
                    return Ok(grid);
                }
            }
        }
        Ok(self.fixed())
    }

    /// This grid with the values `overrides` gives in place of its own. Giving theta_h's
    /// count or theta_d's steps fixes the grid for every material (drops its
    /// [`UnresolvedPeak`] rule, which replaces those two); phi_d and phi_h keep it.
    pub fn with(&self, overrides: &GridOverrides) -> GridSpec {
        let fixes = overrides.theta_h_samples.is_some() || overrides.theta_d.is_some();
        GridSpec {
            theta_h_samples: overrides.theta_h_samples.unwrap_or(self.theta_h_samples),
            theta_d: overrides.theta_d.unwrap_or(self.theta_d),
            phi_d_step_deg: overrides.phi_d_step_deg.unwrap_or(self.phi_d_step_deg),
            phi_d_span: overrides.phi_d_span.unwrap_or(self.phi_d_span),
            phi_h_deg: overrides.phi_h_deg.unwrap_or(self.phi_h_deg),
            unresolved_peak: self.unresolved_peak.filter(|_| !fixes),
        }
    }

    /// This grid for every material: without its [`UnresolvedPeak`] rule.
    pub fn fixed(&self) -> GridSpec {
        GridSpec {
            unresolved_peak: None,
            ..*self
        }
    }

    /// Checks that the grid can be stepped: at least 2 theta_h positions, steps above 0
    /// and at most 90 deg, a grazing threshold from 0 to below 90 deg, a finite phi_h.
    pub fn check(&self) -> Result<(), GridError> {
        let range = |what, value, expected| GridError::Range {
            what,
            value,
            expected,
        };
        if self.theta_h_samples < 2 {
            return Err(range(
                "theta_h samples",
                self.theta_h_samples as f64,
                "at least 2",
            ));
        }
        self.theta_d.check()?;
        if !(self.phi_d_step_deg > 0.0 && self.phi_d_step_deg <= 90.0) {
            return Err(range(
                "phi_d step",
                self.phi_d_step_deg,
                "degrees above 0 and at most 90",
            ));
        }
        if !self.phi_h_deg.is_finite() {
            return Err(range("phi_h", self.phi_h_deg, "a number of degrees"));
        }
        if let Some(rule) = self.unresolved_peak {
            if rule.theta_h_samples < self.theta_h_samples {
                return Err(range(
                    "theta_h samples for an unresolved peak",
                    rule.theta_h_samples as f64,
                    "at least the grid's own",
                ));
            }
            rule.theta_d.check()?;
        }
        Ok(())
    }

    /// theta_d positions in degrees, ascending from 0 and below 90 ([`ThetaDSteps`]).
    pub fn theta_d_deg(&self) -> Vec<f64> {
        self.theta_d.positions_deg()
    }

    /// phi_d positions in degrees: `0, step, 2 step, ...` up to and including 90 or 180
    /// ([`PhiDSpan`]).
    pub fn phi_d_deg(&self) -> Vec<f64> {
        even_steps_deg(self.phi_d_step_deg, self.phi_d_span.end_deg(), true)
    }

    /// The number of configurations: theta_h x theta_d x phi_d positions.
    pub fn configurations(&self) -> usize {
        self.theta_h_samples * self.theta_d_deg().len() * self.phi_d_deg().len()
    }
}

impl Default for GridSpec {
    /// The recommended grid ([`GridSpec::recommended`]), the default plan of `plan`,
    /// `measure`, `evaluate`, the Python package and the demo; the paper's is
    /// [`GridSpec::paper`].
    fn default() -> Self {
        Self::recommended()
    }
}

impl fmt::Display for GridSpec {
    /// In words, e.g. `16 theta_h, theta_d step 3 deg (1 deg from 60), phi_d step 30 deg
    /// over 0-180 (both halves), phi_h 45 deg`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} theta_h, theta_d step {} deg",
            self.theta_h_samples, self.theta_d.step_deg
        )?;
        if let Some(g) = self.theta_d.grazing {
            write!(f, " ({} deg from {})", g.step_deg, g.from_deg)?;
        }
        write!(
            f,
            ", phi_d step {} deg over 0-{}{}, phi_h {} deg",
            self.phi_d_step_deg,
            self.phi_d_span.end_deg(),
            match self.phi_d_span {
                PhiDSpan::Quarter => "",
                PhiDSpan::HalfTurn => " (both halves)",
            },
            self.phi_h_deg
        )?;
        if let Some(rule) = self.unresolved_peak {
            write!(
                f,
                "; up to {} theta_h with theta_d step {} deg where the instrument does not resolve the peak",
                rule.theta_h_samples, rule.theta_d
            )?;
        }
        Ok(())
    }
}

impl ThetaDSteps {
    /// Even steps of `step_deg` everywhere.
    pub const fn even(step_deg: f64) -> Self {
        Self {
            step_deg,
            grazing: None,
        }
    }

    /// The positions in degrees, ascending from 0 and below 90: `i step` while below the
    /// grazing threshold, the first of them at or above it included, then every grazing step.
    /// Steps must be positive.
    pub fn positions_deg(&self) -> Vec<f64> {
        let Some(grazing) = self.grazing else {
            return even_steps_deg(self.step_deg, 90.0, false);
        };
        let mut out: Vec<f64> = Vec::new();
        let mut i = 0.0;
        loop {
            let theta_d = i * self.step_deg;
            if theta_d >= 90.0 - STEP_TOLERANCE_DEG {
                return out;
            }
            out.push(theta_d);
            if theta_d >= grazing.from_deg - STEP_TOLERANCE_DEG {
                break;
            }
            i += 1.0;
        }
        let start = *out.last().unwrap_or(&0.0);
        let fine = even_steps_deg(grazing.step_deg, 90.0 - start, false);
        out.extend(fine.into_iter().skip(1).map(|d| start + d));
        out
    }

    /// Checks the ranges: steps above 0 and at most 90 deg, the threshold from 0 to below
    /// 90 deg (NaN is in no range).
    pub fn check(&self) -> Result<(), GridError> {
        let problem = |problem| GridError::ThetaDRange {
            text: self.to_string(),
            problem,
        };
        let step_ok = |s: f64| s > 0.0 && s <= 90.0;
        if !step_ok(self.step_deg) {
            return Err(problem("the step must be above 0 and at most 90 deg"));
        }
        if let Some(g) = self.grazing {
            if !step_ok(g.step_deg) {
                return Err(problem(
                    "the grazing step must be above 0 and at most 90 deg",
                ));
            }
            if !(0.0..90.0).contains(&g.from_deg) {
                return Err(problem(
                    "the grazing step must start from 0 to below 90 deg",
                ));
            }
        }
        Ok(())
    }
}

impl FromStr for ThetaDSteps {
    type Err = GridError;

    /// `STEP` or `STEP:GRAZING@FROM` in degrees (e.g. `3`, `3:1@60`), checked as
    /// [`ThetaDSteps`] documents.
    fn from_str(text: &str) -> Result<Self, GridError> {
        let notation = || GridError::ThetaDNotation(text.to_string());
        let number = |v: &str| {
            v.trim()
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(notation)
        };
        let steps = match text.split_once(':') {
            None => Self::even(number(text)?),
            Some((step, rest)) => {
                let (grazing, from) = rest.split_once('@').ok_or_else(notation)?;
                Self {
                    step_deg: number(step)?,
                    grazing: Some(GrazingStep {
                        step_deg: number(grazing)?,
                        from_deg: number(from)?,
                    }),
                }
            }
        };
        steps.check()?;
        Ok(steps)
    }
}

impl fmt::Display for ThetaDSteps {
    /// The notation [`FromStr`] reads: `3` or `3:1@60`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.step_deg)?;
        if let Some(g) = self.grazing {
            write!(f, ":{}@{}", g.step_deg, g.from_deg)?;
        }
        Ok(())
    }
}

impl PhiDSpan {
    /// The last phi_d position, degrees: 90 or 180.
    pub const fn end_deg(self) -> f64 {
        match self {
            PhiDSpan::Quarter => 90.0,
            PhiDSpan::HalfTurn => 180.0,
        }
    }

    /// The name of the span: `quarter` or `half-turn` (also its name in a record).
    pub const fn name(self) -> &'static str {
        match self {
            PhiDSpan::Quarter => "quarter",
            PhiDSpan::HalfTurn => "half-turn",
        }
    }

    /// The span of a record written before it existed: the paper's quarter.
    fn before_issue_20() -> Self {
        PhiDSpan::Quarter
    }
}

impl FromStr for PhiDSpan {
    type Err = GridError;

    /// `quarter` or `half-turn` ([`PhiDSpan::name`]).
    fn from_str(text: &str) -> Result<Self, GridError> {
        [PhiDSpan::Quarter, PhiDSpan::HalfTurn]
            .into_iter()
            .find(|s| s.name() == text)
            .ok_or_else(|| GridError::PhiDSpan(text.to_string()))
    }
}

impl fmt::Display for PhiDSpan {
    /// [`PhiDSpan::name`].
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// `0, step, 2 step, ...` below `end_deg`, or up to and including it with `include_end`
/// (within float noise); `step_deg` must be positive. Degrees in, degrees out.
fn even_steps_deg(step_deg: f64, end_deg: f64, include_end: bool) -> Vec<f64> {
    let count = (end_deg / step_deg + STEP_TOLERANCE_DEG).floor() as usize;
    (0..=count)
        .map(|i| i as f64 * step_deg)
        .filter(|&v| {
            if include_end {
                v <= end_deg + STEP_TOLERANCE_DEG
            } else {
                v < end_deg - STEP_TOLERANCE_DEG
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_paper_grid_has_6300_samples() {
        let paper = GridSpec::paper();
        let theta_d = paper.theta_d_deg();
        let phi_d = paper.phi_d_deg();
        assert_eq!(theta_d.len(), 30);
        assert_eq!(theta_d.last(), Some(&87.0));
        assert_eq!(phi_d, vec![0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 90.0]);
        assert_eq!(paper.theta_h_samples * theta_d.len() * phi_d.len(), 6300);
        assert_eq!(paper.configurations(), 6300);
    }

    #[test]
    fn the_recommended_grid_is_graded_over_the_half_turn() {
        let grid = GridSpec::recommended();
        assert_eq!(grid, GridSpec::default());
        let theta_d = grid.theta_d_deg();
        assert_eq!(theta_d[..3], [0.0, 3.0, 6.0]);
        assert_eq!(theta_d[19..22], [57.0, 60.0, 61.0]);
        assert_eq!(theta_d.last(), Some(&89.0));
        assert_eq!(theta_d.len(), 20 + 30);
        assert_eq!(
            grid.phi_d_deg(),
            [0.0, 30.0, 60.0, 90.0, 120.0, 150.0, 180.0]
        );
        assert_eq!(grid.configurations(), 16 * 50 * 7);
    }

    #[test]
    fn even_steps_stop_before_or_at_the_end() {
        assert_eq!(even_steps_deg(90.0, 90.0, false), vec![0.0]);
        assert_eq!(even_steps_deg(90.0, 90.0, true), vec![0.0, 90.0]);
        assert_eq!(even_steps_deg(40.0, 90.0, true), vec![0.0, 40.0, 80.0]);
        assert_eq!(even_steps_deg(0.1, 90.0, false).len(), 900);
        assert_eq!(even_steps_deg(0.1, 90.0, true).len(), 901);
        assert_eq!(
            even_steps_deg(45.0, 180.0, true),
            [0.0, 45.0, 90.0, 135.0, 180.0]
        );
        assert_eq!(*even_steps_deg(40.0, 180.0, true).last().unwrap(), 160.0);
    }

    #[test]
    fn the_step_changes_at_the_grazing_threshold() {
        let graded = |text: &str| text.parse::<ThetaDSteps>().unwrap().positions_deg();
        let positions = graded("3:1.5@60");
        assert_eq!(positions[..3], [0.0, 3.0, 6.0]);
        assert_eq!(positions[20..23], [60.0, 61.5, 63.0]);
        assert_eq!(*positions.last().unwrap(), 88.5);
        assert_eq!(positions.len(), 20 + 20);
        // A threshold between coarse positions: the first coarse one above it starts the
        // fine step.
        assert_eq!(graded("3:1@50")[16..19], [48.0, 51.0, 52.0]);
        // One step everywhere is the even grid.
        assert_eq!(graded("3:3@45"), graded("3"));
        assert_eq!(graded("3").len(), 30);
        // A threshold at 0 is the fine step everywhere.
        assert_eq!(graded("3:1@0"), graded("1"));
    }

    #[test]
    fn theta_d_notation_parses_prints_and_refuses() {
        let steps: ThetaDSteps = "3:1@60".parse().unwrap();
        assert_eq!(
            steps,
            ThetaDSteps {
                step_deg: 3.0,
                grazing: Some(GrazingStep {
                    step_deg: 1.0,
                    from_deg: 60.0
                })
            }
        );
        assert_eq!(steps.to_string(), "3:1@60");
        assert_eq!(" 1.5 ".parse::<ThetaDSteps>(), Ok(ThetaDSteps::even(1.5)));
        assert_eq!(ThetaDSteps::even(1.5).to_string(), "1.5");
        for bad in [
            "", "x", "3:1", "3:@60", "3:1@", "3:1@60@2", "nan", "3:inf@60",
        ] {
            assert_eq!(
                bad.parse::<ThetaDSteps>(),
                Err(GridError::ThetaDNotation(bad.to_string())),
                "{bad}"
            );
        }
        for bad in ["0", "-3", "91", "3:0@60", "3:1@90", "3:1@-1"] {
            assert!(
                matches!(
                    bad.parse::<ThetaDSteps>(),
                    Err(GridError::ThetaDRange { .. })
                ),
                "{bad}"
            );
        }
    }

    #[test]
    fn a_grid_that_cannot_be_stepped_is_refused() {
        assert_eq!(GridSpec::recommended().check(), Ok(()));
        assert_eq!(GridSpec::paper().check(), Ok(()));
        let bad = [
            GridSpec {
                theta_h_samples: 1,
                ..GridSpec::paper()
            },
            GridSpec {
                theta_d: ThetaDSteps::even(0.0),
                ..GridSpec::paper()
            },
            GridSpec {
                phi_d_step_deg: f64::NAN,
                ..GridSpec::paper()
            },
            GridSpec {
                phi_h_deg: f64::INFINITY,
                ..GridSpec::paper()
            },
        ];
        for grid in bad {
            assert!(grid.check().is_err(), "{grid:?}");
        }
    }

    #[test]
    fn phi_d_spans_by_name() {
        assert_eq!("half-turn".parse(), Ok(PhiDSpan::HalfTurn));
        assert_eq!("quarter".parse(), Ok(PhiDSpan::Quarter));
        assert!("half".parse::<PhiDSpan>().is_err());
    }

    #[test]
    fn a_grid_reads_in_words_and_keeps_its_record_flat() {
        assert_eq!(
            GridSpec::recommended().to_string(),
            "16 theta_h, theta_d step 3 deg (1 deg from 60), phi_d step 30 deg over 0-180 \
             (both halves), phi_h 45 deg; up to 30 theta_h with theta_d step 3 deg where the \
             instrument does not resolve the peak"
        );
        assert_eq!(
            GridSpec::recommended().fixed().to_string(),
            "16 theta_h, theta_d step 3 deg (1 deg from 60), phi_d step 30 deg over 0-180 \
             (both halves), phi_h 45 deg"
        );
        assert_eq!(
            GridSpec::paper().to_string(),
            "30 theta_h, theta_d step 3 deg, phi_d step 15 deg over 0-90, phi_h 45 deg"
        );
        let json = toml::Value::try_from(GridSpec::recommended()).unwrap();
        let table = json.as_table().unwrap();
        assert_eq!(table.len(), 7);
        for key in [
            "theta_h_samples",
            "theta_d_step_deg",
            "theta_d_grazing",
            "phi_d_step_deg",
            "phi_d_span",
            "phi_h_deg",
            "unresolved_peak",
        ] {
            assert!(table.contains_key(key), "{key}: {table:?}");
        }
        assert_eq!(table["phi_d_span"].as_str(), Some("half-turn"));
        let back: GridSpec = json.try_into().unwrap();
        assert_eq!(back, GridSpec::recommended());
    }

    #[test]
    fn a_grid_recorded_before_issue_20_is_the_paper_shape() {
        let old = "theta_h_samples = 12\ntheta_d_step_deg = 6.0\nphi_d_step_deg = 15.0\nphi_h_deg = 45.0\n";
        let grid: GridSpec = toml::from_str(old).unwrap();
        assert_eq!(
            grid,
            GridSpec {
                theta_h_samples: 12,
                theta_d: ThetaDSteps::even(6.0),
                ..GridSpec::paper()
            }
        );
    }

    #[test]
    fn an_unresolved_peak_gets_more_theta_h_on_an_even_theta_d() {
        let grid = GridSpec::recommended();
        let tried = grid.unresolved_peak_grids();
        let counts: Vec<usize> = tried.iter().map(|g| g.theta_h_samples).collect();
        assert_eq!(counts, (17..=30).rev().collect::<Vec<_>>());
        for g in &tried {
            assert_eq!(g.theta_d, ThetaDSteps::even(3.0));
            assert_eq!(g.unresolved_peak, None);
            assert_eq!((g.phi_d_step_deg, g.phi_d_span), (30.0, PhiDSpan::HalfTurn));
            assert_eq!(g.check(), Ok(()));
        }
        assert!(GridSpec::paper().unresolved_peak_grids().is_empty());
        assert!(grid.fixed().unresolved_peak_grids().is_empty());
        assert_eq!(grid.fixed().theta_d, grid.theta_d);
        let rule = grid.unresolved_peak.unwrap();
        assert_eq!(rule.budget_samples, PAPER_MEASURED_SAMPLES);
        let fewer = GridSpec {
            unresolved_peak: Some(UnresolvedPeak {
                theta_h_samples: 8,
                ..rule
            }),
            ..grid
        };
        assert!(fewer.check().is_err());
    }

    #[test]
    fn a_material_gets_the_most_theta_h_its_budget_allows() {
        let grid = GridSpec::recommended();
        // A stand-in count: 150 samples per theta_h position.
        let count = |g: &GridSpec| Ok::<_, ()>(150 * g.theta_h_samples);
        let unresolved = grid.for_material(true, count).unwrap();
        assert_eq!(unresolved.theta_h_samples, 4073 / 150);
        assert_eq!(unresolved.theta_d, ThetaDSteps::even(3.0));
        assert_eq!(grid.for_material(false, count), Ok(grid.fixed()));
        assert_eq!(
            grid.for_material(true, |_| Ok::<_, ()>(5000)),
            Ok(grid.fixed())
        );
        assert_eq!(grid.for_material(true, |_| Err("no plan")), Err("no plan"));
        assert_eq!(
            GridSpec::paper().for_material(true, count),
            Ok(GridSpec::paper())
        );
    }

    #[test]
    fn overrides_replace_values_and_theta_h_or_theta_d_fix_the_grid() {
        let grid = GridSpec::recommended();
        assert_eq!(grid.with(&GridOverrides::default()), grid);
        let turned = grid.with(&GridOverrides {
            phi_d_step_deg: Some(45.0),
            phi_d_span: Some(PhiDSpan::Quarter),
            phi_h_deg: Some(30.0),
            ..GridOverrides::default()
        });
        assert_eq!(
            (turned.phi_d_step_deg, turned.phi_d_span, turned.phi_h_deg),
            (45.0, PhiDSpan::Quarter, 30.0)
        );
        assert_eq!(turned.unresolved_peak, grid.unresolved_peak);
        let more = grid.with(&GridOverrides {
            theta_h_samples: Some(20),
            ..GridOverrides::default()
        });
        assert_eq!((more.theta_h_samples, more.unresolved_peak), (20, None));
        let even = grid.with(&GridOverrides {
            theta_d: Some(ThetaDSteps::even(2.0)),
            ..GridOverrides::default()
        });
        assert_eq!(
            (even.theta_d, even.unresolved_peak),
            (ThetaDSteps::even(2.0), None)
        );
    }
}
