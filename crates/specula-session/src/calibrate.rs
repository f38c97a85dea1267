//! The calibration behind `specula calibrate`, the same on any device: the simulator in
//! process, or a device behind the driver protocol (`device serve`, a lab's adapter).
//!
//! Each reference target is mounted in turn through a mount function: the device's own
//! [`Instrument::mount`] when it offers one (a robot, a simulator, an adapter's own prompt),
//! else the operator's (the caller's: a prompt on the terminal). In order: the white
//! reference (dark frames, the photon transfer curve and the gains to 1/sr), the 24
//! ColorChecker patches (the colour matrix), the reference mirror (the instrument's
//! response), and the sample (the check measurement).

use crate::workflow_error::WorkflowError;
use specula_acquisition::calibration::response::{measure_response, ResponseOptions};
use specula_acquisition::calibration::truth_check::{
    measure_check, CheckValue, TRUTH_CHECK_THETA_H_DEG,
};
use specula_acquisition::calibration::white::{CertificateError, WhiteCertificate};
use specula_acquisition::calibration::CalibrationError;
use specula_acquisition::calibration::{calibrate, Calibration, CalibrationOptions};
use specula_acquisition::device::Device;
use specula_acquisition::hdr::{HdrCapturer, HdrSettings};
use specula_acquisition::instrument::{Instrument, InstrumentError, MountOutcome, MountTarget};
use specula_acquisition::simulator::sample::{MountedSample, Tilt};
use specula_acquisition::simulator::{Simulator, SimulatorConfig};
use specula_core::range::RangeError;
use specula_core::request::REFLECTANCE;
use specula_core::Brdf;
use std::path::PathBuf;
use std::sync::Arc;

/// What a calibration is asked for (`specula calibrate`'s options).
#[derive(Debug, Clone)]
pub struct CalibrateRequest {
    /// Reflectance of the white reference (0.99 for a Spectralon tile), in [`REFLECTANCE`].
    pub white_reflectance: f64,
    /// The white reference's certificate (TOML), replacing `white_reflectance` per channel.
    pub white_certificate: Option<PathBuf>,
    /// Seed of the simulated device: its positioning errors and its noise.
    pub seed: u64,
    /// Where to write the calibration (TOML).
    pub out: PathBuf,
}

/// Why a calibration is refused or fails.
#[derive(Debug, thiserror::Error)]
pub enum CalibrateError {
    /// A value outside its range.
    #[error(transparent)]
    Range(#[from] RangeError),
    /// The white reference's certificate cannot be read.
    #[error(transparent)]
    Certificate(#[from] CertificateError),
    /// The calibration failed.
    #[error(transparent)]
    Workflow(#[from] WorkflowError),
    /// The calibration cannot be written.
    #[error(transparent)]
    Save(#[from] CalibrationError),
}

impl CalibrateRequest {
    /// Checks the white reference's reflectance (the error names `white_reflectance`; the
    /// CLI's parser says the same words after `--white-reflectance`).
    pub fn validate(&self) -> Result<(), RangeError> {
        REFLECTANCE
            .check("white_reflectance", self.white_reflectance)
            .map(|_| ())
    }

    /// The calibration's options: the reflectance, or the certificate's values.
    fn options(&self) -> Result<CalibrationOptions, CalibrateError> {
        Ok(CalibrationOptions {
            white_reflectance: self.white_reflectance,
            white_certificate: self
                .white_certificate
                .as_deref()
                .map(WhiteCertificate::load)
                .transpose()?,
            ..CalibrationOptions::default()
        })
    }

    /// The simulated `device` with `truth` on its turntable (untilted), seeded by the request.
    pub fn simulator(&self, truth: Arc<dyn Brdf>, device: &Device) -> Simulator {
        let config = SimulatorConfig::new(self.seed, device);
        let sample = MountedSample::new(truth.name(), truth, Tilt::default());
        Simulator::new(device.clone(), sample, config)
    }
}

/// Calibrates `instrument` as `request` asks ([`calibrate_device`]) and writes the
/// calibration to `request.out`.
pub fn run_calibrate(
    request: &CalibrateRequest,
    instrument: &mut dyn Instrument,
    operator: &mut dyn FnMut(&MountTarget) -> Result<(), InstrumentError>,
    device: &Device,
    step: &mut dyn FnMut(&str),
) -> Result<CalibrationRun, CalibrateError> {
    request.validate()?;
    let options = request.options()?;
    let run = calibrate_device(instrument, operator, device, &options, step)?;
    run.calibration.save(&request.out)?;
    Ok(run)
}

/// A calibration and the check measurement made with it.
#[derive(Debug, Clone, PartialEq)]
pub struct CalibrationRun {
    /// The calibration, with the measured response.
    pub calibration: Calibration,
    /// The sample measured with it at the check's geometries
    /// ([`specula_acquisition::calibration::truth_check`]).
    pub checks: Vec<CheckValue>,
}

/// Calibrates `instrument` (see the module documentation). Each target is mounted by the
/// device when it can, else by `operator` (which returns once the target is in place);
/// `step` hears each step in words.
pub fn calibrate_device(
    instrument: &mut dyn Instrument,
    operator: &mut dyn FnMut(&MountTarget) -> Result<(), InstrumentError>,
    device: &Device,
    options: &CalibrationOptions,
    step: &mut dyn FnMut(&str),
) -> Result<CalibrationRun, WorkflowError> {
    let mut mount =
        |instrument: &mut dyn Instrument, target: &MountTarget| match instrument.mount(target)? {
            MountOutcome::Mounted => Ok(()),
            MountOutcome::ByOperator => operator(target),
        };
    step("calibrating: dark frames, photon transfer and the white reference; the ColorChecker");
    let mut calibration = calibrate(instrument, &mut mount, options)
        .map_err(|cause| WorkflowError::Calibration { cause })?;
    step("calibrating: the response, a mirror across the light");
    let info = instrument.info()?;
    let mut hdr = HdrCapturer::new(HdrSettings::for_device(&info), calibration.noise);
    let fit = measure_response(
        instrument,
        &mut mount,
        &mut hdr,
        &calibration,
        &device.response(),
        &ResponseOptions::default(),
    )
    .map_err(|cause| WorkflowError::Response { cause })?;
    calibration.response = Some(fit);
    step("calibrating: a check measurement of the sample");
    mount(instrument, &MountTarget::Sample)?;
    let checks = measure_check(instrument, device, &calibration, &TRUTH_CHECK_THETA_H_DEG)?;
    Ok(CalibrationRun {
        calibration,
        checks,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reflectance_out_of_range_is_refused_before_any_capture() {
        let dir = tempfile::tempdir().unwrap();
        let request = CalibrateRequest {
            white_reflectance: 1.5,
            white_certificate: None,
            seed: 1,
            out: dir.path().join("calibration.toml"),
        };
        let device = Device::utia();
        let truth: Arc<dyn Brdf> = Arc::new(specula_core::materials::preset("chrome").unwrap());
        let mut simulator = request.simulator(truth, &device);
        let mut operator = |_: &MountTarget| -> Result<(), InstrumentError> {
            panic!("nothing is mounted for a refused request")
        };
        let error = run_calibrate(
            &request,
            &mut simulator,
            &mut operator,
            &device,
            &mut |_| {},
        )
        .unwrap_err()
        .to_string();
        assert_eq!(
            error,
            "white_reflectance 1.5: expected a fraction above 0 and at most 1"
        );
        assert!(!request.out.exists());
    }
}
