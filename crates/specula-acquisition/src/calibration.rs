//! Calibration: from the camera's raw rates to a BRDF in 1/sr (paper 4.1).
//!
//! Three steps, each with a reference target mounted on the turntable and measured at the
//! 45/0 geometry (light at 45 deg, camera at the normal, the usual geometry for colour
//! targets):
//!
//! 1. **Noise model** ([`measure_noise_model`]), the EMVA 1288 way: dark frames (light off) at
//!    the shortest and longest exposure give the black level, the dark current and the read
//!    noise; pairs of flat frames of the white reference at five exposures give the photon
//!    transfer curve, whose slope `var = gain * signal + var_0` is the conversion gain. Pairs
//!    of frames (half the variance of their difference) cancel any fixed pattern.
//! 2. **Radiometric.** A white diffuse reference of known reflectance `rho` (Lambertian:
//!    `f_r = rho / pi`) has the radiance factor `s = rho cos(theta_i) / pi`; its HDR rate
//!    gives each channel's gain, DN/s at full light per unit radiance factor (1/sr).
//! 3. **Colour.** The 24 ColorChecker patches ([`colorchecker`]), divided by those gains,
//!    give the camera's colour response `u = M rho` to the patches' reference linear-sRGB
//!    reflectances; a 3 x 3 matrix `C` by least squares (`rho ~ C u`, nalgebra's SVD)
//!    undoes the crosstalk, "as the paper does" with its ColorChecker.
//!
//! A measured rate `r` at incidence `theta_i` is then `f_r = C (r / gain) / cos(theta_i)`
//! ([`Calibration::brdf`]). `specula calibrate` stores the result as TOML for later runs.

pub mod colorchecker;
pub mod response;
pub mod truth_check;
pub mod white;

use crate::hdr::{HdrCapturer, HdrSettings, HdrValue, NoiseModel};
use crate::instrument::{Capture, Instrument, InstrumentError, MountOutcome, MountTarget};
use crate::kinematics::AxisPositions;
use glam::{DMat3, DVec3};
use serde::{Deserialize, Serialize};
use specula_core::shown::shown;
use specula_core::{Brdf, Rgb};
use std::f64::consts::PI;
use std::path::Path;

/// A Lambertian reference target: `f_r = reflectance / pi` per channel.
#[derive(Debug, Clone, PartialEq)]
pub struct DiffuseTarget {
    /// The target's name, as its BRDF reports it ([`Brdf::name`]).
    pub name: String,
    /// Diffuse reflectance (albedo) per channel.
    pub reflectance: Rgb,
}

impl DiffuseTarget {
    /// The white reference (a Spectralon-like tile of flat reflectance).
    pub fn white(reflectance: f64) -> Self {
        Self {
            name: format!("white reference {reflectance}"),
            reflectance: Rgb::splat(reflectance),
        }
    }

    /// The ColorChecker patches as targets.
    pub fn colorchecker() -> Vec<DiffuseTarget> {
        colorchecker::PATCHES
            .iter()
            .map(|p| DiffuseTarget {
                name: format!("ColorChecker {}", p.name),
                reflectance: p.reflectance(),
            })
            .collect()
    }
}

impl Brdf for DiffuseTarget {
    fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
        Some(if wi.z > 0.0 && wo.z > 0.0 {
            self.reflectance / PI
        } else {
            Rgb::ZERO
        })
    }

    fn name(&self) -> String {
        self.name.clone()
    }
}

/// Mounts `target` by the device itself ([`Instrument::mount`]), as a simulator or a robot
/// does; a device that leaves it to the operator is an error here (an operator's prompt is
/// the caller's: see `specula calibrate`).
pub fn mount_by_device(
    instrument: &mut dyn Instrument,
    target: &MountTarget,
) -> Result<(), InstrumentError> {
    match instrument.mount(target)? {
        MountOutcome::Mounted => Ok(()),
        MountOutcome::ByOperator => Err(InstrumentError::Disconnected(format!(
            "the device cannot mount {target} itself and no operator was asked"
        ))),
    }
}

