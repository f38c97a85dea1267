//! High-dynamic-range capture (paper 5.3: "multiple exposures and intensities of light are
//! used"): a highly specular sample spans seven or more orders of magnitude between its
//! highlight and its off-specular floor, far beyond a 12-bit frame.
//!
//! **Merging.** Each unsaturated capture `i` (exposure `t_i`, light level `l_i`) estimates a
//! channel's rate at full light, `y_i = (mean_raw_i - dark(t_i)) / (t_i l_i)` DN/s, where the
//! dark level `dark(t) = black + dark_current t` comes from the [`NoiseModel`]. The merge is
//! the inverse-variance (signal-to-noise) weighted mean: `w_i = 1 / var(y_i)` with
//! `var(y_i) = (gain * signal_i + dark noise + read_noise^2 + 1/12) / (N t_i^2 l_i^2)` for the
//! `N` pixels of the region, the signal taken from the merged estimate rather than from each
//! noisy capture (which would bias the weights). A channel with any saturated pixel in a
//! capture is dropped from that capture. If every capture saturates a channel, its rate is a
//! lower bound and is flagged.
//!
//! **Two ranges.** The exposure time is one range (the camera's shortest to longest
//! exposure), the light level the second, as in the paper: the brightest highlights need the
//! light dimmed below what the shortest exposure can handle.
//!
//! **Adaptive choice.** [`HdrCapturer::measure`] starts from a predicted rate (for example
//! from the probe and the fitted k, or the neighbouring sample) and aims the brightest channel
//! at `target_fraction` of the sensor's range, at the highest light level whose exposure is
//! not below the shortest (so exposures stay short). A capture that saturates is retaken
//! darker; one whose brightest channel is below `min_fraction` of the range is retaken with
//! the exposure it measured; otherwise one capture is enough. With a prediction within a
//! factor of a few, most samples take one capture, the rest two. [`CaptureStats`] counts them.

use crate::instrument::{Capture, Instrument, InstrumentError, InstrumentInfo};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The sensor's offsets and noise, as the merge needs them (measured by
/// [`crate::calibration::measure_noise_model`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NoiseModel {
    /// Raw value of a dark pixel at zero exposure, DN.
    pub black_level_dn: f64,
    /// Growth of the dark level with exposure, DN per second.
    pub dark_current_dn_s: f64,
    /// Conversion gain, DN per electron (the slope of the photon transfer curve).
    pub gain_dn_per_e: f64,
    /// Read-out noise, DN.
    pub read_noise_dn: f64,
    /// The largest raw value (saturation).
    pub white_level_dn: f64,
}

impl NoiseModel {
    /// The raw value of a dark pixel after `exposure_s`, DN.
    pub fn dark_level_dn(&self, exposure_s: f64) -> f64 {
        self.black_level_dn + self.dark_current_dn_s * exposure_s
    }

    /// The range between the black level and saturation, DN.
    pub fn headroom_dn(&self) -> f64 {
        self.white_level_dn - self.black_level_dn
    }

    /// Variance of one pixel whose dark-subtracted signal is `signal_dn`, DN^2: photon noise
    /// of the signal and the dark current, read noise, and the rounding to whole DN.
    pub fn pixel_variance_dn2(&self, signal_dn: f64, exposure_s: f64) -> f64 {
        let shot = signal_dn.max(0.0) + self.dark_current_dn_s * exposure_s;
        self.gain_dn_per_e * shot + self.read_noise_dn.powi(2) + 1.0 / 12.0
    }
}

/// The merged value of one sample.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HdrValue {
    /// Dark-subtracted raw rate of each channel at full light, DN per second.
    pub rate_dn_s: [f64; 3],
    /// One standard deviation of each rate, DN per second (infinite for a lower bound).
    pub sigma_dn_s: [f64; 3],
    /// Captures merged into each channel.
    pub used: [u32; 3],
    /// True for a channel saturated in every capture: its rate is only a lower bound.
    pub saturated: [bool; 3],
}

impl HdrValue {
    /// The largest channel rate, DN/s: the next sample's prediction.
    pub fn brightest_rate_dn_s(&self) -> f64 {
        self.rate_dn_s.into_iter().fold(0.0, f64::max)
    }
}

/// One channel of one capture, as the merge sees it.
struct Reading {
    /// Rate estimate, DN/s at full light.
    rate: f64,
    /// Exposure times light level, seconds.
    scale: f64,
    exposure_s: f64,
    pixels: f64,
}

