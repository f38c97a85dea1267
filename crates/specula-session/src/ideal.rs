//! The ideal simulated device of `specula measure --ideal`: the simulator's geometry (arms,
//! occlusion, the light's disk, the clock) with the axes exactly where they are told and a
//! noise-free camera, and its exact calibration. For comparing sampling and reconstruction
//! methods without the noise of one particular run. [`simulated_instrument`] is the
//! simulated device `specula device serve` offers, ideal or not.

use specula_acquisition::calibration::Calibration;
use specula_acquisition::device::Device;
use specula_acquisition::instrument::{
    Capture, Instrument, InstrumentError, InstrumentInfo, MountOutcome, MountTarget,
};
use specula_acquisition::kinematics::AxisPositions;
use specula_acquisition::simulator::camera::CameraModel;
use specula_acquisition::simulator::sample::{MountedSample, Tilt};
use specula_acquisition::simulator::{Simulator, SimulatorConfig};
use specula_core::Brdf;
use std::sync::Arc;

/// A simulator whose captures are the expected values of its camera (no photon, read or
/// dark noise). Build the simulator with a zero positioning error and an untilted sample.
pub struct NoiselessSimulator {
    inner: Simulator,
    commanded: AxisPositions,
    light_level: f64,
}

impl NoiselessSimulator {
    /// Wraps `inner`, starting at its device's park position with the light at full power.
    pub fn new(inner: Simulator) -> Self {
        let commanded = inner.device().park_axes();
        Self {
            inner,
            commanded,
            light_level: 1.0,
        }
    }

    /// The wrapped simulator.
    pub fn simulator(&self) -> &Simulator {
        &self.inner
    }
}

impl Instrument for NoiselessSimulator {
    fn home(&mut self) -> Result<AxisPositions, InstrumentError> {
        let read_back = self.inner.home()?;
        self.commanded = self.inner.device().park_axes();
        Ok(read_back)
    }

    fn move_to(&mut self, target: &AxisPositions) -> Result<AxisPositions, InstrumentError> {
        let read_back = self.inner.move_to(target)?;
        self.commanded = *target;
        Ok(read_back)
    }

    fn set_light(&mut self, level: f64) -> Result<(), InstrumentError> {
        self.inner.set_light(level)?;
        self.light_level = level;
        Ok(())
    }

    fn capture(&mut self, exposure_s: f64, with_pixels: bool) -> Result<Capture, InstrumentError> {
        // The simulator's own capture checks the exposure and advances its clock.
        let mut capture = self.inner.capture(exposure_s, with_pixels)?;
        let camera = &self.inner.config().camera;
        let radiance = self.inner.scene_radiance(&self.commanded) * self.light_level;
        let rate = camera.photo_rate_e_s(radiance);
        let white = camera.white_level_dn();
        for (c, rate_e_s) in rate.iter().enumerate() {
            let electrons =
                (exposure_s * (rate_e_s + camera.dark_current_e_s)).min(camera.full_well_e);
            let raw = (camera.black_level_dn + camera.gain_dn_per_e * electrons).min(white);
            capture.mean_raw[c] = raw;
            capture.saturated_fraction[c] = if raw >= white { 1.0 } else { 0.0 };
        }
        if let Some(pixels) = capture.pixels.as_mut() {
            let mean = capture.mean_raw.map(|v| v as f32);
            pixels.iter_mut().for_each(|p| *p = mean);
        }
        Ok(capture)
    }

    fn info(&mut self) -> Result<InstrumentInfo, InstrumentError> {
        let mut info = self.inner.info()?;
        info.model = format!("{} (ideal: noise-free, exact positioning)", info.model);
        Ok(info)
    }

    fn simulated_clock_s(&self) -> Option<f64> {
        self.inner.simulated_clock_s()
    }

    fn mount(&mut self, target: &MountTarget) -> Result<MountOutcome, InstrumentError> {
        self.inner.mount(target)
    }
}

/// The simulated `device` with `truth` mounted untilted, as `specula device serve` offers
/// it: with `ideal` a [`NoiselessSimulator`] with exact positioning, else the simulator with
/// the noise and positioning error that `seed` picks.
pub fn simulated_instrument(
    device: Device,
    truth: Arc<dyn Brdf>,
    seed: u64,
    ideal: bool,
) -> Box<dyn Instrument> {
    let mut config = SimulatorConfig::new(seed, &device);
    if ideal {
        config.positioning.sigma_deg = 0.0;
    }
    let sample = MountedSample::new(truth.name(), truth, Tilt::default());
    let simulator = Simulator::new(device, sample, config);
    if ideal {
        Box::new(NoiselessSimulator::new(simulator))
    } else {
        Box::new(simulator)
    }
}

/// The calibration that inverts a simulated camera exactly: its channel gains and the
/// inverse of its colour crosstalk (the response is not measured).
pub fn exact_calibration(camera: &CameraModel, device: &str) -> Calibration {
    let gain = camera.responsivity_e_s.map(|r| r * camera.gain_dn_per_e);
    let crosstalk = glam::DMat3::from_cols_array_2d(&camera.crosstalk).transpose();
    let inverse = crosstalk.inverse();
    Calibration {
        device: device.to_string(),
        white_reflectance: 1.0,
        white_certificate: None,
        light_elevation_deg: 45.0,
        gain_dn_s_per_sr: gain,
        colour_matrix: inverse.transpose().to_cols_array_2d(),
        colour_rms_error: 0.0,
        colour_reference: "exact (the simulated camera's own crosstalk)".into(),
        noise: camera.noise_model(),
        response: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::Rgb;

    #[test]
    fn the_exact_calibration_inverts_the_camera() {
        let camera = CameraModel::default();
        let calibration = exact_calibration(&camera, "sim");
        let f = Rgb::new(0.3, 2.0, 40.0);
        let cos_i = 0.6;
        let rate = camera.signal_rate_dn_s(f * cos_i);
        let back = calibration.brdf(rate, cos_i);
        assert!((back - f).length() < 1e-9 * f.length(), "{back} vs {f}");
    }

    #[test]
    fn the_ideal_instrument_repeats_a_capture_exactly_and_the_noisy_one_does_not() {
        let truth = Arc::new(specula_core::materials::preset("green-paint").unwrap());
        let twice = |ideal: bool| {
            let mut instrument = simulated_instrument(Device::utia(), truth.clone(), 3, ideal);
            let first = instrument.capture(0.01, false).unwrap();
            let second = instrument.capture(0.01, false).unwrap();
            (first, second)
        };
        let (a, b) = twice(true);
        assert_eq!(a, b);
        let (a, b) = twice(false);
        assert_ne!(a.mean_raw, b.mean_raw);
    }
}
