//! The checked range of every numeric option. Each option's parser refuses a value outside
//! its range while the command line is read, before any work starts, with one line naming
//! the option, the value and the range in words (exit 2, as every usage error); the same
//! words end the option's `--help` text ("Range: ..."), which a test checks.

use clap::builder::TypedValueParser;
use clap::error::ErrorKind;
use specula_core::grid::ThetaDSteps;
use specula_formats::rgl::write as rgl;

/// A real number between two finite bounds, in a unit: degrees, seconds, stops, ...
#[derive(Clone, Copy, Debug)]
pub(crate) struct Real {
    min: f64,
    max: f64,
    /// The minimum itself is refused (a step, a timeout: above 0).
    above_min: bool,
    unit: &'static str,
}

impl Real {
    /// Values from `min` to `max`, both included, in `unit`.
    pub(crate) const fn from_to(min: f64, max: f64, unit: &'static str) -> Self {
        Self {
            min,
            max,
            above_min: false,
            unit,
        }
    }

    /// Values above `min` (excluded) up to `max` (included), in `unit`.
    pub(crate) const fn above(min: f64, max: f64, unit: &'static str) -> Self {
        Self {
            min,
            max,
            above_min: true,
            unit,
        }
    }

    /// The range in words, as `--help` and the error say it.
    pub(crate) fn words(&self) -> String {
        if self.above_min {
            format!("{} above {} and at most {}", self.unit, self.min, self.max)
        } else {
            format!("{} from {} to {}", self.unit, self.min, self.max)
        }
    }

    /// Whether `value` lies in the range (NaN never does).
    pub(crate) fn contains(&self, value: f64) -> bool {
        let above = if self.above_min {
            value > self.min
        } else {
            value >= self.min
        };
        above && value <= self.max
    }
}

/// A whole number between two bounds (a count of samples, pixels, tries).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Count {
    min: usize,
    max: usize,
}

impl Count {
    /// Counts from `min` to `max`, both included.
    pub(crate) const fn from_to(min: usize, max: usize) -> Self {
        Self { min, max }
    }

    /// The range in words, as `--help` and the error say it.
    pub(crate) fn words(&self) -> String {
        format!("a whole number from {} to {}", self.min, self.max)
    }
}

/// The error of a value outside its range: `--flag VALUE: expected WORDS`.
fn out_of_range(arg: Option<&clap::Arg>, value: &str, words: &str) -> clap::Error {
    let flag = arg
        .and_then(|a| a.get_long())
        .map_or_else(|| "value".to_string(), |long| format!("--{long}"));
    clap::Error::raw(
        ErrorKind::ValueValidation,
        format!("{flag} {value}: expected {words}\n"),
    )
}

impl TypedValueParser for Real {
    type Value = f64;

    fn parse_ref(
        &self,
        _cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<f64, clap::Error> {
        let text = value.to_string_lossy();
        match text.trim().parse::<f64>() {
            Ok(number) if self.contains(number) => Ok(number),
            _ => Err(out_of_range(arg, &text, &self.words())),
        }
    }
}

impl TypedValueParser for Count {
    type Value = usize;

    fn parse_ref(
        &self,
        _cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<usize, clap::Error> {
        let text = value.to_string_lossy();
        match text.trim().parse::<usize>() {
            Ok(number) if (self.min..=self.max).contains(&number) => Ok(number),
            _ => Err(out_of_range(arg, &text, &self.words())),
        }
    }
}

/// theta_d's positions of a grid, `STEP` or `STEP:GRAZING@FROM`
/// ([`specula_core::grid::ThetaDSteps`]): both steps in [`GRID_STEP_DEG`], FROM from 0 to
/// below 90 deg.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ThetaDStepsArg;

impl ThetaDStepsArg {
    /// The range in words, as `--help` and the error say it.
    pub(crate) fn words() -> String {
        format!(
            "{}, or STEP:GRAZING@FROM with both steps from {} to {} and FROM from 0 to below 90",
            GRID_STEP_DEG.words(),
            GRID_STEP_DEG.min,
            GRID_STEP_DEG.max
        )
    }
}

impl TypedValueParser for ThetaDStepsArg {
    type Value = ThetaDSteps;

