//! A calibration in words, as `specula calibrate` prints it: the noise model, the gains to
//! 1/sr, the white reference, the colour matrix and the measured response
//! ([`CalibrationText`]), and the check measurement beside the truth's values
//! ([`CheckTable`]).

use crate::calibrate::CalibrationRun;
use specula_acquisition::calibration::truth_check::{
    CheckValue, TRUTH_CHECK_PHI_D_DEG, TRUTH_CHECK_PHI_H_DEG, TRUTH_CHECK_THETA_D_DEG,
};
use specula_acquisition::calibration::Calibration;
use specula_acquisition::device::Device;
use specula_core::Brdf;
use std::fmt;

/// A calibration in words; the device file's light radius beside the measured one.
pub struct CalibrationText<'a> {
    /// The calibration.
    pub calibration: &'a Calibration,
    /// The device described.
    pub device: &'a Device,
}

impl fmt::Display for CalibrationText<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let cal = self.calibration;
        let n = &cal.noise;
        writeln!(
            f,
            "noise model: black {:.2} DN, dark current {:.3} DN/s, read noise {:.3} DN, gain {:.4} DN/e-",
            n.black_level_dn, n.dark_current_dn_s, n.read_noise_dn, n.gain_dn_per_e
        )?;
        let g = cal.gain_dn_s_per_sr;
        writeln!(
            f,
            "gain to 1/sr: R {:.5e}  G {:.5e}  B {:.5e} DN/s per 1/sr",
            g[0], g[1], g[2]
        )?;
        if let Some(c) = &cal.white_certificate {
            let (r, u) = (c.reflectance, c.uncertainty);
            writeln!(
                f,
                "white reference: R {:.4} +- {:.4}  G {:.4} +- {:.4}  B {:.4} +- {:.4} (certificate)",
                r[0], u[0], r[1], u[1], r[2], u[2]
            )?;
        }
        writeln!(f, "colour matrix (camera to linear sRGB):")?;
        for row in cal.colour_matrix {
            writeln!(f, "  {:+.4} {:+.4} {:+.4}", row[0], row[1], row[2])?;
        }
        writeln!(
            f,
            "ColorChecker fit: {:.4} RMS (linear sRGB reflectance)",
            cal.colour_rms_error
        )?;
        if let Some(fit) = &cal.response {
            writeln!(
                f,
                "response ({}): light radius {:.4} deg (device file {:.4} deg), scan centre {:+.4} deg, fit residual {:.4} of the peak; resolution {:.3} deg in theta_h",
                fit.reference,
                fit.response.light.radius_deg,
                self.device.response().light.radius_deg,
                fit.centre_offset_deg,
                fit.rms_relative,
                fit.response.resolution_deg()
            )?;
        }
        Ok(())
    }
}

/// The check measurement of a calibration run, beside the truth's values when there is one.
pub struct CheckTable<'a> {
    /// The run.
    pub run: &'a CalibrationRun,
    /// The simulated truth, if any.
    pub truth: Option<&'a dyn Brdf>,
    /// The device (its light's size explains ratios below 1 near the highlight).
    pub device: &'a Device,
}

impl fmt::Display for CheckTable<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "check on the sample (theta_d {TRUTH_CHECK_THETA_D_DEG}, phi_d {TRUTH_CHECK_PHI_D_DEG}, phi_h {TRUTH_CHECK_PHI_H_DEG} deg):"
        )?;
        let truth_of = |check: &CheckValue| self.truth.and_then(|t| t.eval(check.wi, check.wo));
        match self.truth {
            Some(_) => writeln!(
                f,
                "theta_h_deg,measured_r,measured_g,measured_b,truth_r,truth_g,truth_b,ratio_g"
            )?,
            None => writeln!(f, "theta_h_deg,measured_r,measured_g,measured_b")?,
        }
        for check in &self.run.checks {
            let m = check.measured;
            write!(
                f,
                "{},{:.4e},{:.4e},{:.4e}",
                check.theta_h_deg, m.x, m.y, m.z
            )?;
            match truth_of(check) {
                Some(t) => writeln!(f, ",{:.4e},{:.4e},{:.4e},{:.4}", t.x, t.y, t.z, m.y / t.y)?,
                None => writeln!(f)?,
            }
        }
        if self.truth.is_some() {
            writeln!(
                f,
                "(near the highlight the light's {:.1} deg disk blurs a sharp lobe: ratios below 1 there \
                 are the source's size, not the calibration)",
                self.device.light_radius_deg()
            )?;
        }
        Ok(())
    }
}
