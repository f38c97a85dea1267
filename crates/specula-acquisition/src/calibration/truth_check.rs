//! A calibration checked on a sample of known BRDF: the sample measured at a few theta_h
//! positions, its calibrated values ([`Calibration::brdf`]) beside the truth's. Near the
//! highlight the light's disk ([`crate::device::Device::light_radius_deg`]) blurs a sharp
//! lobe, so ratios below 1 there are the source's size, not the calibration.

use super::Calibration;
use crate::checks::{free_positions, measure_at};
use crate::device::Device;
use crate::hdr::{HdrCapturer, HdrSettings};
use crate::instrument::{Instrument, InstrumentError};
use glam::DVec3;
use specula_core::{Brdf, HalfDiff, Rgb};

/// The theta_h positions of the check, degrees (at [`TRUTH_CHECK_THETA_D_DEG`],
/// [`TRUTH_CHECK_PHI_D_DEG`], [`TRUTH_CHECK_PHI_H_DEG`]).
pub const TRUTH_CHECK_THETA_H_DEG: [f64; 6] = [0.0, 1.0, 3.0, 10.0, 30.0, 60.0];
/// theta_d of the check, degrees.
pub const TRUTH_CHECK_THETA_D_DEG: f64 = 30.0;
/// phi_d of the check, degrees: the characteristic slice.
pub const TRUTH_CHECK_PHI_D_DEG: f64 = 90.0;
/// phi_h of the check, degrees: the paper's.
pub const TRUTH_CHECK_PHI_H_DEG: f64 = 45.0;

/// One geometry of the check as the calibrated device measured it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CheckValue {
    /// theta_h of the geometry, degrees.
    pub theta_h_deg: f64,
    /// f_r as the calibrated device measured it, 1/sr.
    pub measured: Rgb,
    /// The light's direction, sample frame.
    pub wi: DVec3,
    /// The camera's direction, sample frame.
    pub wo: DVec3,
}

/// One geometry of the check beside the truth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TruthCheck {
    /// theta_h of the geometry, degrees.
    pub theta_h_deg: f64,
    /// f_r as the calibrated device measured it, 1/sr.
    pub measured: Rgb,
    /// f_r of the truth, 1/sr.
    pub truth: Rgb,
}

impl TruthCheck {
    /// Measured over true f_r in the green channel.
    pub fn green_ratio(&self) -> f64 {
        self.measured.y / self.truth.y
    }
}

/// Measures the mounted sample at each of `theta_h_deg` (at theta_d 30, phi_d 90, phi_h
/// 45 deg) with `calibration`'s noise model and gains: the check measurement of a
/// calibration, which needs no truth. A geometry the device cannot reach is left out.
pub fn measure_check(
    instrument: &mut dyn Instrument,
    device: &Device,
    calibration: &Calibration,
    theta_h_deg: &[f64],
) -> Result<Vec<CheckValue>, InstrumentError> {
    let settings = HdrSettings::for_device(&instrument.info()?);
    let mut hdr = HdrCapturer::new(settings, calibration.noise);
    let mut checks = Vec::with_capacity(theta_h_deg.len());
    for &theta_h in theta_h_deg {
        let hd = HalfDiff::from_degrees(
            theta_h,
            TRUTH_CHECK_PHI_H_DEG,
            TRUTH_CHECK_THETA_D_DEG,
            TRUTH_CHECK_PHI_D_DEG,
        );
        let (wi, wo) = hd.to_directions();
        let Some(axes) = free_positions(device, wi, wo, None).first().copied() else {
            continue;
        };
        let value = measure_at(instrument, &mut hdr, &axes, None)?.value;
        checks.push(CheckValue {
            theta_h_deg: theta_h,
            measured: calibration.brdf(value.rate_dn_s, wi.z),
            wi,
            wo,
        });
    }
    Ok(checks)
}

/// [`measure_check`] on a sample whose BRDF is `truth`, beside the truth's values; a
/// geometry the truth does not answer is left out.
pub fn check_against_truth(
    instrument: &mut dyn Instrument,
    device: &Device,
    calibration: &Calibration,
    truth: &dyn Brdf,
    theta_h_deg: &[f64],
) -> Result<Vec<TruthCheck>, InstrumentError> {
    Ok(measure_check(instrument, device, calibration, theta_h_deg)?
        .into_iter()
        .filter_map(|check| {
            Some(TruthCheck {
                theta_h_deg: check.theta_h_deg,
                measured: check.measured,
                truth: truth.eval(check.wi, check.wo)?,
            })
        })
        .collect())
}