    fn parse_ref(
        &self,
        _cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<ThetaDSteps, clap::Error> {
        let text = value.to_string_lossy();
        match text.trim().parse::<ThetaDSteps>() {
            Ok(steps)
                if GRID_STEP_DEG.contains(steps.step_deg)
                    && steps
                        .grazing
                        .is_none_or(|g| GRID_STEP_DEG.contains(g.step_deg)) =>
            {
                Ok(steps)
            }
            _ => Err(out_of_range(arg, &text, &Self::words())),
        }
    }
}

/// Angles in degrees: a turntable or half-vector azimuth, either way round.
pub(crate) const AZIMUTH_DEG: Real = Real::from_to(-360.0, 360.0, "degrees");
/// phi_d of MERL's half-difference angles (folded by reciprocity to [0, 180]).
pub(crate) const PHI_D_DEG: Real = Real::from_to(0.0, 180.0, "degrees");
/// theta_d, from the half vector: below the horizon at 90.
pub(crate) const THETA_D_DEG: Real = Real::from_to(0.0, 89.5, "degrees");
/// A theta_h position.
pub(crate) const THETA_H_DEG: Real = Real::from_to(0.0, 90.0, "degrees");
/// A step of a grid in degrees (theta_d, phi_d).
pub(crate) const GRID_STEP_DEG: Real = Real::from_to(0.5, 90.0, "degrees");
/// An elevation from the normal that bounds the device's reach.
pub(crate) const ELEVATION_DEG: Real = Real::above(0.0, 90.0, "degrees");
/// The sample's tilt on the turntable (a misalignment to simulate).
pub(crate) const TILT_DEG: Real = Real::from_to(0.0, 10.0, "degrees");
/// k of a theta_h sampling function (the family's own bound is checked as well: base-k
/// needs k above 1).
pub(crate) const SAMPLING_K: Real = Real::above(0.0, 100.0, "a number");
/// A scan step of phi_h.
pub(crate) const PHI_H_STEP_DEG: Real = Real::above(0.0, 45.0, "degrees");
/// An elevation of the light above the sample for the alignment check.
pub(crate) const LIGHT_ELEVATION_DEG: Real = Real::from_to(5.0, 75.0, "degrees");
/// A reflectance (a white reference).
pub(crate) const REFLECTANCE: Real = Real::above(0.0, 1.0, "a fraction");
/// Radiance factor of the simulated lens flare, 1/sr.
pub(crate) const FLARE_STRENGTH_SR: Real = Real::from_to(0.0, 10.0, "1/sr");
/// Seconds to wait (timeouts): up to a day.
pub(crate) const TIMEOUT_S: Real = Real::above(0.0, 86_400.0, "seconds");
/// How much faster than real time a rehearsal runs.
pub(crate) const SPEEDUP: Real = Real::above(0.0, 1e6, "a factor");
/// An instrument's angular resolution, e.g. the angular radius of its light source.
pub(crate) const RESOLUTION_DEG: Real = Real::above(0.0, 90.0, "degrees");
/// Exposure of a tone-mapped picture.
pub(crate) const EXPOSURE_STOPS: Real = Real::from_to(-20.0, 20.0, "stops");

/// theta_h samples of a measurement's sampling function (the paper: 30; MERL has 90 bins).
pub(crate) const THETA_H_SAMPLES: Count = Count::from_to(2, 360);
/// Samples of a probe (the paper: 90).
pub(crate) const PROBE_SAMPLES: Count = Count::from_to(2, 10_000);
/// Failures in a row on one request before giving up.
pub(crate) const FAILURES: Count = Count::from_to(1, 100);
/// Turntable rotations of the alignment check.
pub(crate) const ROTATIONS: Count = Count::from_to(3, 72);
/// Width and height of a picture, pixels.
pub(crate) const IMAGE_PX: Count = Count::from_to(8, specula_report::MAX_IMAGE_PX);
/// Camera rays per pixel.
pub(crate) const SAMPLES_PER_PIXEL: Count =
    Count::from_to(1, specula_visual::render::MAX_SAMPLES_PER_PIXEL);
/// Incident elevations of a written RGL file.
pub(crate) const RGL_ELEVATIONS: Count =
    Count::from_to(*rgl::ELEVATIONS_RANGE.start(), *rgl::ELEVATIONS_RANGE.end());
/// Nodes per axis of a written RGL file's microfacet distribution.
pub(crate) const RGL_NDF_SIZE: Count =
    Count::from_to(*rgl::NDF_SIZE_RANGE.start(), *rgl::NDF_SIZE_RANGE.end());
/// Samples per axis of a written RGL file's RGB grid.
pub(crate) const RGL_SAMPLE_SIZE: Count = Count::from_to(
    *rgl::SAMPLE_SIZE_RANGE.start(),
    *rgl::SAMPLE_SIZE_RANGE.end(),
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_read_in_words_and_refuse_nan() {
        assert_eq!(ELEVATION_DEG.words(), "degrees above 0 and at most 90");
        assert_eq!(PHI_D_DEG.words(), "degrees from 0 to 180");
        assert!(!ELEVATION_DEG.contains(0.0) && ELEVATION_DEG.contains(90.0));
        assert!(!PHI_D_DEG.contains(f64::NAN) && !PHI_D_DEG.contains(400.0));
        assert_eq!(PROBE_SAMPLES.words(), "a whole number from 2 to 10000");
        assert_eq!(
            ThetaDStepsArg::words(),
            "degrees from 0.5 to 90, or STEP:GRAZING@FROM with both steps from 0.5 to 90 and \
             FROM from 0 to below 90"
        );
    }
}
