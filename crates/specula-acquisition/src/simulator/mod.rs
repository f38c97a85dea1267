//! A simulated gonioreflectometer: the paper's device (4.1) with a ground-truth BRDF on the
//! turntable, realistic enough that the practical problems of 4.3 show up.
//!
//! A capture is computed at the *actual* geometry (the commanded axes plus their repeatable
//! positioning error, [`sample::PositioningError`], and the sample's tilt,
//! [`sample::Tilt`]): the radiance factor `f_r cos(theta_i)` integrated over the instrument's
//! response (the light's disk, the camera's pupil and the measured area,
//! [`crate::response`]), times the light level, plus the lens flare's ghost where it falls
//! into the region of interest ([`optics::LensFlare`]), seen by a 12-bit camera with noise,
//! saturation and colour crosstalk ([`camera::CameraModel`]). An arm in the camera's view or
//! in the light's beam ([`crate::occlusion`]) makes the capture dark; a move into a
//! collision fails with a motor fault.
//!
//! **Determinism.** The noise of a capture comes from a random stream keyed by the seed, the
//! mounted sample's name, the commanded axes, the exposure, the light level and how many
//! times that same capture was taken since the last move ([`rng`]). The same measurement
//! gives the same numbers whatever was measured before, and after a restart.
//!
//! **Time.** A simulated clock advances as the device would take time: moves and settling
//! from [`TimeModel`], the LED's settling after a change of level, and each frame's exposure
//! plus read-out (the device file's `[capture]` table). [`Instrument::simulated_clock_s`]
//! reports it.

pub mod camera;
pub mod optics;
pub mod rng;
pub mod sample;

use crate::calibration::{colorchecker, response::reference_mirror, DiffuseTarget};
use crate::device::Device;
use crate::hdr::{HdrCapturer, HdrSettings};
use crate::instrument::{
    Capture, Instrument, InstrumentError, InstrumentInfo, MountOutcome, MountTarget,
};
use crate::kinematics::{AxisPositions, AXIS_NAMES, CAMERA_AXIS};
use crate::occlusion::{blockage, Blockage};
use crate::response::InstrumentResponse;
use crate::timing::TimeModel;
use camera::CameraModel;
use glam::DVec3;
use optics::{Ghost, LensFlare};
use sample::{MountedSample, PositioningError};
use specula_core::capture::{self, CaptureNode};
use std::collections::HashMap;

/// Everything about the simulated device that the device file does not say.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulatorConfig {
    /// Picks the device's positioning errors and the noise of every capture.
    pub seed: u64,
    /// The sensor: its noise and colour filters.
    pub camera: CameraModel,
    /// Light levels offered for HDR, fractions of full power, highest first. `set_light`
    /// accepts any level in `[0, 1]`; 0 is off (dark frames).
    pub light_levels: Vec<f64>,
    /// Shortest and longest exposure, seconds.
    pub exposure_range_s: (f64, f64),
    /// What a capture integrates (the device's own, [`Device::response`], by default).
    pub response: InstrumentResponse,
    /// Quadrature nodes of the response per capture: enough to integrate a mirror
    /// (alpha 0.001) over the disk smoothly.
    pub response_nodes: usize,
    /// The repeatable positioning error of the axes.
    pub positioning: PositioningError,
    /// The lens flare, if any.
    pub flare: Option<LensFlare>,
}

/// Quadrature nodes of the response per simulated capture ([`SimulatorConfig::new`]).
pub const SIMULATOR_RESPONSE_NODES: usize = 4096;

impl SimulatorConfig {
    /// The defaults for a device: its accuracy as the positioning error's standard
    /// deviation, no flare.
    pub fn new(seed: u64, device: &Device) -> Self {
        Self {
            seed,
            camera: CameraModel::default(),
            light_levels: vec![1.0, 0.1, 0.01],
            exposure_range_s: (2e-5, 8.0),
            response: device.response(),
            response_nodes: SIMULATOR_RESPONSE_NODES,
            positioning: PositioningError {
                sigma_deg: device.accuracy_deg,
            },
            flare: None,
        }
    }
}

