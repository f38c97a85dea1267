//! The HDR capture made at every sample (paper 5.3: "multiple exposures and intensities of
//! light are used"): a bracket of exposures at each light level. A leaf: the device file
//! holds one, and [`crate::timing`] prices it.

use serde::{Deserialize, Serialize};

/// The HDR capture made at every sample.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaptureBracket {
    /// Exposure times of the bracket, seconds; the full bracket is taken at every light level.
    /// Range: 0 to [`MAX_TIME_S`] each.
    pub exposures_s: Vec<f64>,
    /// Relative LED intensities (1 = full). Range: above 0, at most 1.
    pub light_levels: Vec<f64>,
    /// Read-out and transfer of one frame, seconds. Range: 0 to [`MAX_TIME_S`].
    pub readout_s: f64,
    /// Changing the LED current and waiting for it to stabilise, seconds. Range: 0 to
    /// [`MAX_TIME_S`].
    pub light_change_s: f64,
    /// Per sample: saving frames and bookkeeping, seconds. Range: 0 to [`MAX_TIME_S`].
    pub overhead_s: f64,
}

/// The longest time of a capture bracket, seconds (an exposure, a read-out, a change of
/// light, the overhead): an hour.
pub(crate) const MAX_TIME_S: f64 = 3600.0;

impl CaptureBracket {
    /// `levels * (light_change + sum(exposure + readout)) + overhead`, seconds.
    pub fn duration_s(&self) -> f64 {
        let frames_s: f64 = self.exposures_s.iter().map(|e| e + self.readout_s).sum();
        self.light_levels.len() as f64 * (self.light_change_s + frames_s) + self.overhead_s
    }

    pub(crate) fn validate(&self) -> Result<(), CaptureProblem> {
        if self.exposures_s.is_empty() || self.light_levels.is_empty() {
            return Err(CaptureProblem::Empty);
        }
        let times = self.exposures_s.iter().chain([
            &self.readout_s,
            &self.light_change_s,
            &self.overhead_s,
        ]);
        if times.into_iter().any(|t| !(0.0..=MAX_TIME_S).contains(t)) {
            return Err(CaptureProblem::Time);
        }
        if self.light_levels.iter().any(|l| !(*l > 0.0 && *l <= 1.0)) {
            return Err(CaptureProblem::LightLevel);
        }
        Ok(())
    }
}

/// What makes a device file's capture bracket unusable.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum CaptureProblem {
    /// No exposure or no light level.
    #[error("capture needs at least one exposure and one light level")]
    Empty,
    /// A time outside 0 to [`MAX_TIME_S`] seconds, or not a number.
    #[error("capture times must be numbers of seconds from 0 to {MAX_TIME_S}")]
    Time,
    /// A light level outside (0, 1], or not a number.
    #[error("capture.light_levels must be above 0 and at most 1")]
    LightLevel,
}