/// Why a calibration failed or could not be read.
#[derive(Debug, thiserror::Error)]
pub enum CalibrationError {
    /// The instrument failed while a calibration measured.
    #[error("device: {0}")]
    Instrument(#[from] InstrumentError),
    /// A fit could not be made from the measurements (too few, or degenerate); the message
    /// says why.
    #[error("calibration: {0}")]
    Fit(String),
    /// A calibration file cannot be read, written or parsed.
    #[error("{path}: {message}")]
    File {
        /// The calibration file.
        path: String,
        /// What went wrong reading, writing or parsing it.
        message: String,
    },
    /// A value of a calibration file lies outside its range.
    #[error("{path}: {problem}")]
    Range {
        /// The calibration file.
        path: String,
        /// The value and the range it should lie in.
        problem: OutOfRange,
    },
}

/// The range of a calibration's gains, DN/s at full light per 1/sr: wide enough for any
/// camera behind any light (the simulated UTIA device calibrates to about 2e5), narrow
/// enough that a gain cannot saturate every capture (1e300 would measure a table of zeros)
/// or turn one DN into an absurd BRDF (1e-300 would give 1e304 1/sr).
pub const GAIN_DN_S_PER_SR: (f64, f64) = (1e-2, 1e12);

/// The largest level or noise of a calibration's noise model, DN: a 30-bit sensor.
pub const MAX_DN: f64 = 1e9;

/// The range of a noise model's conversion gain, DN per electron.
pub const GAIN_DN_PER_E: (f64, f64) = (1e-6, 1e6);

/// A calibration value outside its range: `field must be RANGE, got VALUE`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{field} must be {range}, got {}", shown(*.value))]
pub struct OutOfRange {
    /// The field's path in the calibration file, e.g. `noise.gain_dn_per_e`.
    pub field: String,
    /// The range in words, e.g. `positive and finite`.
    pub range: String,
    /// The value found.
    pub value: f64,
}

/// How to calibrate.
#[derive(Debug, Clone, PartialEq)]
pub struct CalibrationOptions {
    /// Reflectance of the white reference (0.99 for a Spectralon tile), the same in every
    /// channel; a certificate's values per channel replace it.
    pub white_reflectance: f64,
    /// The white reference's certificate, integrated per channel
    /// ([`white::WhiteCertificate::load`]), when one is given.
    pub white_certificate: Option<white::WhiteCertificate>,
    /// Elevation of the light, degrees (45 for the 45/0 geometry).
    pub light_elevation_deg: f64,
}

impl Default for CalibrationOptions {
    fn default() -> Self {
        Self {
            white_reflectance: 0.99,
            white_certificate: None,
            light_elevation_deg: 45.0,
        }
    }
}

impl CalibrationOptions {
    /// The axes of the reference geometry: camera at the normal, light in the x-z plane.
    pub fn axes(&self) -> AxisPositions {
        AxisPositions::from_degrees(0.0, 0.0, 180.0, self.light_elevation_deg)
    }

    fn cos_theta_i(&self) -> f64 {
        self.light_elevation_deg.to_radians().cos()
    }