/// Merges captures of one sample (see the module documentation).
pub fn merge(captures: &[Capture], noise: &NoiseModel) -> HdrValue {
    let mut value = HdrValue {
        rate_dn_s: [0.0; 3],
        sigma_dn_s: [f64::INFINITY; 3],
        used: [0; 3],
        saturated: [false; 3],
    };
    let lit = || captures.iter().filter(|c| c.light_level > 0.0);
    for c in 0..3 {
        let reading = |cap: &Capture| {
            let scale = cap.exposure_s * cap.light_level;
            Reading {
                rate: (cap.mean_raw[c] - noise.dark_level_dn(cap.exposure_s)) / scale,
                scale,
                exposure_s: cap.exposure_s,
                pixels: cap.pixel_count.max(1) as f64,
            }
        };
        let usable: Vec<Reading> = lit()
            .filter(|cap| cap.saturated_fraction[c] == 0.0)
            .map(reading)
            .collect();
        if usable.is_empty() {
            // Saturated everywhere: the least exposed capture bounds the rate from below.
            let least = lit().min_by(|a, b| {
                (a.exposure_s * a.light_level).total_cmp(&(b.exposure_s * b.light_level))
            });
            if let Some(cap) = least {
                value.rate_dn_s[c] = reading(cap).rate;
                value.saturated[c] = true;
            }
            continue;
        }
        // Start from the capture with the most signal, then re-weight twice.
        let best = usable
            .iter()
            .max_by(|a, b| (a.rate * a.scale).total_cmp(&(b.rate * b.scale)))
            .expect("not empty");
        let mut estimate = best.rate;
        let mut weight_sum = 0.0;
        for _ in 0..3 {
            let (mut sw, mut swy) = (0.0, 0.0);
            for r in &usable {
                let variance = noise.pixel_variance_dn2(estimate * r.scale, r.exposure_s)
                    / r.pixels
                    / (r.scale * r.scale);
                sw += 1.0 / variance;
                swy += r.rate / variance;
            }
            estimate = swy / sw;
            weight_sum = sw;
        }
        value.rate_dn_s[c] = estimate;
        value.sigma_dn_s[c] = weight_sum.sqrt().recip();
        value.used[c] = usable.len() as u32;
    }
    value
}

/// How HDR captures are chosen.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HdrSettings {
    /// Light levels to use, fractions of full power.
    pub light_levels: Vec<f64>,
    /// Shortest and longest exposure, seconds.
    pub exposure_range_s: (f64, f64),
    /// Where to put the brightest channel, as a fraction of the range above black.
    pub target_fraction: f64,
    /// Below this fraction of the range the brightest channel is retaken brighter.
    pub min_fraction: f64,
    /// Most captures for one sample.
    pub max_captures: usize,
    /// Ask for the pixels of every capture (for the flare check).
    pub with_pixels: bool,
}

impl HdrSettings {
    /// Defaults for a device: its light levels and exposures, the brightest channel aimed at
    /// 40 % of the range and accepted down to 4 %, at most 6 captures.
    pub fn for_device(info: &InstrumentInfo) -> Self {
        Self {
            light_levels: info.light_levels.clone(),
            exposure_range_s: info.exposure_range_s,
            target_fraction: 0.4,
            min_fraction: 0.04,
            max_captures: 6,
            with_pixels: false,
        }
    }

    /// Light levels from the highest down.
    fn levels_descending(&self) -> Vec<f64> {
        let mut levels: Vec<f64> = self
            .light_levels
            .iter()
            .copied()
            .filter(|l| *l > 0.0)
            .collect();
        levels.sort_by(|a, b| b.total_cmp(a));
        if levels.is_empty() {
            levels.push(1.0);
        }
        levels
    }
}

/// A light level and an exposure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Exposure {
    /// Light level, fraction of full power in (0, 1].
    pub light_level: f64,
    /// Exposure time, seconds.
    pub exposure_s: f64,
}

/// Counts of captures per measured sample.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct CaptureStats {
    /// Samples measured.
    pub samples: u64,
    /// Frames captured.
    pub captures: u64,
    /// Changes of the light level.
    pub light_changes: u64,
    /// Samples by the number of captures they took.
    pub by_count: BTreeMap<usize, u64>,
}

impl CaptureStats {
    fn record(&mut self, captures: usize) {
        self.samples += 1;
        self.captures += captures as u64;
        *self.by_count.entry(captures).or_insert(0) += 1;
    }

    /// Mean captures per sample.
    pub fn mean_captures(&self) -> f64 {
        self.captures as f64 / self.samples.max(1) as f64
    }

    /// Share of the samples that took at most `n` captures.
    pub fn share_at_most(&self, n: usize) -> f64 {
        let within: u64 = self.by_count.range(..=n).map(|(_, k)| k).sum();
        within as f64 / self.samples.max(1) as f64
    }
}

/// One sample's captures and their merged value.
#[derive(Debug, Clone, PartialEq)]
pub struct HdrMeasurement {
    /// The merged value (see [`merge`]).
    pub value: HdrValue,
    /// The captures it was merged from, in the order they were taken.
    pub captures: Vec<Capture>,
}

/// Takes HDR measurements and keeps count (see the module documentation).
#[derive(Debug, Clone)]
pub struct HdrCapturer {
    /// How exposures are chosen.
    pub settings: HdrSettings,
    /// The camera's noise model, which weights the captures in the merge.
    pub noise: NoiseModel,
    /// Counts of the captures taken so far.
    pub stats: CaptureStats,
    /// The light level last set, if known.
    light_level: Option<f64>,
}

