//! Characterising the instrument's response by measurement ([`crate::response`]): a
//! reference mirror (a front-surface aluminium mirror, GGX alpha 0.001) is measured around
//! its specular direction by scanning the camera arm across the reflected image of the
//! light, and the light's angular radius and the scan's centre (the mirror's tilt and the
//! axes' offsets move it) are fitted so that the forward model, the mirror's own BRDF
//! integrated over the response, matches the scan (an amplitude is free as well, so the
//! mirror's reflectance need not be known exactly). The camera's pupil, the measured area
//! and the emission profile are taken from the device file.
//!
//! A lab does this once per set-up; on a real device the same function runs through the
//! driver protocol, with `mount` asking the operator to put the mirror on the turntable.

use crate::checks::measure_at;
use crate::hdr::HdrCapturer;
use crate::instrument::{Instrument, InstrumentError};
use crate::kinematics::AxisPositions;
use crate::response::InstrumentResponse;
use glam::DVec3;
use serde::{Deserialize, Serialize};
use specula_core::capture;
use specula_core::materials::conductor::RoughConductor;
use specula_core::materials::{Base, Distribution, Material};
use specula_core::{Brdf, Rgb};
use std::sync::Arc;

use super::{Calibration, CalibrationError};

/// How the response is measured.
#[derive(Debug, Clone, PartialEq)]
pub struct ResponseOptions {
    /// Elevation of the light and of the scan's centre, degrees (on opposite sides of the
    /// zenith).
    pub elevation_deg: f64,
    /// Half width of the camera's scan about the specular direction, degrees.
    pub half_width_deg: f64,
    /// Step of the scan, degrees.
    pub step_deg: f64,
    /// Quadrature nodes of the forward model.
    pub model_nodes: usize,
}

impl Default for ResponseOptions {
    fn default() -> Self {
        Self {
            elevation_deg: 20.0,
            half_width_deg: 3.5,
            step_deg: 0.05,
            model_nodes: 3000,
        }
    }
}

/// The reference mirror: aluminium (Rakic 1995), GGX alpha 0.001.
pub fn reference_mirror() -> Arc<dyn Brdf> {
    let conductor = RoughConductor::new(
        Distribution::Ggx,
        0.001,
        Rgb::new(1.558, 1.015, 0.633),
        Rgb::new(7.712, 6.627, 5.454),
    );
    Arc::new(Material::new(
        "front-surface mirror (aluminium, GGX 0.001)",
        Base::Conductor(conductor),
    ))
}

/// The measured response and how well it fits, as the calibration file and the journal keep
/// it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ResponseFit {
    /// The response with the fitted light radius.
    pub response: InstrumentResponse,
    /// The reference measured.
    pub reference: String,
    /// Offset of the scan's centre from the nominal specular direction, degrees.
    pub centre_offset_deg: f64,
    /// RMS of the fit's residual relative to the scan's peak.
    pub rms_relative: f64,
    /// Camera positions of the scan (degrees from the nominal specular direction) and the
    /// measured values (1/sr, mean of R, G, B).
    pub scan: Vec<(f64, f64)>,
}

impl ResponseFit {
    /// A response known exactly (a simulator's own), not measured.
    pub fn exact(response: InstrumentResponse) -> Self {
        Self {
            response,
            reference: "exact (the simulator's own response)".into(),
            centre_offset_deg: 0.0,
            rms_relative: 0.0,
            scan: Vec::new(),
        }
    }
}

/// The camera angle's scan values (degrees from the specular direction) and the model's
/// value there for a light radius and a centre offset.
fn model_scan(
    prior: &InstrumentResponse,
    mirror: &dyn Brdf,
    options: &ResponseOptions,
    offsets_deg: &[f64],
    radius_deg: f64,
    centre_deg: f64,
) -> Vec<f64> {
    let nodes = prior
        .with_light_radius_deg(radius_deg)
        .capture_nodes(options.model_nodes);
    let e = options.elevation_deg.to_radians();
    let wi = DVec3::new(-e.sin(), 0.0, e.cos());
    offsets_deg
        .iter()
        .map(|d| {
            let a = (options.elevation_deg + d - centre_deg).to_radians();
            let wo = DVec3::new(a.sin(), 0.0, a.cos());
            let m = capture::measure_brdf(&nodes, mirror, wi, wo);
            (m.x + m.y + m.z) / 3.0
        })
        .collect()
}

