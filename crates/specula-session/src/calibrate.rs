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
use specula_acquisition::calibration::{calibrate, Calibration, CalibrationOptions};
use specula_acquisition::device::Device;
use specula_acquisition::hdr::{HdrCapturer, HdrSettings};
use specula_acquisition::instrument::{Instrument, InstrumentError, MountOutcome, MountTarget};

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
