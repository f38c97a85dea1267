//! The HDR capture made at every sample (paper 5.3: "multiple exposures and intensities of
//! light are used"): a bracket of exposures at each light level. A leaf: the device file
//! holds one, and [`crate::timing`] prices it.

use serde::{Deserialize, Serialize};

/// The HDR capture made at every sample.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaptureBracket {
    /// Exposure times of the bracket, seconds; the full bracket is taken at every light level.
    pub exposures_s: Vec<f64>,
    /// Relative LED intensities (1 = full).
    pub light_levels: Vec<f64>,
    /// Read-out and transfer of one frame, seconds.
    pub readout_s: f64,
    /// Changing the LED current and waiting for it to stabilise, seconds.
    pub light_change_s: f64,
    /// Per sample: saving frames and bookkeeping, seconds.
    pub overhead_s: f64,
}

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
        if times.into_iter().any(|t| !(t.is_finite() && *t >= 0.0)) {
            return Err(CaptureProblem::Time);
        }
        if self
            .light_levels
            .iter()
            .any(|l| !(l.is_finite() && *l > 0.0))
        {
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
    /// A time is negative or not a number.
    #[error("capture times must be zero or positive numbers of seconds")]
    Time,
    /// A light level is zero, negative or not a number.
    #[error("capture.light_levels must be positive")]
    LightLevel,
}
