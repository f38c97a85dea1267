//! What the fit through the instrument's response found ([`DeblurRecord`]): the response's
//! light, the resolution in theta_h, the fitted peak's width and the checks of the
//! deblurred table, for the measurement's summary and the report.

use serde::{Deserialize, Serialize};
use specula_acquisition::calibration::response::ResponseFit;

/// What the fit through the instrument's response found, for the summary and the report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DeblurRecord {
    /// The light's angular radius of the response, degrees.
    pub light_radius_deg: f64,
    /// How it was known ("exact (the simulator's own response)" or the reference measured).
    pub measured_with: String,
    /// The instrument's resolution in theta_h, degrees.
    pub resolution_deg: f64,
    /// The fitted lobe's half width at half maximum in theta_h, degrees.
    pub peak_half_width_deg: Option<f64>,
    /// What the checks of the deblurred table found, as summary lines
    /// ([`specula_reconstruct::safeguard::Safeguard::lines`]).
    #[serde(default)]
    pub checks: Vec<String>,
    /// Below this theta_h (degrees) the table holds the un-deblurred values, because the
    /// deblurred ones failed a check.
    #[serde(default)]
    pub fallback_below_deg: Option<f64>,
    /// True when the deblurred table failed a check ([`specula_reconstruct::safeguard`]).
    #[serde(default)]
    pub check_failed: bool,
}

impl DeblurRecord {
    /// Of a response and the reconstruction made through it.
    pub fn new(fit: &ResponseFit, reconstruction: &specula_reconstruct::Reconstruction) -> Self {
        let safeguard = reconstruction.safeguard.as_ref();
        Self {
            light_radius_deg: fit.response.light.radius_deg,
            measured_with: fit.reference.clone(),
            resolution_deg: fit.response.resolution_deg(),
            peak_half_width_deg: reconstruction.lobe.map(|l| l.shape.half_width_deg()),
            checks: safeguard.map_or_else(Vec::new, |s| s.lines()),
            fallback_below_deg: safeguard.and_then(|s| s.fallback_below_deg),
            check_failed: safeguard.is_some_and(|s| s.failed()),
        }
    }

    /// True when the peak is at least as wide as the instrument resolves and the deblurred
    /// table passed its checks.
    pub fn resolved(&self) -> bool {
        !self.check_failed
            && self
                .peak_half_width_deg
                .is_some_and(|w| w >= self.resolution_deg)
    }

    /// One sentence: the resolution and whether the peak is resolved.
    pub fn describe(&self) -> String {
        let resolution = format!("resolution {:.3} deg in theta_h", self.resolution_deg);
        match self.peak_half_width_deg {
            _ if self.check_failed && self.fallback_below_deg.is_none() => format!(
                "{resolution}; the deblurred table failed a check (deblur_fallback says which), so its peak is not a measurement"
            ),
            _ if self.fallback_below_deg.is_some() => format!(
                "{resolution}; the deblurred peak was not kept (deblur_fallback says why), so theta_h below {:.2} deg holds the values as measured (a bound, not a measurement)",
                self.fallback_below_deg.unwrap_or_default()
            ),
            Some(w) if self.resolved() => {
                format!("{resolution}; the peak's half width {w:.3} deg is resolved")
            }
            Some(w) => format!(
                "{resolution}; the peak's half width {w:.3} deg is narrower than that: a bound, not a measurement"
            ),
            None => resolution,
        }
    }

    /// The summary's lines.
    pub fn lines(&self) -> Vec<String> {
        let mut lines = vec![
            "deblurred=true".to_string(),
            format!("response_light_radius_deg={:.4}", self.light_radius_deg),
            format!("response_measured_with={}", self.measured_with),
            format!("resolution_deg={:.4}", self.resolution_deg),
        ];
        if let Some(w) = self.peak_half_width_deg {
            lines.push(format!("peak_half_width_deg={w:.4}"));
            lines.push(if self.resolved() {
                "peak_resolved=true".into()
            } else if let Some(limit) = self.fallback_below_deg {
                format!(
                    "peak_resolved=false (the deblurred peak was not kept, see deblur_fallback: theta_h below {limit:.2} deg holds the values as measured, a bound at the instrument's resolution)"
                )
            } else if self.check_failed {
                "peak_resolved=false (the deblurred table failed a check: see deblur_fallback; its peak is not a measurement)".into()
            } else {
                format!(
                    "peak_resolved=false (the peak is narrower than the instrument's resolution of {:.2} deg: its width is a bound, not a measurement)",
                    self.resolution_deg
                )
            });
        }
        lines.extend(self.checks.iter().cloned());
        lines
    }
}
