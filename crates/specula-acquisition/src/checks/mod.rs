//! The paper's practical checks before and during a measurement (sections 4.2 and 4.3):
//!
//! - [`alignment`]: the specular highlight's position at several turntable rotations gives
//!   the sample's tilt and the adjustment to make;
//! - [`orientation`]: the intensity against `phi_h` shows the anisotropic scratch lobe and
//!   picks a `phi_h` free of it;
//! - [`flare`]: a capture whose colour changes locally is flagged and retaken at another
//!   position of the arms, or excluded.
//!
//! Each works through the [`Instrument`] interface and the HDR capturer, so it runs the same
//! on the simulator and on a real device.

pub mod alignment;
pub mod flare;
pub mod orientation;
mod request;

pub use request::{run_check, Check, CheckOutcome, CheckRequest, CheckRunError, Found};

use crate::device::Device;
use crate::hdr::{HdrCapturer, HdrMeasurement};
use crate::instrument::{Instrument, InstrumentError};
use crate::kinematics::{solutions, AxisPositions};
use crate::occlusion::blockage_within_accuracy;
use glam::DVec3;

/// Why a check could not finish.
#[derive(Debug, thiserror::Error)]
pub enum CheckError {
    /// The instrument failed during the check's measurements.
    #[error("device: {0}")]
    Instrument(#[from] InstrumentError),
    /// The scan did not find what it looks for (e.g. no highlight within its range).
    #[error("{0}")]
    NotFound(String),
}

/// Every position of the arms that gives `(wi, wo)` and is free of occlusion and collision,
/// the one nearest `near` (in the sum of axis moves) first.
pub fn free_positions(
    device: &Device,
    wi: DVec3,
    wo: DVec3,
    near: Option<&AxisPositions>,
) -> Vec<AxisPositions> {
    let mut free: Vec<AxisPositions> = solutions(device, wi, wo)
        .into_iter()
        .filter(|a| blockage_within_accuracy(device, a).is_none())
        .collect();
    if let Some(near) = near {
        let distance = |a: &AxisPositions| -> f64 {
            a.as_array()
                .iter()
                .zip(near.as_array())
                .map(|(x, y)| (x - y).abs())
                .sum()
        };
        free.sort_by(|a, b| distance(a).total_cmp(&distance(b)));
    }
    free
}

/// Moves to `axes` and measures in HDR, predicting from `predicted_rate_dn_s`.
pub fn measure_at(
    instrument: &mut dyn Instrument,
    hdr: &mut HdrCapturer,
    axes: &AxisPositions,
    predicted_rate_dn_s: Option<f64>,
) -> Result<HdrMeasurement, InstrumentError> {
    instrument.move_to(axes)?;
    hdr.measure(instrument, predicted_rate_dn_s)
}

/// The sum of a measurement's channel rates, DN/s: an intensity for scans.
pub fn intensity(measurement: &HdrMeasurement) -> f64 {
    measurement.value.rate_dn_s.iter().sum()
}
