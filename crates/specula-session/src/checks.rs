//! The alignment and orientation checks (paper 4.2, 4.3) a session runs once before its
//! probe, each retried after a fault another try may cure, and their record.

use crate::engine::{is_retryable, EngineSettings};
use crate::journal::{ChecksRecord, Journal, MeasureSettings};
use crate::observer::Observer;
use crate::workflow_error::WorkflowError;
use specula_acquisition::checks::alignment::{check_alignment, AlignmentSettings};
use specula_acquisition::checks::orientation::{check_orientation, OrientationSettings};
use specula_acquisition::checks::CheckError;
use specula_acquisition::device::Device;
use specula_acquisition::hdr::HdrCapturer;
use specula_acquisition::instrument::{Instrument, InstrumentError};

/// Alignment and orientation (paper 4.2, 4.3), once per session.
pub(crate) fn run_checks(
    journal: &mut Journal,
    instrument: &mut dyn Instrument,
    hdr: &mut HdrCapturer,
    device: &Device,
    settings: &MeasureSettings,
    observer: &mut dyn Observer,
) -> Result<ChecksRecord, WorkflowError> {
    if let Some(stored) = journal.record::<ChecksRecord>()? {
        return Ok(stored);
    }
    let clock = |i: &dyn Instrument| i.simulated_clock_s();
    let started = (clock(instrument), std::time::Instant::now());
    let alignment_settings = AlignmentSettings::default();
    observer.step(&format!(
        "alignment check: the highlight at {} turntable rotations",
        alignment_settings.rotations
    ));
    instrument
        .home()
        .map_err(WorkflowError::device("homing the device"))?;
    let alignment = with_retries(journal, instrument, hdr, "alignment check", |i, h| {
        check_alignment(i, h, &alignment_settings)
    })?;
    let (tilt_deg, tilt_azimuth_deg, alignment) = match alignment {
        Ok(report) => {
            journal.put_record(&report)?;
            let advice = report.adjustment(device.accuracy_deg);
            (
                Some(report.fit.tilt_deg),
                Some(report.fit.azimuth_deg),
                advice,
            )
        }
        Err(e) => (None, None, format!("inconclusive: {e}")),
    };
    observer.step(&format!("alignment: {alignment}"));
    observer.step("orientation check: rings of phi_h for the scratch lobe");
    let orientation_settings = OrientationSettings {
        planned_phi_h_deg: settings.grid.phi_h_deg,
        ..OrientationSettings::default()
    };
    let orientation = with_retries(journal, instrument, hdr, "orientation check", |i, h| {
        check_orientation(i, h, device, &orientation_settings)
    })?;
    let (anisotropic, plan_phi_h_deg, orientation) = match orientation {
        Ok(report) => {
            journal.put_record(&report)?;
            if report.planned_is_clean {
                let what = if report.anisotropic {
                    "anisotropic, but"
                } else {
                    "isotropic:"
                };
                (
                    Some(report.anisotropic),
                    settings.grid.phi_h_deg,
                    format!("{what} phi_h {} deg is clean", settings.grid.phi_h_deg),
                )
            } else {
                let chosen = report.recommended_phi_h_deg;
                let message = format!(
                    "scratch lobe at phi_h {} deg: measuring at phi_h {chosen} deg instead (turn the sample by {:.1} deg to keep {})",
                    settings.grid.phi_h_deg,
                    report.turn_sample_deg(),
                    settings.grid.phi_h_deg
                );
                (Some(true), chosen, message)
            }
        }
        Err(e) => (None, settings.grid.phi_h_deg, format!("inconclusive: {e}")),
    };
    observer.step(&format!("orientation: {orientation}"));
    let device_s = match (started.0, clock(instrument)) {
        (Some(a), Some(b)) => b - a,
        _ => started.1.elapsed().as_secs_f64(),
    };
    let record = ChecksRecord {
        tilt_deg,
        tilt_azimuth_deg,
        alignment,
        anisotropic,
        plan_phi_h_deg,
        orientation,
        device_s,
    };
    journal.put_record(&record)?;
    Ok(record)
}

/// Runs a check with the acquisition's retries: after a fault that another try may cure
/// ([`is_retryable`]; the axes homed after a motor fault) the check starts again, up to the
/// engine's [`EngineSettings::max_attempts`] tries, each fault journaled. A check that still
/// cannot run is an error (the user may skip the checks); one that ran but found nothing
/// (no highlight, say) comes back as `Ok(Err(..))`, recorded as inconclusive.
fn with_retries<T>(
    journal: &Journal,
    instrument: &mut dyn Instrument,
    hdr: &mut HdrCapturer,
    what: &str,
    mut check: impl FnMut(&mut dyn Instrument, &mut HdrCapturer) -> Result<T, CheckError>,
) -> Result<Result<T, CheckError>, WorkflowError> {
    let max_attempts = EngineSettings::default().max_attempts;
    let mut attempts = 0;
    loop {
        attempts += 1;
        let error = match check(instrument, hdr) {
            Err(CheckError::Instrument(error)) => error,
            done => return Ok(done),
        };
        journal.log_event("fault", &format!("{what} try {attempts}: {error}"))?;
        if !is_retryable(&error) || attempts >= max_attempts {
            return Err(WorkflowError::Check {
                check: what.to_string(),
                cause: error,
                attempts,
            });
        }
        hdr.forget_light_level();
        if matches!(error, InstrumentError::MotorFault(_)) {
            instrument.home().map_err(WorkflowError::device(format!(
                "{what}: homing the device after a motor fault"
            )))?;
            journal.log_event("recovered", "homed the axes")?;
        }
    }
}