/// The simulated gonioreflectometer (see the module documentation).
pub struct Simulator {
    device: Device,
    time: TimeModel,
    config: SimulatorConfig,
    nodes: Vec<CaptureNode>,
    sample: MountedSample,
    /// The sample to measure, which [`MountTarget::Sample`] puts back.
    under_test: MountedSample,
    commanded: AxisPositions,
    light_level: f64,
    clock_s: f64,
    /// Captures taken since the last move, by (exposure, level) key.
    repeats: HashMap<(u64, u64), u64>,
    calls: u64,
    captures: u64,
    /// Faults to raise: at which call, which error.
    faults: Vec<(u64, InstrumentError)>,
}

impl Simulator {
    /// A device with `sample` mounted, parked, the light at full power.
    pub fn new(device: Device, sample: MountedSample, config: SimulatorConfig) -> Self {
        let nodes = config.response.capture_nodes(config.response_nodes);
        Self {
            time: TimeModel::from_device(&device),
            commanded: device.park_axes(),
            device,
            config,
            nodes,
            under_test: sample.clone(),
            sample,
            light_level: 1.0,
            clock_s: 0.0,
            repeats: HashMap::new(),
            calls: 0,
            captures: 0,
            faults: Vec::new(),
        }
    }

    /// The simulated `device` with `sample` mounted (`seed` picks its positioning errors and
    /// noise; `flare` adds a lens flare), and an HDR capturer for it that uses the
    /// simulator's own sensor model: what the practical checks (4.2, 4.3) run on, without a
    /// calibration (`specula calibrate` measures the sensor model on a device).
    pub fn with_hdr(
        device: Device,
        sample: MountedSample,
        seed: u64,
        flare: Option<LensFlare>,
    ) -> Result<(Self, HdrCapturer), InstrumentError> {
        let mut config = SimulatorConfig::new(seed, &device);
        config.flare = flare;
        let mut simulator = Self::new(device, sample, config);
        let settings = HdrSettings::for_device(&simulator.info()?);
        let noise = simulator.config().camera.noise_model();
        Ok((simulator, HdrCapturer::new(settings, noise)))
    }

    /// Puts another sample (a reference target) on the turntable, as the operator would.
    pub fn mount_sample(&mut self, sample: MountedSample) {
        self.sample = sample;
        self.repeats.clear();
    }

    /// The sample on the turntable.
    pub fn sample(&self) -> &MountedSample {
        &self.sample
    }

    /// The device file the simulator was made from.
    pub fn device(&self) -> &Device {
        &self.device
    }

    /// Everything else about the simulated device.
    pub fn config(&self) -> &SimulatorConfig {
        &self.config
    }

    /// Frames captured so far.
    pub fn capture_count(&self) -> u64 {
        self.captures
    }

    /// Makes the `call`-th call to the device from now (1 = the next) fail with `error`.
    pub fn schedule_fault(&mut self, call: u64, error: InstrumentError) {
        self.faults.push((self.calls + call, error));
    }

    /// Where the axes really are for a command.
    pub fn actual_axes(&self, commanded: &AxisPositions) -> AxisPositions {
        self.config.positioning.actual(self.config.seed, commanded)
    }

    /// The noise-free radiance factor in the region of interest at full light for a command,
    /// 1/sr, without flare: `f_r cos(theta_i)` at the actual geometry integrated over the
    /// response; zero when an arm blocks the view or the beam.
    pub fn scene_radiance(&self, commanded: &AxisPositions) -> DVec3 {
        let actual = self.actual_axes(commanded);
        if blockage(&self.device, &actual).is_some() {
            return DVec3::ZERO;
        }
        let to_turntable =
            |lab: DVec3| specula_core::geometry::rotate_z(lab, -actual.turntable_rad);
        let wi = to_turntable(actual.light_direction());
        let wo = to_turntable(actual.camera_direction());
        capture::integrate(&self.nodes, wi, wo, |a, b| self.sample.reflected(a, b))
    }