    /// The white reference's reflectance per channel: the certificate's, else
    /// `white_reflectance` in every channel.
    pub fn white_reflectance_rgb(&self) -> [f64; 3] {
        self.white_certificate
            .as_ref()
            .map_or([self.white_reflectance; 3], |c| c.reflectance)
    }
}

/// The calibration of a device: stored by `specula calibrate`, used by later runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Calibration {
    /// The device it belongs to ("model, serial").
    pub device: String,
    /// The reflectance of the white reference used (the mean over channels of a
    /// certificate's).
    pub white_reflectance: f64,
    /// The white reference's certificate per channel (reflectance and its standard
    /// uncertainty), when one was given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub white_certificate: Option<white::WhiteCertificate>,
    /// The light's elevation of the reference geometry, degrees.
    pub light_elevation_deg: f64,
    /// DN/s at full light per unit radiance factor (1/sr), per camera channel. Range:
    /// [`GAIN_DN_S_PER_SR`].
    pub gain_dn_s_per_sr: [f64; 3],
    /// Camera colour (gain-normalised) to linear sRGB, rows.
    pub colour_matrix: [[f64; 3]; 3],
    /// RMS error of the matrix over the 24 patches, linear sRGB reflectance.
    pub colour_rms_error: f64,
    /// The colour reference used.
    pub colour_reference: String,
    /// The camera's noise model, measured from dark and flat frames (EMVA 1288,
    /// [`measure_noise_model`]).
    pub noise: NoiseModel,
    /// The instrument's response measured with the reference mirror
    /// ([`response::measure_response`]); absent in files made before it was measured.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub response: Option<response::ResponseFit>,
}

impl Calibration {
    fn matrix(&self) -> DMat3 {
        DMat3::from_cols_array_2d(&self.colour_matrix).transpose()
    }

    /// The BRDF (1/sr) of a rate measured with the light at incidence `cos_theta_i`.
    pub fn brdf(&self, rate_dn_s: [f64; 3], cos_theta_i: f64) -> Rgb {
        let camera = DVec3::from(rate_dn_s) / DVec3::from(self.gain_dn_s_per_sr);
        self.matrix() * camera / cos_theta_i
    }

    /// The BRDF of an HDR value and its standard deviation per channel (channels taken as
    /// independent).
    pub fn brdf_with_sigma(&self, value: &HdrValue, cos_theta_i: f64) -> (Rgb, Rgb) {
        (
            self.brdf(value.rate_dn_s, cos_theta_i),
            self.brdf_sigma(value.sigma_dn_s, cos_theta_i),
        )
    }

    /// The standard deviation per channel of the BRDF of a rate with standard deviation
    /// `sigma_dn_s` (channels taken as independent, through the colour matrix).
    fn brdf_sigma(&self, sigma_dn_s: [f64; 3], cos_theta_i: f64) -> Rgb {
        let m = self.matrix();
        let sigma_camera = DVec3::from(sigma_dn_s) / DVec3::from(self.gain_dn_s_per_sr);
        let squared = DMat3::from_cols(
            m.x_axis * m.x_axis,
            m.y_axis * m.y_axis,
            m.z_axis * m.z_axis,
        ) * (sigma_camera * sigma_camera);
        squared.map(f64::sqrt) / cos_theta_i
    }

    /// The relative standard deviation of the BRDF value of a rate with standard deviation
    /// `sigma_dn_s`: the camera's noise through the colour matrix
    /// ([`Calibration::brdf_with_sigma`]), per channel; infinite in a channel whose sigma is
    /// not finite (a camera channel saturated in every capture that mixes into it: the value is
    /// a lower bound) or whose value is not positive.
    pub fn relative_sigma(&self, rate_dn_s: [f64; 3], sigma_dn_s: [f64; 3]) -> Rgb {
        let (brdf, sigma) = (self.brdf(rate_dn_s, 1.0), self.brdf_sigma(sigma_dn_s, 1.0));
        Rgb::from(std::array::from_fn(|c| {
            let r = sigma[c] / brdf[c];
            if r.is_finite() && brdf[c] > 0.0 {
                r
            } else {
                f64::INFINITY
            }
        }))
    }

    /// The brightest channel's rate (DN/s at full light) a BRDF value should give: the
    /// prediction that starts an HDR measurement.
    pub fn predicted_rate_dn_s(&self, brdf: Rgb, cos_theta_i: f64) -> f64 {
        let camera = self.matrix().inverse() * (brdf * cos_theta_i);
        (camera * DVec3::from(self.gain_dn_s_per_sr)).max_element()
    }

