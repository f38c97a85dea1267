//! The checked range of every numeric option. Each option's parser refuses a value outside
//! its range while the command line is read, before any work starts, with one line naming
//! the option, the value and the range in words (exit 2, as every usage error); the same
//! words end the option's `--help` text ("Range: ..."), which a test checks. The ranges of
//! the grid, the probe and the tilt are the library's ([`specula_core::request`]), which the
//! Python package checks as well.

use clap::builder::TypedValueParser;
use clap::error::ErrorKind;
use specula_core::grid::ThetaDSteps;
use specula_core::range::{CountRange, RangeError, RealRange};
use specula_core::request;
use specula_formats::rgl::write as rgl;

/// A real number in a [`RealRange`], as an option's parser.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Real(RealRange);

impl Real {
    /// Values from `min` to `max`, both included, in `unit`.
    pub(crate) const fn from_to(min: f64, max: f64, unit: &'static str) -> Self {
        Self(RealRange::from_to(min, max, unit))
    }

    /// Values above `min` (excluded) up to `max` (included), in `unit`.
    pub(crate) const fn above(min: f64, max: f64, unit: &'static str) -> Self {
        Self(RealRange::above(min, max, unit))
    }
}

/// A whole number in a [`CountRange`], as an option's parser.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Count(CountRange);

impl Count {
    /// Counts from `min` to `max`, both included.
    pub(crate) const fn from_to(min: usize, max: usize) -> Self {
        Self(CountRange::from_to(min, max))
    }
}

/// The option's flag (`--theta-h-samples`) as the library's errors name it.
fn flag(arg: Option<&clap::Arg>) -> String {
    arg.and_then(|a| a.get_long())
        .map_or_else(|| "value".to_string(), |long| format!("--{long}"))
}

/// The library's range error as clap's usage error.
fn usage_error(error: RangeError) -> clap::Error {
    clap::Error::raw(ErrorKind::ValueValidation, format!("{error}\n"))
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
            Ok(number) if self.0.contains(number) => Ok(number),
            _ => Err(usage_error(self.0.refuse(&flag(arg), &text))),
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
            Ok(number) if self.0.contains(number) => Ok(number),
            _ => Err(usage_error(self.0.refuse(&flag(arg), &text))),
        }
    }
}

/// theta_d's positions of a grid, `STEP` or `STEP:GRAZING@FROM`
/// ([`specula_core::grid::ThetaDSteps`], checked by [`request::check_theta_d_steps`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct ThetaDStepsArg;

impl ThetaDStepsArg {
    /// The range in words, as `--help` and the error say it.
    pub(crate) fn words() -> String {
        request::theta_d_steps_words()
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
        let flag = flag(arg);
        let steps = text.trim().parse::<ThetaDSteps>().map_err(|_| {
            usage_error(RangeError {
                option: flag.clone(),
                value: text.to_string(),
                expected: Self::words(),
            })
        })?;
        request::check_theta_d_steps(&flag, steps).map_err(|mut error| {
            error.value = text.to_string();
            usage_error(error)
        })
    }
}

/// Angles in degrees: a turntable or half-vector azimuth, either way round.
pub(crate) const AZIMUTH_DEG: Real = Real(request::AZIMUTH_DEG);
/// phi_d of MERL's half-difference angles (folded by reciprocity to [0, 180]).
pub(crate) const PHI_D_DEG: Real = Real::from_to(0.0, 180.0, "degrees");
/// theta_d, from the half vector: below the horizon at 90.
pub(crate) const THETA_D_DEG: Real = Real::from_to(0.0, 89.5, "degrees");
/// A theta_h position.
pub(crate) const THETA_H_DEG: Real = Real::from_to(0.0, 90.0, "degrees");
/// A step of a grid in degrees (theta_d, phi_d).
pub(crate) const GRID_STEP_DEG: Real = Real(request::GRID_STEP_DEG);
/// An elevation from the normal that bounds the device's reach.
pub(crate) const ELEVATION_DEG: Real = Real::above(0.0, 90.0, "degrees");
/// The sample's tilt on the turntable (a misalignment to simulate).
pub(crate) const TILT_DEG: Real = Real(request::TILT_DEG);
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
pub(crate) const THETA_H_SAMPLES: Count = Count(request::THETA_H_SAMPLES);
/// Samples of a probe (the paper: 90).
pub(crate) const PROBE_SAMPLES: Count = Count(request::PROBE_SAMPLES);
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
    fn the_grid_ranges_are_the_librarys() {
        assert_eq!(PROBE_SAMPLES.0, request::PROBE_SAMPLES);
        assert_eq!(ELEVATION_DEG.0.words(), "degrees above 0 and at most 90");
        assert_eq!(
            ThetaDStepsArg::words(),
            "degrees from 0.5 to 90, or STEP:GRAZING@FROM with both steps from 0.5 to 90 and \
             FROM from 0 to below 90"
        );
    }
}
