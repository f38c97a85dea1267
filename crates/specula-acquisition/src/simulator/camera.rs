//! The simulated camera: a linear sensor read out with 12 bits (the paper's AVT Pike 1600C,
//! section 4.1), seen only through the region of interest (the 3 x 3 mm area at
//! 70 um/pixel, section 4.2: 43 x 43 pixels).
//!
//! The scene in front of a pixel is its radiance factor `s = L / E` per RGB channel (1/sr):
//! the radiance towards the camera over the irradiance that the light at full power gives at
//! normal incidence. For a BRDF `f_r`, `s = level * f_r * cos(theta_i)`. A pixel then
//! collects, per channel `c`, in an exposure of `t` seconds
//!
//! `electrons_c = t * (responsivity_c * (M s)_c + dark_current)`, Poisson distributed,
//!
//! where `M` is the 3 x 3 colour crosstalk of the colour filters (rows sum to 1, so that a
//! grey scene stays grey before the channel responsivities). The pixel holds at most
//! `full_well_e`; its raw value is `black_level + gain * electrons + read noise`, rounded and
//! clipped to `[0, white_level]`. A pixel at the white level is saturated.

use crate::hdr::NoiseModel;
use crate::instrument::Capture;
use glam::DVec3;
use rand::Rng;
use rand_distr::{Distribution, Poisson, StandardNormal};
use serde::{Deserialize, Serialize};

/// The sensor and its colour filters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraModel {
    /// Bits of the analogue-to-digital converter.
    pub bit_depth: u32,
    /// Raw value of a pixel that received no light, DN.
    pub black_level_dn: f64,
    /// Conversion gain, DN per electron.
    pub gain_dn_per_e: f64,
    /// Standard deviation of the read-out noise, DN.
    pub read_noise_dn: f64,
    /// Electrons a pixel holds before it clips.
    pub full_well_e: f64,
    /// Thermal electrons per second and pixel.
    pub dark_current_e_s: f64,
    /// Electrons per second per unit radiance factor (1/sr) of each channel, after the
    /// crosstalk.
    pub responsivity_e_s: [f64; 3],
    /// Colour crosstalk: row c says how much of the scene's R, G and B channel c sees.
    pub crosstalk: [[f64; 3]; 3],
    /// Side of the square region of interest, pixels.
    pub roi_side_px: u32,
}

impl Default for CameraModel {
    /// A 12-bit industrial camera of the Pike's class: 16 k electrons full well, 8 electrons
    /// of read noise, and a crosstalk typical of a Bayer sensor. The responsivity puts a white
    /// diffuse reference at 45 deg incidence and full light at half scale in about 1.3 ms.
    fn default() -> Self {
        Self {
            bit_depth: 12,
            black_level_dn: 64.0,
            gain_dn_per_e: 0.25,
            read_noise_dn: 2.0,
            full_well_e: 18_000.0,
            dark_current_e_s: 3.0,
            responsivity_e_s: [2.2e7, 2.7e7, 1.8e7],
            crosstalk: [[0.86, 0.11, 0.03], [0.07, 0.85, 0.08], [0.02, 0.12, 0.86]],
            roi_side_px: 43,
        }
    }
}

impl CameraModel {
    /// The largest raw value, `2^bits - 1`.
    pub fn white_level_dn(&self) -> f64 {
        ((1u64 << self.bit_depth) - 1) as f64
    }

    /// Pixels in the region of interest.
    pub fn pixel_count(&self) -> u32 {
        self.roi_side_px * self.roi_side_px
    }

    /// The sensor's true offsets and noise (what calibration should measure).
    pub fn noise_model(&self) -> NoiseModel {
        NoiseModel {
            black_level_dn: self.black_level_dn,
            dark_current_dn_s: self.dark_current_e_s * self.gain_dn_per_e,
            gain_dn_per_e: self.gain_dn_per_e,
            read_noise_dn: self.read_noise_dn,
            white_level_dn: self.white_level_dn(),
        }
    }

    /// Mean photo-electrons per second of each channel for a scene radiance factor `s`.
    pub fn photo_rate_e_s(&self, s: DVec3) -> [f64; 3] {
        let s = s.to_array();
        std::array::from_fn(|c| {
            let mixed: f64 = (0..3).map(|j| self.crosstalk[c][j] * s[j]).sum();
            self.responsivity_e_s[c] * mixed
        })
    }

    /// The noise-free black-subtracted raw rate, DN per second, of each channel for a scene
    /// radiance factor `s` (dark current excluded): what HDR and calibration estimate.
    pub fn signal_rate_dn_s(&self, s: DVec3) -> [f64; 3] {
        self.photo_rate_e_s(s).map(|e| e * self.gain_dn_per_e)
    }