    /// The noise-free black-subtracted raw rate of each channel at full light, DN/s: what an
    /// HDR measurement estimates.
    pub fn expected_rate_dn_s(&self, commanded: &AxisPositions) -> [f64; 3] {
        self.config
            .camera
            .signal_rate_dn_s(self.scene_radiance(commanded))
    }

    /// The lens flare's ghost in the region for a command at a light level, if any.
    pub fn ghost(&self, commanded: &AxisPositions, level: f64) -> Option<Ghost> {
        let flare = self.config.flare.as_ref()?;
        let actual = self.actual_axes(commanded);
        flare.ghost(
            actual.camera_direction() * self.device.camera.distance_m,
            CAMERA_AXIS,
            actual.light_direction() * self.device.light.distance_m,
            level,
            self.config.camera.roi_side_px,
        )
    }

    /// Counts a call and raises a scheduled fault, if this call has one.
    fn call(&mut self) -> Result<(), InstrumentError> {
        self.calls += 1;
        match self.faults.iter().position(|(at, _)| *at == self.calls) {
            Some(i) => Err(self.faults.swap_remove(i).1),
            None => Ok(()),
        }
    }

    /// The radiance factor of every pixel of the region at the current light level.
    fn scene_image(&self) -> Vec<DVec3> {
        let side = self.config.camera.roi_side_px;
        let base = self.scene_radiance(&self.commanded) * self.light_level;
        let mut image = vec![base; (side * side) as usize];
        if self.light_level > 0.0 {
            if let Some(ghost) = self.ghost(&self.commanded, self.light_level) {
                for y in 0..side {
                    for x in 0..side {
                        if ghost.covers(x, y) {
                            image[(y * side + x) as usize] += ghost.radiance;
                        }
                    }
                }
            }
        }
        image
    }

    fn check_limits(&self, target: &AxisPositions) -> Result<(), InstrumentError> {
        if self.device.within_limits(target) {
            return Ok(());
        }
        let axes = self.device.axes();
        let (name, angle, axis) = AXIS_NAMES
            .iter()
            .zip(target.to_degrees())
            .zip(axes)
            .map(|((name, angle), axis)| (*name, angle, axis))
            .find(|(_, angle, axis)| *angle < axis.min_deg - 1e-7 || *angle > axis.max_deg + 1e-7)
            .expect("an axis is out of its range");
        Err(InstrumentError::Limit(format!(
            "{name} at {angle:.3} deg is outside [{}, {}] deg",
            axis.min_deg, axis.max_deg
        )))
    }
}

/// The reflectance of the simulated white reference (a Spectralon tile's, flat).
pub const SIMULATED_WHITE_REFLECTANCE: f64 = 0.99;

/// The target the simulated operator mounts for `target`, aligned; `under_test` is the
/// sample to measure. An unknown ColorChecker patch is an axis-limit error naming it.
fn simulated_target(
    target: &MountTarget,
    under_test: &MountedSample,
) -> Result<MountedSample, InstrumentError> {
    let diffuse = |target: DiffuseTarget| {
        let name = target.name.clone();
        MountedSample::new(name, std::sync::Arc::new(target), sample::Tilt::default())
    };
    Ok(match target {
        MountTarget::White => diffuse(DiffuseTarget::white(SIMULATED_WHITE_REFLECTANCE)),
        MountTarget::Colorchecker { patch } => {
            let found = colorchecker::PATCHES
                .iter()
                .position(|p| p.name == patch.as_str())
                .ok_or_else(|| {
                    InstrumentError::Limit(format!(
                        "the ColorChecker has no patch named '{}'",
                        specula_core::shown::excerpt(patch)
                    ))
                })?;
            diffuse(DiffuseTarget::colorchecker().swap_remove(found))
        }
        MountTarget::Mirror => {
            let mirror = reference_mirror();
            MountedSample::new(mirror.name(), mirror, sample::Tilt::default())
        }
        MountTarget::Sample => under_test.clone(),
    })
}

