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
use specula_formats::convert;

/// A real number in a [`RealRange`], as an option's parser.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Real(RealRange);

/// A whole number in a [`CountRange`], as an option's parser.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Count(CountRange);

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

// The library's ranges ([`specula_core::request`], [`specula_visual::render`]), as parsers.
pub(crate) const AZIMUTH_DEG: Real = Real(request::AZIMUTH_DEG);
pub(crate) const PHI_D_DEG: Real = Real(request::PHI_D_DEG);
pub(crate) const THETA_D_DEG: Real = Real(request::THETA_D_DEG);
pub(crate) const THETA_H_DEG: Real = Real(request::THETA_H_DEG);
pub(crate) const GRID_STEP_DEG: Real = Real(request::GRID_STEP_DEG);
pub(crate) const ELEVATION_DEG: Real = Real(request::ELEVATION_DEG);
pub(crate) const TILT_DEG: Real = Real(request::TILT_DEG);
pub(crate) const SAMPLING_K: Real = Real(request::SAMPLING_K);
pub(crate) const PHI_H_STEP_DEG: Real = Real(request::PHI_H_STEP_DEG);
pub(crate) const LIGHT_ELEVATION_DEG: Real = Real(request::LIGHT_ELEVATION_DEG);
pub(crate) const REFLECTANCE: Real = Real(request::REFLECTANCE);
pub(crate) const FLARE_STRENGTH_SR: Real = Real(request::FLARE_STRENGTH_SR);
pub(crate) const TIMEOUT_S: Real = Real(request::TIMEOUT_S);
pub(crate) const SPEEDUP: Real = Real(request::SPEEDUP);
pub(crate) const RESOLUTION_DEG: Real = Real(request::RESOLUTION_DEG);
pub(crate) const EXPOSURE_STOPS: Real = Real(request::EXPOSURE_STOPS);
pub(crate) const THETA_H_SAMPLES: Count = Count(request::THETA_H_SAMPLES);
pub(crate) const PROBE_SAMPLES: Count = Count(request::PROBE_SAMPLES);
pub(crate) const MAX_HOURS: Real = Real(request::MAX_HOURS);
pub(crate) const MAX_SAMPLES: Count = Count(request::MAX_SAMPLES);
pub(crate) const TARGET_UNCERTAINTY_PERCENT: Real = Real(request::TARGET_UNCERTAINTY_PERCENT);
pub(crate) const FAILURES: Count = Count(request::FAILURES);
pub(crate) const ROTATIONS: Count = Count(request::ROTATIONS);
pub(crate) const IMAGE_PX: Count = Count(specula_visual::render::IMAGE_PX);
pub(crate) const SAMPLES_PER_PIXEL: Count = Count(specula_visual::render::SAMPLES_PER_PIXEL);
/// Incident elevations, nodes per axis of the microfacet distribution and samples per axis
/// of the RGB grid of a written RGL file.
pub(crate) const RGL_ELEVATIONS: Count = Count(convert::RGL_ELEVATIONS);
pub(crate) const RGL_NDF_SIZE: Count = Count(convert::RGL_NDF_SIZE);
pub(crate) const RGL_SAMPLE_SIZE: Count = Count(convert::RGL_SAMPLE_SIZE);

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
