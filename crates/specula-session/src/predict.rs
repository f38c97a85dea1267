//! Predicted exposures: the raw rate a sample should give, so that its HDR measurement
//! starts close to the right exposure and light level and most samples take one capture
//! (paper 5.3 used a fixed bracket of "multiple exposures and intensities of light" at every
//! sample; predicting cuts the captures, the largest part of the time).
//!
//! The prediction for a sample combines
//! - a **model** of the material from the probe (section 5.2): the BRDF along theta_h at
//!   theta_d = 40, phi_d = 90 deg, interpolated in log f over MERL's index coordinate
//!   `sqrt(theta_h * 90)`, turned into a raw rate by the calibration at the sample's incidence;
//! - a **correction** from the sample measured just before (in execution order): the ratio
//!   of what it gave to what the model predicted for it, which carries the slow change with
//!   theta_d and phi_d that the probe does not see (Fresnel, shadowing). Consecutive samples
//!   of an ordered plan are neighbours in axis space, so the ratio is local.
//!
//! Without a probe (the probe itself) the previous sample's rate, scaled by the ratio of the
//! incidence cosines, is the prediction.
//!
//! A prediction depends only on what the journal holds (the probe and the previous sample),
//! so a resumed session predicts, captures and measures exactly as an uninterrupted one.

use crate::journal::{PlannedRow, SampleRecord};
use specula_acquisition::calibration::Calibration;
use specula_core::merl;
use specula_core::{HalfDiff, ProbePoint, Rgb};

/// The largest correction applied, either way: beyond it the previous sample is taken to be
/// unlike this one (an occlusion, a lower bound) and ignored.
const MAX_CORRECTION: f64 = 30.0;

/// The probe's BRDF along theta_h, for predictions.
#[derive(Debug, Clone, PartialEq)]
pub struct ProbeModel {
    /// MERL's index coordinate `sqrt(theta_h_deg * 90)`, increasing.
    index: Vec<f64>,
    /// ln f per channel, floored at a tiny positive value.
    log_value: Vec<[f64; 3]>,
}

impl ProbeModel {
    /// From the probe's points; `None` with fewer than two positive samples.
    pub fn new(samples: &[ProbePoint]) -> Option<Self> {
        let mut points: Vec<(f64, [f64; 3])> = samples
            .iter()
            .filter(|p| {
                p.theta_h_deg.is_finite() && p.theta_h_deg >= 0.0 && p.value.max_element() > 0.0
            })
            .map(|p| {
                (
                    merl::theta_h_coordinate(p.theta_h_deg),
                    p.value.to_array().map(|x| x.max(1e-12).ln()),
                )
            })
            .collect();
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        points.dedup_by(|a, b| a.0 == b.0);
        if points.len() < 2 {
            return None;
        }
        let (index, log_value) = points.into_iter().unzip();
        Some(Self { index, log_value })
    }

    /// f at `theta_h_deg` (clamped to the probe's range), 1/sr.
    pub fn brdf(&self, theta_h_deg: f64) -> Rgb {
        let x = merl::theta_h_coordinate(theta_h_deg);
        let n = self.index.len();
        let i = self.index.partition_point(|&t| t <= x).clamp(1, n - 1);
        let (x0, x1) = (self.index[i - 1], self.index[i]);
        let w = ((x - x0) / (x1 - x0)).clamp(0.0, 1.0);
        let (a, b) = (self.log_value[i - 1], self.log_value[i]);
        Rgb::from_array(std::array::from_fn(|c| (a[c] + w * (b[c] - a[c])).exp()))
    }
}

/// Predicts the brightest channel's rate (DN/s at full light) of planned samples.
#[derive(Debug, Clone)]
pub struct Predictor {
    calibration: Calibration,
    model: Option<ProbeModel>,
}

/// The cosine of the light's incidence for a planned sample.
pub fn cos_theta_i(row: &PlannedRow) -> f64 {
    row.hd.to_directions().0.z
}

impl Predictor {
    /// A predictor from the calibration and, once the probe is fitted, its model.
    pub fn new(calibration: Calibration, model: Option<ProbeModel>) -> Self {
        Self { calibration, model }
    }

    /// The model's rate for a planned sample, if there is a model.
    fn model_rate(&self, row: &PlannedRow) -> Option<f64> {
        self.model_rate_at(row.hd)
    }

    /// The model's brightest-channel rate (DN/s at full light) of a sample, if there is a
    /// model: what a time estimate prices the sample's exposure from.
    pub fn model_rate_at(&self, hd: HalfDiff) -> Option<f64> {
        let model = self.model.as_ref()?;
        let f = model.brdf(hd.theta_h.to_degrees());
        let cos_i = hd.to_directions().0.z;
        let rate = self.calibration.predicted_rate_dn_s(f, cos_i.max(1e-3));
        (rate.is_finite() && rate > 0.0).then_some(rate)
    }

