//! How long a stage will take: the one time model behind `specula plan`'s `predicted_hours`,
//! the step times a session journals with its plan (the ETA during a run starts from them and
//! is corrected by the times observed), the summary's `predicted_main_hours` and the
//! report's "planned duration".
//!
//! Moves and settling come from the device's axes ([`specula_acquisition::timing`]). The
//! capture at each sample follows the HDR scheme the measurement uses:
//! - [`HdrChoice::Bracket`]: the device file's fixed bracket at every sample;
//! - [`HdrChoice::Predicted`]: one frame at the exposure [`HdrCapturer::choose`] picks for
//!   the sample's predicted brightness (the probe's model through the calibration, as the
//!   run predicts it), plus the light changes
//!   ([`specula_acquisition::timing::predicted_capture_times_s`]). Retakes (a prediction
//!   off by more than the sensor's range) are rare and not counted.
//!
//! Before a probe exists (`specula plan`) the brightness is an assumption:
//! [`assumed_brightness`] takes a material's BRDF along the probe's column, through the
//! simulated camera's exact calibration.

use crate::ideal::{exact_calibration, simulated_instrument};
use crate::journal::HdrChoice;
use crate::predict::{Predictor, ProbeModel};
use crate::workflow_error::WorkflowError;
use specula_acquisition::device::Device;
use specula_acquisition::hdr::{Exposure, HdrCapturer, HdrSettings};
use specula_acquisition::plan::Plan;
use specula_acquisition::simulator::SimulatorConfig;
use specula_acquisition::timing::predicted_capture_times_s;
use specula_core::{Brdf, ProbePoint, ProbeSpec};
use std::sync::Arc;

/// What predicted exposures are chosen from: the brightness predictor and the capturer's
/// settings (light levels, exposure range, target level).
pub struct PredictedExposures<'a> {
    /// Predicts each sample's brightest-channel rate.
    pub predictor: &'a Predictor,
    /// Chooses the exposure for a predicted rate.
    pub capturer: &'a HdrCapturer,
}

/// Prices the capture of every measured sample of `plan` for `hdr` and retimes it. With
/// [`HdrChoice::Bracket`], or when `predicted` cannot predict every sample (no probe model),
/// the plan keeps the device's bracket.
pub fn price_captures(
    plan: &mut Plan,
    device: &Device,
    hdr: HdrChoice,
    predicted: &PredictedExposures,
) {
    if hdr == HdrChoice::Bracket {
        return;
    }
    let exposures: Option<Vec<Exposure>> = plan
        .measured()
        .map(|(sample, _)| {
            let rate = predicted.predictor.model_rate_at(sample.hd)?;
            Some(predicted.capturer.choose(rate))
        })
        .collect();
    if let Some(exposures) = exposures {
        plan.set_capture_times_s(&predicted_capture_times_s(&exposures, &device.capture));
    }
}

/// A brightness to price predicted exposures with before any probe: `truth`'s BRDF along the
/// probe's column at `phi_h_deg` (the probe [`ProbeSpec::paper`] takes), through the exact
/// calibration of the simulated `device`'s camera, and the capturer the simulated device
/// would use.
pub fn assumed_brightness(
    device: &Device,
    truth: Arc<dyn Brdf>,
    phi_h_deg: f64,
) -> Result<(Predictor, HdrCapturer), WorkflowError> {
    let info = simulated_instrument(device.clone(), truth.clone(), 0, true)
        .info()
        .map_err(WorkflowError::device(
            "cannot describe the simulated device",
        ))?;
    let config = SimulatorConfig::new(0, device);
    let calibration = exact_calibration(&config.camera, &info.model);
    let probe = ProbeSpec {
        phi_h_deg,
        ..ProbeSpec::paper()
    };
    let points: Vec<ProbePoint> = probe
        .theta_h_deg()
        .into_iter()
        .filter_map(|theta_h| {
            let value = truth.eval_half_diff(probe.half_diff(theta_h))?;
            Some(ProbePoint::new(theta_h, value))
        })
        .collect();
    let capturer = HdrCapturer::new(HdrSettings::for_device(&info), calibration.noise);
    let predictor = Predictor::new(calibration, ProbeModel::new(&points));
    Ok((predictor, capturer))
}

/// The material whose brightness `specula plan` assumes for predicted exposures when told no
/// other: the paper's polished silver, a typical specular sample.
pub const ASSUMED_MATERIAL: &str = "silver-925";

/// Prices the captures of `plans` before any probe, as `specula plan` does, and says in words
/// what it assumed: with `truth`, predicted exposures for its brightness
/// ([`assumed_brightness`]); without, the device's bracket at every sample.
pub fn price_before_probe(
    plans: &mut [&mut Plan],
    device: &Device,
    truth: Option<Arc<dyn Brdf>>,
    phi_h_deg: f64,
) -> Result<String, WorkflowError> {
    let Some(truth) = truth else {
        return Ok(format!(
            "the device's bracket at every sample ({:.2} s each)",
            device.capture.duration_s()
        ));
    };
    let name = truth.name();
    let (predictor, capturer) = assumed_brightness(device, truth, phi_h_deg)?;
    let predicted = PredictedExposures {
        predictor: &predictor,
        capturer: &capturer,
    };
    for plan in plans.iter_mut() {
        price_captures(plan, device, HdrChoice::Predicted, &predicted);
    }
    Ok(format!(
        "predicted exposures for the brightness of {name} (its probe column through the \
         simulated camera's exact calibration)"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn predicted_exposures_price_one_frame_a_sample_and_the_bracket_keeps_the_device_file() {
        let device = Device::utia();
        let grid = |device: &Device| {
            Plan::from_grid(
                &[1.0, 10.0, 40.0],
                &[30.0, 60.0],
                &[0.0, 90.0],
                45.0,
                device,
            )
        };
        let mut bracket = grid(&device);
        let before = bracket.clone();
        let truth: Arc<dyn Brdf> = Arc::new(specula_core::materials::preset("silver-925").unwrap());
        price_before_probe(&mut [&mut bracket], &device, None, 45.0).unwrap();
        assert_eq!(bracket, before);

        let mut predicted = grid(&device);
        let said = price_before_probe(&mut [&mut predicted], &device, Some(truth), 45.0).unwrap();
        assert!(said.contains("silver-925"), "{said}");
        let (_, capturer) = assumed_brightness(
            &device,
            Arc::new(specula_core::materials::preset("silver-925").unwrap()),
            45.0,
        )
        .unwrap();
        let (longest_s, frame_s) = (
            capturer.settings.exposure_range_s.1,
            device.capture.readout_s,
        );
        let steps = predicted.steps();
        assert!(!steps.is_empty());
        for step in &steps {
            assert!(step.capture_s >= frame_s, "{step:?}");
            assert!(
                step.capture_s <= frame_s + longest_s + device.capture.light_change_s,
                "{step:?}"
            );
        }
        let motion = |p: &Plan| p.steps().iter().map(|s| s.move_s + s.settle_s).sum::<f64>();
        assert_eq!(motion(&predicted), motion(&before));
    }
}