/// A retake after saturation aims this many times brighter than the saturation bound.
const SATURATED_STEP: f64 = 6.0;

impl HdrCapturer {
    /// A capturer with no captures counted and the light level unknown.
    pub fn new(settings: HdrSettings, noise: NoiseModel) -> Self {
        Self {
            settings,
            noise,
            stats: CaptureStats::default(),
            light_level: None,
        }
    }

    /// Forgets the light level (after the device was restarted or the light set elsewhere).
    pub fn forget_light_level(&mut self) {
        self.light_level = None;
    }

    /// The exposure for a predicted brightest-channel rate at full light, DN/s: the highest
    /// light level whose exposure for the target is not below the shortest exposure.
    pub fn choose(&self, predicted_rate_dn_s: f64) -> Exposure {
        let levels = self.settings.levels_descending();
        let (shortest, longest) = self.settings.exposure_range_s;
        let target = self.settings.target_fraction * self.noise.headroom_dn();
        let rate = if predicted_rate_dn_s.is_finite() && predicted_rate_dn_s > 0.0 {
            predicted_rate_dn_s
        } else {
            f64::MIN_POSITIVE
        };
        for &level in &levels {
            let exposure_s = target / (rate * level);
            if exposure_s >= shortest {
                return Exposure {
                    light_level: level,
                    exposure_s: exposure_s.min(longest),
                };
            }
        }
        Exposure {
            light_level: *levels.last().expect("at least one level"),
            exposure_s: shortest,
        }
    }

    /// The rate in the geometric middle of what the settings can measure: the start when
    /// nothing is predicted.
    fn middle_rate_dn_s(&self) -> f64 {
        let levels = self.settings.levels_descending();
        let (shortest, longest) = self.settings.exposure_range_s;
        let target = self.settings.target_fraction * self.noise.headroom_dn();
        let dimmest = target / (levels[0] * longest);
        let brightest = target / (levels[levels.len() - 1] * shortest);
        (dimmest * brightest).sqrt()
    }

    fn capture(
        &mut self,
        instrument: &mut dyn Instrument,
        exposure: Exposure,
    ) -> Result<Capture, InstrumentError> {
        if self.light_level != Some(exposure.light_level) {
            instrument.set_light(exposure.light_level)?;
            self.light_level = Some(exposure.light_level);
            self.stats.light_changes += 1;
        }
        instrument.capture(exposure.exposure_s, self.settings.with_pixels)
    }

    /// Measures one sample adaptively, starting from `predicted_rate_dn_s` (the brightest
    /// channel's rate at full light, DN/s) when given.
    pub fn measure(
        &mut self,
        instrument: &mut dyn Instrument,
        predicted_rate_dn_s: Option<f64>,
    ) -> Result<HdrMeasurement, InstrumentError> {
        let headroom = self.noise.headroom_dn();
        let mut guess = predicted_rate_dn_s
            .filter(|r| r.is_finite() && *r > 0.0)
            .unwrap_or_else(|| self.middle_rate_dn_s());
        let mut captures: Vec<Capture> = Vec::new();
        let mut last: Option<Exposure> = None;
        loop {
            let exposure = self.choose(guess);
            if last == Some(exposure) {
                break; // at the end of both ranges: nothing better to try
            }
            let capture = self.capture(instrument, exposure)?;
            let scale = exposure.exposure_s * exposure.light_level;
            let signal = (0..3)
                .map(|c| capture.mean_raw[c] - self.noise.dark_level_dn(exposure.exposure_s))
                .fold(f64::MIN, f64::max);
            let saturated = capture.saturated_fraction.iter().any(|&f| f > 0.0);
            captures.push(capture);
            last = Some(exposure);
            if captures.len() >= self.settings.max_captures {
                break;
            }
            if saturated {
                guess = (guess * SATURATED_STEP).max(SATURATED_STEP * headroom / scale);
            } else if signal < self.settings.min_fraction * headroom {
                // The measured rate, unless it is lost in the noise: then a big step.
                let measured = signal / scale;
                guess = measured.max(guess / 100.0).min(guess / 2.0);
            } else {
                break;
            }
        }
        self.stats.record(captures.len());
        Ok(HdrMeasurement {
            value: merge(&captures, &self.noise),
            captures,
        })
    }

    /// The paper's fixed bracket: every exposure at every light level, merged.
    pub fn bracket(
        &mut self,
        instrument: &mut dyn Instrument,
        exposures_s: &[f64],
        light_levels: &[f64],
    ) -> Result<HdrMeasurement, InstrumentError> {
        let mut captures = Vec::with_capacity(exposures_s.len() * light_levels.len());
        for &light_level in light_levels {
            for &exposure_s in exposures_s {
                let exposure = Exposure {
                    light_level,
                    exposure_s,
                };
                captures.push(self.capture(instrument, exposure)?);
            }
        }
        self.stats.record(captures.len());
        Ok(HdrMeasurement {
            value: merge(&captures, &self.noise),
            captures,
        })
    }
}

#[cfg(test)]
mod tests;