    /// The predicted rate of `row`, given the sample measured just before it (if any).
    pub fn predict(
        &self,
        row: &PlannedRow,
        previous: Option<(&PlannedRow, &SampleRecord)>,
    ) -> Option<f64> {
        let measured = previous.and_then(|(prev_row, record)| {
            let rate = record.rate_dn_s.into_iter().fold(0.0, f64::max);
            (rate.is_finite() && rate > 0.0 && !record.lower_bound).then_some((prev_row, rate))
        });
        match (self.model_rate(row), measured) {
            (Some(model), Some((prev_row, rate))) => {
                let correction = self.model_rate(prev_row).map(|expected| rate / expected);
                match correction {
                    Some(c) if (1.0 / MAX_CORRECTION..=MAX_CORRECTION).contains(&c) => {
                        Some(model * c)
                    }
                    _ => Some(model),
                }
            }
            (Some(model), None) => Some(model),
            (None, Some((prev_row, rate))) => {
                let ratio = cos_theta_i(row) / cos_theta_i(prev_row).max(1e-3);
                Some(rate * ratio.clamp(1e-3, 1e3))
            }
            (None, None) => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_acquisition::hdr::NoiseModel;
    use specula_acquisition::kinematics::AxisPositions;

    fn calibration() -> Calibration {
        Calibration {
            device: "test".into(),
            white_reflectance: 0.99,
            white_certificate: None,
            light_elevation_deg: 45.0,
            gain_dn_s_per_sr: [1000.0, 2000.0, 500.0],
            colour_matrix: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            colour_rms_error: 0.0,
            colour_reference: "identity".into(),
            noise: NoiseModel {
                black_level_dn: 64.0,
                dark_current_dn_s: 0.0,
                gain_dn_per_e: 0.25,
                read_noise_dn: 2.0,
                white_level_dn: 4095.0,
            },
            response: None,
        }
    }

    fn row(seq: u32, theta_h_deg: f64, theta_d_deg: f64) -> PlannedRow {
        PlannedRow {
            seq,
            hd: HalfDiff::from_degrees(theta_h_deg, 45.0, theta_d_deg, 90.0),
            axes: AxisPositions::new(0.0, 0.0, 0.0, 0.0),
            predicted_s: 1.0,
        }
    }

    fn record(rate: f64) -> SampleRecord {
        SampleRecord {
            stage: "main".into(),
            seq: 0,
            value: Rgb::ZERO,
            rate_dn_s: [rate, rate / 2.0, rate / 3.0],
            sigma_dn_s: [0.0; 3],
            lower_bound: false,
            readback: AxisPositions::new(0.0, 0.0, 0.0, 0.0),
            device_s: 0.0,
            wall_s: 0.0,
            finished_unix_s: 0.0,
            attempts: 1,
            captures: Vec::new(),
        }
    }

    #[test]
    fn the_model_interpolates_log_f_in_the_merl_coordinate() {
        // f = exp(-x) in MERL's coordinate x = sqrt(90 theta_h): exact for log-linear
        // interpolation between the nodes.
        let samples: Vec<ProbePoint> = (0..10)
            .map(|i| {
                let x = i as f64 * 3.0;
                ProbePoint::new(merl::theta_h_deg_at(x), Rgb::splat((-x).exp()))
            })
            .collect();
        let model = ProbeModel::new(&samples).unwrap();
        for x in [0.0, 1.3, 7.7, 26.9] {
            let f = model.brdf(merl::theta_h_deg_at(x));
            assert!((f.x / (-x).exp() - 1.0).abs() < 1e-9, "{x}: {f}");
        }
        // Clamped beyond the last node.
        assert!((model.brdf(89.0).y / (-27.0f64).exp() - 1.0).abs() < 1e-9);
        assert!(ProbeModel::new(&samples[..1]).is_none());
    }

    #[test]
    fn predictions_follow_the_model_and_the_previous_sample() {
        let samples = [
            ProbePoint::new(0.0, Rgb::splat(100.0)),
            ProbePoint::new(10.0, Rgb::splat(1.0)),
            ProbePoint::new(90.0, Rgb::splat(0.1)),
        ];
        let with_model = Predictor::new(calibration(), ProbeModel::new(&samples));
        let here = row(1, 10.0, 40.0);
        let base = with_model.predict(&here, None).unwrap();
        // The brightest channel: G's gain, f = 1, cos theta_i of the sample.
        assert!(
            (base / (2000.0 * cos_theta_i(&here)) - 1.0).abs() < 1e-9,
            "{base}"
        );
        // The previous sample gave 3x its model: the prediction follows.
        let before = row(0, 10.0, 20.0);
        let expected_before = 2000.0 * cos_theta_i(&before);
        let got = with_model
            .predict(&here, Some((&before, &record(3.0 * expected_before))))
            .unwrap();
        assert!((got / (3.0 * base) - 1.0).abs() < 1e-9);
        // A wildly different previous sample (an occlusion) is ignored.
        let got = with_model
            .predict(&here, Some((&before, &record(1e-6))))
            .unwrap();
        assert_eq!(got, base);

        let without = Predictor::new(calibration(), None);
        assert_eq!(without.predict(&here, None), None);
        let got = without
            .predict(&here, Some((&before, &record(500.0))))
            .unwrap();
        assert!((got - 500.0 * cos_theta_i(&here) / cos_theta_i(&before)).abs() < 1e-9);
    }
}
