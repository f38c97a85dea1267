//! The interface between Specula and a gonioreflectometer: what the acquisition engine asks of
//! any device, real (through the driver protocol) or simulated.
//!
//! A device moves its four axes ([`AxisPositions`]), sets the light's intensity and captures
//! the region of interest (the 3 x 3 mm patch of paper 4.2) with a given exposure. It reports
//! raw sensor statistics; HDR merging and calibration to 1/sr happen on Specula's side.

use crate::kinematics::AxisPositions;
use serde::{Deserialize, Serialize};

/// Why a device could not do what it was asked. Every variant is recoverable by the engine
/// (retry, re-home, reconnect) up to a configured number of failures.
#[derive(Debug, Clone, PartialEq, thiserror::Error, Serialize, Deserialize)]
#[serde(tag = "kind", content = "message", rename_all = "snake_case")]
pub enum InstrumentError {
    /// No answer within the allowed time.
    #[error("timeout: {0}")]
    Timeout(String),
    /// A requested position is outside an axis's range.
    #[error("axis limit: {0}")]
    Limit(String),
    /// A motor or its controller reported a fault.
    #[error("motor fault: {0}")]
    MotorFault(String),
    /// The camera failed to capture.
    #[error("camera fault: {0}")]
    CameraFault(String),
    /// The link to the device is gone.
    #[error("disconnected: {0}")]
    Disconnected(String),
}

/// What a device says about itself.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InstrumentInfo {
    /// A human-readable model name, e.g. "UTIA gonioreflectometer (simulated)".
    pub model: String,
    /// Serial number or another identifier of this unit.
    pub serial: String,
    /// Sensor bit depth (12 for the paper's AVT Pike 1600C).
    pub bit_depth: u32,
    /// Largest raw value of the sensor, e.g. 4095 for 12 bits.
    pub white_level: f64,
    /// Light intensity levels the source offers, as fractions of full power in (0, 1].
    pub light_levels: Vec<f64>,
    /// Shortest and longest exposure, seconds.
    pub exposure_range_s: (f64, f64),
}

/// One capture of the region of interest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Capture {
    /// Exposure time, seconds.
    pub exposure_s: f64,
    /// Light level in effect, as a fraction of full power.
    pub light_level: f64,
    /// Mean raw value per channel (R, G, B) over the region's pixels, black level included.
    pub mean_raw: [f64; 3],
    /// Fraction of the region's pixels at the white level, per channel.
    pub saturated_fraction: [f64; 3],
    /// Number of pixels in the region.
    pub pixel_count: u32,
    /// The region's raw pixels, row-major RGB, when asked for. The region is square: its side
    /// is the square root of `pixel_count`.
    pub pixels: Option<Vec<[f32; 3]>>,
}

/// A gonioreflectometer as the acquisition engine sees it.
pub trait Instrument: Send {
    /// Drives every axis to its reference switch and back to the park position.
    fn home(&mut self) -> Result<AxisPositions, InstrumentError>;
    /// Moves the axes and returns the positions read back from the encoders.
    fn move_to(&mut self, target: &AxisPositions) -> Result<AxisPositions, InstrumentError>;
    /// Sets the light source's intensity as a fraction of full power; 0 turns it off (dark
    /// frames).
    fn set_light(&mut self, level: f64) -> Result<(), InstrumentError>;
    /// Captures the region of interest with the given exposure; `with_pixels` asks for the
    /// pixels too (for the flare check).
    fn capture(&mut self, exposure_s: f64, with_pixels: bool) -> Result<Capture, InstrumentError>;
    /// What the device is.
    fn info(&mut self) -> Result<InstrumentInfo, InstrumentError>;
    /// The device's own clock in seconds since it started, for a simulated device (which
    /// spends no real time moving or exposing); `None` for real hardware, whose time is the
    /// wall clock.
    fn simulated_clock_s(&self) -> Option<f64> {
        None
    }
    /// Puts `target` on the turntable, if the device can (a robot, a simulator); by default
    /// it cannot, and the operator mounts it ([`MountOutcome::ByOperator`]).
    fn mount(&mut self, target: &MountTarget) -> Result<MountOutcome, InstrumentError> {
        let _ = target;
        Ok(MountOutcome::ByOperator)
    }
}

/// What goes on the turntable during a calibration: a reference target or the sample to
/// measure. On the wire (the driver protocol's `mount`) it reads
/// `{"target": "white"}`, `{"target": "colorchecker", "patch": "dark skin"}`,
/// `{"target": "mirror"}` or `{"target": "sample"}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "target", rename_all = "snake_case")]
pub enum MountTarget {
    /// The white diffuse reference (a Spectralon-like tile).
    White,
    /// One patch of the ColorChecker in the camera's view.
    Colorchecker {
        /// The patch's name as the chart prints it (`dark skin`, ..., `black 2`).
        patch: String,
    },
    /// The reference mirror (a front-surface aluminium mirror).
    Mirror,
    /// The sample to measure.
    Sample,
}

impl std::fmt::Display for MountTarget {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MountTarget::White => write!(f, "the white reference"),
            MountTarget::Colorchecker { patch } => {
                write!(f, "the ColorChecker, patch '{patch}' in view")
            }
            MountTarget::Mirror => write!(f, "the reference mirror"),
            MountTarget::Sample => write!(f, "the sample"),
        }
    }
}

/// Whether a device put a target on its turntable itself.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MountOutcome {
    /// The device (a robot, or its adapter's own prompt) mounted it.
    Mounted,
    /// The device cannot mount targets: the operator must.
    ByOperator,
}