/// The amplitude that best scales `model` onto `data` and the RMS residual it leaves.
fn scaled_residual(model: &[f64], data: &[f64]) -> (f64, f64) {
    let mm: f64 = model.iter().map(|m| m * m).sum();
    let md: f64 = model.iter().zip(data).map(|(m, d)| m * d).sum();
    let scale = if mm > 0.0 { md / mm } else { 0.0 };
    let ss: f64 = model
        .iter()
        .zip(data)
        .map(|(m, d)| (scale * m - d).powi(2))
        .sum();
    (scale, (ss / data.len() as f64).sqrt())
}

/// Measures the response with the reference mirror mounted by `mount` (see the module
/// documentation); `prior` is the device file's response (its pupil, footprint and emission
/// profile are kept, its light radius starts the search).
pub fn measure_response<I: Instrument>(
    instrument: &mut I,
    mount: impl FnOnce(&mut I, Arc<dyn Brdf>) -> Result<(), InstrumentError>,
    hdr: &mut HdrCapturer,
    calibration: &Calibration,
    prior: &InstrumentResponse,
    options: &ResponseOptions,
) -> Result<ResponseFit, CalibrationError> {
    let mirror = reference_mirror();
    mount(instrument, mirror.clone())?;
    let steps = (options.half_width_deg / options.step_deg).round() as i64;
    let offsets: Vec<f64> = (-steps..=steps)
        .map(|k| k as f64 * options.step_deg)
        .collect();
    let e = options.elevation_deg;
    let mut data = Vec::with_capacity(offsets.len());
    for d in &offsets {
        let axes = AxisPositions::from_degrees(0.0, e + d, 180.0, e);
        let value = measure_at(instrument, hdr, &axes, None)?.value;
        let f = calibration.brdf(value.rate_dn_s, e.to_radians().cos());
        data.push((f.x + f.y + f.z) / 3.0);
    }
    let peak = data.iter().copied().fold(0.0, f64::max);
    if peak <= 0.0 || peak.is_nan() {
        return Err(CalibrationError::Fit(
            "the mirror's scan saw no light: is the light's image within the scan?".into(),
        ));
    }
    let cost = |r: f64, c: f64| {
        let model = model_scan(prior, mirror.as_ref(), options, &offsets, r, c);
        scaled_residual(&model, &data).1
    };
    // Start: the scan's half-maximum crossings give the radius and the centre.
    let above: Vec<f64> = offsets
        .iter()
        .zip(&data)
        .filter(|(_, v)| **v >= 0.5 * peak)
        .map(|(d, _)| *d)
        .collect();
    let (lo, hi) = (above[0], above[above.len() - 1]);
    let mut best = ((0.5 * (hi - lo)).max(options.step_deg), 0.5 * (hi + lo));
    let mut best_cost = cost(best.0, best.1);
    let mut step = 0.25 * options.step_deg.max(0.05 * best.0);
    while step > 1e-4 {
        let moves = [(step, 0.0), (-step, 0.0), (0.0, step), (0.0, -step)];
        let candidate = moves
            .iter()
            .map(|m| (best.0 + m.0, best.1 + m.1))
            .filter(|p| p.0 > 0.0)
            .map(|p| (p, cost(p.0, p.1)))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        match candidate {
            Some((p, c)) if c < best_cost => (best, best_cost) = (p, c),
            _ => step *= 0.5,
        }
    }
    Ok(ResponseFit {
        response: prior.with_light_radius_deg(best.0),
        reference: mirror.name(),
        centre_offset_deg: best.1,
        rms_relative: best_cost / peak,
        scan: offsets.into_iter().zip(data).collect(),
    })
}