    /// Writes the calibration as TOML.
    pub fn save(&self, path: &Path) -> Result<(), CalibrationError> {
        let text = toml::to_string_pretty(self).expect("a calibration always serialises");
        let header =
            "# Specula camera calibration (specula calibrate): noise model, gains to 1/sr\n\
                      # and the colour matrix to linear sRGB. See the guide,\n\
                      # docs/book/src/calibrate.md.\n";
        specula_core::atomic_file::write_bytes(path, format!("{header}{text}").as_bytes()).map_err(
            |e| CalibrationError::File {
                path: path.display().to_string(),
                message: format!("cannot write: {e}"),
            },
        )
    }

    /// Reads a calibration written by [`Calibration::save`].
    pub fn load(path: &Path) -> Result<Calibration, CalibrationError> {
        let name = path.display().to_string();
        let text = specula_core::bounded_read::read_toml_text(path).map_err(|e| {
            CalibrationError::File {
                path: name.clone(),
                message: format!("cannot read: {e}"),
            }
        })?;
        let calibration: Calibration =
            toml::from_str(&text).map_err(|e| CalibrationError::File {
                path: name.clone(),
                message: e.message().trim().replace('\n', " "),
            })?;
        calibration
            .validate()
            .map_err(|problem| CalibrationError::Range {
                path: name,
                problem,
            })?;
        Ok(calibration)
    }

    /// The first value outside its range, as `field must be RANGE, got VALUE`: gains in
    /// [`GAIN_DN_S_PER_SR`], the colour matrix finite and invertible, the noise model's
    /// levels and noise up to [`MAX_DN`] with its black level below its white level and its
    /// conversion gain in [`GAIN_DN_PER_E`], the reference's reflectance in (0, 1].
    pub fn validate(&self) -> Result<(), OutOfRange> {
        let rule = |ok: bool, field: &str, range: &str, value: f64| {
            if ok {
                Ok(())
            } else {
                Err(OutOfRange {
                    field: field.to_string(),
                    range: range.to_string(),
                    value,
                })
            }
        };
        for (c, &gain) in self.gain_dn_s_per_sr.iter().enumerate() {
            let field = format!("gain_dn_s_per_sr[{c}]");
            let (min, max) = GAIN_DN_S_PER_SR;
            rule(
                (min..=max).contains(&gain),
                &field,
                &format!("from {} to {}", shown(min), shown(max)),
                gain,
            )?;
        }
        for (r, row) in self.colour_matrix.iter().enumerate() {
            for (c, &v) in row.iter().enumerate() {
                rule(
                    v.is_finite(),
                    &format!("colour_matrix[{r}][{c}]"),
                    "finite",
                    v,
                )?;
            }
        }
        let m = self.matrix();
        let scale = self
            .colour_matrix
            .iter()
            .flatten()
            .fold(0.0f64, |a, v| a.max(v.abs()));
        let det = m.determinant();
        rule(
            scale > 0.0 && det.abs() > 1e-9 * scale.powi(3),
            "colour_matrix",
            "invertible (its determinant is not 0)",
            det,
        )?;
        let w = self.white_reflectance;
        rule(w > 0.0 && w <= 1.0, "white_reflectance", "in (0, 1]", w)?;
        if let Some(certificate) = &self.white_certificate {
            for c in 0..3 {
                let r = certificate.reflectance[c];
                let field = format!("white_certificate.reflectance[{c}]");
                rule(r > 0.0 && r <= 1.0, &field, "in (0, 1]", r)?;
                let u = certificate.uncertainty[c];
                let field = format!("white_certificate.uncertainty[{c}]");
                rule((0.0..1.0).contains(&u), &field, "in [0, 1)", u)?;
            }
        }
        let e = self.light_elevation_deg;
        rule(
            (0.0..90.0).contains(&e),
            "light_elevation_deg",
            "in [0, 90)",
            e,
        )?;
        let n = &self.noise;
        let black = n.black_level_dn;
        let dn = |v: f64| (0.0..=MAX_DN).contains(&v);
        let dn_range = format!("from 0 to {}", shown(MAX_DN));
        rule(dn(black), "noise.black_level_dn", &dn_range, black)?;
        let white = n.white_level_dn;
        let range = format!(
            "above noise.black_level_dn ({}) and at most {}",
            shown(black),
            shown(MAX_DN)
        );
        rule(
            dn(white) && white > black,
            "noise.white_level_dn",
            &range,
            white,
        )?;
        let g = n.gain_dn_per_e;
        let (min, max) = GAIN_DN_PER_E;
        rule(
            (min..=max).contains(&g),
            "noise.gain_dn_per_e",
            &format!("from {} to {}", shown(min), shown(max)),
            g,
        )?;
        let read = n.read_noise_dn;
        rule(dn(read), "noise.read_noise_dn", &dn_range, read)?;
        let dark = n.dark_current_dn_s;
        rule(dn(dark), "noise.dark_current_dn_s", &dn_range, dark)?;
        match &self.response {
            Some(fit) => validate_response(fit, &rule),
            None => Ok(()),
        }
    }
}