/// Rounds for keys: 1 ns of exposure, 1e-9 of light level, 1e-7 rad of axis angle.
fn capture_key(exposure_s: f64, level: f64) -> (u64, u64) {
    (
        rng::quantised(exposure_s, 1e-9),
        rng::quantised(level, 1e-9),
    )
}

impl Instrument for Simulator {
    fn home(&mut self) -> Result<AxisPositions, InstrumentError> {
        self.call()?;
        let park = self.device.park_axes();
        self.clock_s += self.time.transition_s(&self.commanded, &park);
        if park != self.commanded {
            self.repeats.clear();
        }
        self.commanded = park;
        Ok(PositioningError::read_back(&park))
    }

    fn move_to(&mut self, target: &AxisPositions) -> Result<AxisPositions, InstrumentError> {
        self.call()?;
        self.check_limits(target)?;
        let actual = self.actual_axes(target);
        if let Some(Blockage::Collision { .. }) = blockage(&self.device, &actual) {
            let what = blockage(&self.device, &actual).map(|b| b.describe(&self.device));
            return Err(InstrumentError::MotorFault(format!(
                "stopped before a collision: {}",
                what.unwrap_or_default()
            )));
        }
        self.clock_s += self.time.transition_s(&self.commanded, target);
        if *target != self.commanded {
            self.repeats.clear();
        }
        self.commanded = *target;
        Ok(PositioningError::read_back(target))
    }

    fn set_light(&mut self, level: f64) -> Result<(), InstrumentError> {
        self.call()?;
        if !(0.0..=1.0).contains(&level) {
            return Err(InstrumentError::Limit(format!(
                "light level {level} is outside [0, 1]"
            )));
        }
        if level != self.light_level {
            self.clock_s += self.device.capture.light_change_s;
            self.light_level = level;
        }
        Ok(())
    }

    fn capture(&mut self, exposure_s: f64, with_pixels: bool) -> Result<Capture, InstrumentError> {
        self.call()?;
        let (shortest, longest) = self.config.exposure_range_s;
        if !(shortest..=longest).contains(&exposure_s) {
            return Err(InstrumentError::CameraFault(format!(
                "exposure {exposure_s} s is outside [{shortest}, {longest}] s"
            )));
        }
        let key = capture_key(exposure_s, self.light_level);
        let repeat = self.repeats.entry(key).or_insert(0);
        let this_repeat = *repeat;
        *repeat += 1;
        let axes = self.commanded.as_array().map(|a| rng::quantised(a, 1e-7));
        let mut stream = rng::stream(&[
            self.config.seed,
            rng::text(&self.sample.name),
            axes[0],
            axes[1],
            axes[2],
            axes[3],
            key.0,
            key.1,
            this_repeat,
        ]);
        let image = self.scene_image();
        let capture = self.config.camera.expose(
            &image,
            exposure_s,
            self.light_level,
            with_pixels,
            &mut stream,
        );
        self.clock_s += exposure_s + self.device.capture.readout_s;
        self.captures += 1;
        Ok(capture)
    }

    fn info(&mut self) -> Result<InstrumentInfo, InstrumentError> {
        self.call()?;
        let camera = &self.config.camera;
        Ok(InstrumentInfo {
            model: format!("Specula simulator of {}", self.device.name),
            serial: format!("sim-{}", self.config.seed),
            bit_depth: camera.bit_depth,
            white_level: camera.white_level_dn(),
            light_levels: self.config.light_levels.clone(),
            exposure_range_s: self.config.exposure_range_s,
        })
    }

    fn simulated_clock_s(&self) -> Option<f64> {
        Some(self.clock_s)
    }

    fn mount(&mut self, target: &MountTarget) -> Result<MountOutcome, InstrumentError> {
        let sample = simulated_target(target, &self.under_test)?;
        self.mount_sample(sample);
        Ok(MountOutcome::Mounted)
    }
}

#[cfg(test)]
mod tests;