    /// Exposes the region for `exposure_s` seconds. `scene` gives each pixel's radiance
    /// factor, row-major; it must hold [`Self::pixel_count`] values.
    pub fn expose<R: Rng>(
        &self,
        scene: &[DVec3],
        exposure_s: f64,
        light_level: f64,
        with_pixels: bool,
        rng: &mut R,
    ) -> Capture {
        debug_assert_eq!(scene.len(), self.pixel_count() as usize);
        let white = self.white_level_dn();
        let mut sums = [0.0f64; 3];
        let mut saturated = [0u32; 3];
        let mut pixels = with_pixels.then(|| Vec::with_capacity(scene.len()));
        for &s in scene {
            let rate = self.photo_rate_e_s(s);
            let raw: [f64; 3] = std::array::from_fn(|c| {
                let mean_e = exposure_s * (rate[c] + self.dark_current_e_s);
                self.read_pixel(mean_e, white, rng)
            });
            for c in 0..3 {
                sums[c] += raw[c];
                if raw[c] >= white {
                    saturated[c] += 1;
                }
            }
            if let Some(pixels) = pixels.as_mut() {
                pixels.push(raw.map(|v| v as f32));
            }
        }
        let n = scene.len() as f64;
        Capture {
            exposure_s,
            light_level,
            mean_raw: sums.map(|s| s / n),
            saturated_fraction: saturated.map(|k| k as f64 / n),
            pixel_count: scene.len() as u32,
            pixels,
        }
    }

    /// One pixel's raw value for `mean_e` expected electrons.
    fn read_pixel<R: Rng>(&self, mean_e: f64, white: f64, rng: &mut R) -> f64 {
        // Far above the full well the pixel clips whatever the noise: skip the draw.
        let electrons = if mean_e > 2.0 * self.full_well_e {
            self.full_well_e
        } else if mean_e > 0.0 {
            let poisson = Poisson::new(mean_e).expect("a positive finite mean");
            let e: f64 = poisson.sample(rng);
            e.min(self.full_well_e)
        } else {
            0.0
        };
        let read: f64 = rng.sample(StandardNormal);
        let raw = self.black_level_dn + self.gain_dn_per_e * electrons + self.read_noise_dn * read;
        raw.round().clamp(0.0, white)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulator::rng;

    fn flat(camera: &CameraModel, s: f64) -> Vec<DVec3> {
        vec![DVec3::splat(s); camera.pixel_count() as usize]
    }

    #[test]
    fn mean_and_variance_follow_the_sensor_model() {
        let camera = CameraModel::default();
        let mut rng = rng::stream(&[7]);
        let s = 0.2;
        let t = 2e-4;
        let capture = camera.expose(&flat(&camera, s), t, 1.0, true, &mut rng);
        let rate = camera.photo_rate_e_s(DVec3::splat(s));
        let pixels = capture.pixels.as_ref().unwrap();
        let n = pixels.len() as f64;
        for c in 0..3 {
            let mean_e = t * (rate[c] + camera.dark_current_e_s);
            let expected = camera.black_level_dn + camera.gain_dn_per_e * mean_e;
            let var_expected =
                camera.gain_dn_per_e.powi(2) * mean_e + camera.read_noise_dn.powi(2) + 1.0 / 12.0;
            let mean = capture.mean_raw[c];
            let var = pixels
                .iter()
                .map(|p| (p[c] as f64 - mean).powi(2))
                .sum::<f64>()
                / (n - 1.0);
            // The mean within 5 standard errors, the variance within 15 % (n = 1849).
            assert!(
                (mean - expected).abs() < 5.0 * (var_expected / n).sqrt(),
                "{c}: {mean} vs {expected}"
            );
            assert!(
                (var / var_expected - 1.0).abs() < 0.15,
                "{c}: {var} vs {var_expected}"
            );
            assert_eq!(capture.saturated_fraction[c], 0.0);
        }
    }

    #[test]
    fn grey_stays_grey_through_the_crosstalk() {
        let camera = CameraModel::default();
        for row in camera.crosstalk {
            assert!((row.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        }
        let rate = camera.signal_rate_dn_s(DVec3::splat(1.0));
        for (rate, responsivity) in rate.iter().zip(camera.responsivity_e_s) {
            let expected = responsivity * camera.gain_dn_per_e;
            assert!((rate / expected - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn bright_pixels_saturate_and_dark_ones_sit_at_the_black_level() {
        let camera = CameraModel::default();
        let mut rng = rng::stream(&[8]);
        let bright = camera.expose(&flat(&camera, 100.0), 0.01, 1.0, false, &mut rng);
        assert_eq!(bright.saturated_fraction, [1.0; 3]);
        assert_eq!(bright.mean_raw, [camera.white_level_dn(); 3]);
        assert!(bright.pixels.is_none());
        let dark = camera.expose(&flat(&camera, 0.0), 1e-4, 0.0, false, &mut rng);
        for c in 0..3 {
            assert!((dark.mean_raw[c] - camera.black_level_dn).abs() < 0.5);
        }
    }
}