/// One range check of [`Calibration::validate`]: whether the value is in range, the field's
/// name, the range in words and the value; an error names the field.
type RangeRule<'a> = dyn Fn(bool, &str, &str, f64) -> Result<(), OutOfRange> + 'a;

/// The response's first value outside its range (see [`Calibration::validate`]): angles in
/// [0, 90) degrees, the emission profile zero or positive, the footprint zero or positive,
/// the distances positive, the fit residual zero or positive.
fn validate_response(fit: &response::ResponseFit, rule: &RangeRule<'_>) -> Result<(), OutOfRange> {
    let r = &fit.response;
    let angle = |v: f64| (0.0..90.0).contains(&v);
    let at_least_zero = |v: f64| v.is_finite() && v >= 0.0;
    let positive = |v: f64| v.is_finite() && v > 0.0;
    rule(
        angle(r.light.radius_deg),
        "response.response.light.radius_deg",
        "in [0, 90)",
        r.light.radius_deg,
    )?;
    for (i, &e) in r.light.emission.iter().enumerate() {
        rule(
            at_least_zero(e),
            &format!("response.response.light.emission[{i}]"),
            "zero or positive",
            e,
        )?;
    }
    rule(
        angle(r.camera_aperture_deg),
        "response.response.camera_aperture_deg",
        "in [0, 90)",
        r.camera_aperture_deg,
    )?;
    rule(
        at_least_zero(r.footprint_radius_m),
        "response.response.footprint_radius_m",
        "zero or positive",
        r.footprint_radius_m,
    )?;
    rule(
        positive(r.light_distance_m),
        "response.response.light_distance_m",
        "positive and finite",
        r.light_distance_m,
    )?;
    rule(
        positive(r.camera_distance_m),
        "response.response.camera_distance_m",
        "positive and finite",
        r.camera_distance_m,
    )?;
    rule(
        at_least_zero(fit.rms_relative),
        "response.rms_relative",
        "zero or positive",
        fit.rms_relative,
    )
}

/// The 3 x 3 matrix `C` minimising `sum |C camera_p - reference_p|^2`, by SVD least squares.
pub fn fit_colour_matrix(camera: &[DVec3], reference: &[DVec3]) -> Result<DMat3, CalibrationError> {
    if camera.len() != reference.len() || camera.len() < 3 {
        return Err(CalibrationError::Fit(format!(
            "need at least 3 pairs of colours, got {} and {}",
            camera.len(),
            reference.len()
        )));
    }
    let a = nalgebra::DMatrix::from_fn(camera.len(), 3, |i, j| camera[i][j]);
    let b = nalgebra::DMatrix::from_fn(reference.len(), 3, |i, j| reference[i][j]);
    let svd = a.svd(true, true);
    if svd.rank(1e-9 * svd.singular_values.max()) < 3 {
        return Err(CalibrationError::Fit(
            "the measured colours do not span three dimensions".into(),
        ));
    }
    let x = svd
        .solve(&b, 1e-12)
        .map_err(|e| CalibrationError::Fit(e.to_string()))?;
    // camera_row * x = reference_row, so C = x^T.
    Ok(DMat3::from_cols_array_2d(&[
        [x[(0, 0)], x[(1, 0)], x[(2, 0)]],
        [x[(0, 1)], x[(1, 1)], x[(2, 1)]],
        [x[(0, 2)], x[(1, 2)], x[(2, 2)]],
    ])
    .transpose())
}

/// Mean over pixels of channel `c`, and half the variance of the difference of two frames.
fn pair_statistics(a: &Capture, b: &Capture, c: usize) -> Result<(f64, f64), CalibrationError> {
    let (Some(pa), Some(pb)) = (a.pixels.as_ref(), b.pixels.as_ref()) else {
        return Err(CalibrationError::Fit(
            "the device returned no pixels for the noise measurement".into(),
        ));
    };
    let n = pa.len().min(pb.len()) as f64;
    let diffs: Vec<f64> = pa
        .iter()
        .zip(pb)
        .map(|(x, y)| (x[c] - y[c]) as f64)
        .collect();
    let mean_diff = diffs.iter().sum::<f64>() / n;
    let var = diffs.iter().map(|d| (d - mean_diff).powi(2)).sum::<f64>() / (n - 1.0);
    Ok(((a.mean_raw[c] + b.mean_raw[c]) / 2.0, var / 2.0))
}

/// Measures the sensor's noise model with a flat white target in view (see the module
/// documentation). Leaves the light at full power.
pub fn measure_noise_model(
    instrument: &mut dyn Instrument,
) -> Result<NoiseModel, CalibrationError> {
    let info = instrument.info()?;
    let (shortest, longest) = info.exposure_range_s;
    let pair =
        |instrument: &mut dyn Instrument, t: f64| -> Result<(Capture, Capture), CalibrationError> {
            Ok((instrument.capture(t, true)?, instrument.capture(t, true)?))
        };

    // Dark frames.
    instrument.set_light(0.0)?;
    let (short_a, short_b) = pair(instrument, shortest)?;
    let long = instrument.capture(longest, false)?;
    let mean3 = |v: [f64; 3]| v.iter().sum::<f64>() / 3.0;
    let dark_short = (mean3(short_a.mean_raw) + mean3(short_b.mean_raw)) / 2.0;
    let dark_current_dn_s = (mean3(long.mean_raw) - dark_short) / (longest - shortest);
    let black_level_dn = dark_short - dark_current_dn_s * shortest;
    let mut read_var = 0.0;
    for c in 0..3 {
        read_var += pair_statistics(&short_a, &short_b, c)?.1 / 3.0;
    }
    let read_noise_dn = (read_var - 1.0 / 12.0).max(0.0).sqrt();

    // Photon transfer on the white target.
    instrument.set_light(1.0)?;
    let probe = instrument.capture(shortest, false)?;
    let probe_signal = probe.mean_raw.iter().fold(f64::MIN, |m, v| m.max(*v)) - black_level_dn;
    if probe.saturated_fraction.iter().any(|&f| f > 0.0) || probe_signal <= 1.0 {
        return Err(CalibrationError::Fit(format!(
            "the white target gives {probe_signal:.1} DN at the shortest exposure: \
             too bright or too dark for the photon transfer curve"
        )));
    }
    let headroom = info.white_level - black_level_dn;
    let mut points = Vec::new();
    for fraction in [0.1, 0.25, 0.4, 0.55, 0.7] {
        let t = (shortest * fraction * headroom / probe_signal).clamp(shortest, longest);
        let (a, b) = pair(instrument, t)?;
        for c in 0..3 {
            if a.saturated_fraction[c] > 0.0 || b.saturated_fraction[c] > 0.0 {
                continue;
            }
            let (mean, var) = pair_statistics(&a, &b, c)?;
            points.push((mean - black_level_dn - dark_current_dn_s * t, var));
        }
    }
    let gain_dn_per_e = photon_transfer_slope(&points)?;
    Ok(NoiseModel {
        black_level_dn,
        dark_current_dn_s,
        gain_dn_per_e,
        read_noise_dn,
        white_level_dn: info.white_level,
    })
}

/// Least-squares slope of variance against signal.
fn photon_transfer_slope(points: &[(f64, f64)]) -> Result<f64, CalibrationError> {
    let n = points.len() as f64;
    let (sx, sy) = points
        .iter()
        .fold((0.0, 0.0), |(sx, sy), (x, y)| (sx + x, sy + y));
    let (mx, my) = (sx / n, sy / n);
    let sxx: f64 = points.iter().map(|(x, _)| (x - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    if points.len() < 3 || sxx <= 0.0 {
        return Err(CalibrationError::Fit(
            "too few unsaturated frames for the photon transfer curve".into(),
        ));
    }
    Ok(sxy / sxx)
}

/// Calibrates a device. `mount` puts a reference target on the turntable (the operator's job
/// on a real device, [`mount_by_device`] for a simulator or a robot): the white reference,
/// then each ColorChecker patch in turn.
pub fn calibrate(
    instrument: &mut dyn Instrument,
    mut mount: impl FnMut(&mut dyn Instrument, &MountTarget) -> Result<(), InstrumentError>,
    options: &CalibrationOptions,
) -> Result<Calibration, CalibrationError> {
    let info = instrument.info()?;
    instrument.move_to(&options.axes())?;
    mount(instrument, &MountTarget::White)?;
    let noise = measure_noise_model(instrument)?;
    let mut hdr = HdrCapturer::new(HdrSettings::for_device(&info), noise);

    let cos_i = options.cos_theta_i();
    let white_reflectance = options.white_reflectance_rgb();
    let white_rate = hdr.measure(instrument, None)?.value;
    if white_rate.saturated.iter().any(|&s| s) {
        return Err(CalibrationError::Fit(
            "the white reference saturates".into(),
        ));
    }
    let mut gain = white_rate.rate_dn_s;
    for (g, rho) in gain.iter_mut().zip(white_reflectance) {
        *g /= rho * cos_i / PI;
    }

    let mut camera = Vec::with_capacity(colorchecker::PATCHES.len());
    let mut reference = Vec::with_capacity(colorchecker::PATCHES.len());
    let predicted = white_rate.brightest_rate_dn_s();
    for patch in colorchecker::PATCHES {
        let target = MountTarget::Colorchecker {
            patch: patch.name.to_string(),
        };
        mount(instrument, &target)?;
        let value = hdr.measure(
            instrument,
            Some(predicted * patch.reflectance().max_element()),
        )?;
        let rate = DVec3::from(value.value.rate_dn_s);
        camera.push(rate / DVec3::from(gain) * PI / cos_i);
        reference.push(patch.reflectance());
    }
    let matrix = fit_colour_matrix(&camera, &reference)?;
    let squared: f64 = camera
        .iter()
        .zip(&reference)
        .map(|(u, r)| (matrix * *u - *r).length_squared())
        .sum();
    Ok(Calibration {
        device: format!("{}, {}", info.model, info.serial),
        white_reflectance: white_reflectance.iter().sum::<f64>() / 3.0,
        white_certificate: options.white_certificate,
        light_elevation_deg: options.light_elevation_deg,
        gain_dn_s_per_sr: gain,
        colour_matrix: matrix.transpose().to_cols_array_2d(),
        colour_rms_error: (squared / (3.0 * camera.len() as f64)).sqrt(),
        colour_reference: "X-Rite ColorChecker Classic (November 2014 on), L*a*b* D50 as \
                           linear sRGB D65"
            .into(),
        noise,
        response: None,
    })
}

#[cfg(test)]
mod tests;
