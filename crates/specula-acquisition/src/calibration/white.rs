//! The white reference's certificate: its reflectance factor and standard uncertainty per
//! channel, as a calibration laboratory certifies a Spectralon tile.
//!
//! A certificate file (TOML) gives either three values, one per channel (R, G, B):
//!
//! ```toml
//! reflectance = [0.991, 0.990, 0.988]
//! uncertainty = [0.004, 0.004, 0.005]
//! ```
//!
//! or a spectrum, which is integrated per channel:
//!
//! ```toml
//! wavelength_nm = [380, 390, 400, ..., 780]
//! reflectance = [0.975, 0.980, 0.984, ..., 0.990]
//! uncertainty = [0.006, 0.006, 0.005, ..., 0.005]
//! ```
//!
//! A channel of the calibration is a channel of linear sRGB (the colour matrix maps the
//! camera to it), so a spectrum is weighted by that channel's colour matching function
//! (the CIE 1931 functions in Wyman, Sloan and Shirley's analytic form, 2013, through the
//! XYZ-to-linear-sRGB matrix) under an equal-energy light, and normalised so that a flat
//! spectrum gives its own value. The uncertainty is integrated the same way with the
//! weights' magnitudes (errors taken as correlated across wavelengths: the conservative
//! choice). The spectrum must cover 400 to 700 nm, where the weights are.

use serde::{Deserialize, Serialize};
use std::path::Path;

/// The white reference's reflectance and its standard uncertainty per channel (R, G, B).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WhiteCertificate {
    /// Reflectance factor per channel, in (0, 1].
    pub reflectance: [f64; 3],
    /// Standard uncertainty of the reflectance per channel, in [0, 1).
    pub uncertainty: [f64; 3],
}

/// The certificate file as written: per channel or per wavelength.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct CertificateFile {
    #[serde(default)]
    wavelength_nm: Option<Vec<f64>>,
    reflectance: Vec<f64>,
    uncertainty: Vec<f64>,
}

/// A certificate file that cannot be used: the file and the problem.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{path}: {problem}")]
pub struct CertificateError {
    /// The certificate file.
    pub path: String,
    /// What is wrong with it.
    pub problem: String,
}

/// The shortest and longest wavelength a spectrum must reach, nm.
const SPECTRUM_SPAN_NM: (f64, f64) = (400.0, 700.0);

/// XYZ to linear sRGB (IEC 61966-2-1), rows.
const XYZ_TO_SRGB: [[f64; 3]; 3] = [
    [3.2406, -1.5372, -0.4986],
    [-0.9689, 1.8758, 0.0415],
    [0.0557, -0.2040, 1.0570],
];

/// A piecewise Gaussian: `sigma_low` below `mean_nm`, `sigma_high` above.
fn lobe(wavelength_nm: f64, mean_nm: f64, sigma_low: f64, sigma_high: f64) -> f64 {
    let sigma = if wavelength_nm < mean_nm {
        sigma_low
    } else {
        sigma_high
    };
    (-0.5 * ((wavelength_nm - mean_nm) / sigma).powi(2)).exp()
}

/// The CIE 1931 colour matching functions at a wavelength (Wyman, Sloan and Shirley 2013,
/// the multi-lobe fit).
fn cie_1931_xyz(nm: f64) -> [f64; 3] {
    [
        1.056 * lobe(nm, 599.8, 37.9, 31.0) + 0.362 * lobe(nm, 442.0, 16.0, 26.7)
            - 0.065 * lobe(nm, 501.1, 20.4, 26.2),
        0.821 * lobe(nm, 568.8, 46.9, 40.5) + 0.286 * lobe(nm, 530.9, 16.3, 31.1),
        1.217 * lobe(nm, 437.0, 11.8, 36.0) + 0.681 * lobe(nm, 459.0, 26.0, 13.8),
    ]
}

/// The weight of linear sRGB channel `channel` at a wavelength.
fn channel_weight(channel: usize, nm: f64) -> f64 {
    let xyz = cie_1931_xyz(nm);
    (0..3).map(|j| XYZ_TO_SRGB[channel][j] * xyz[j]).sum()
}

/// The trapezoid rule's integral of `f` sampled at `x`.
fn trapezoid(x: &[f64], f: impl Fn(usize) -> f64) -> f64 {
    (1..x.len())
        .map(|i| 0.5 * (x[i] - x[i - 1]) * (f(i) + f(i - 1)))
        .sum()
}

impl WhiteCertificate {
    /// The same reflectance in every channel, without uncertainty.
    pub fn flat(reflectance: f64) -> Self {
        Self {
            reflectance: [reflectance; 3],
            uncertainty: [0.0; 3],
        }
    }

    /// Reads a certificate file (see the module documentation).
    pub fn load(path: &Path) -> Result<Self, CertificateError> {
        let error = |problem: String| CertificateError {
            path: path.display().to_string(),
            problem,
        };
        let text = specula_core::bounded_read::read_toml_text(path).map_err(|e| {
            error(format!(
                "cannot read: {}",
                specula_core::shown::io_cause(&e)
            ))
        })?;
        Self::from_toml_str(&text).map_err(error)
    }

    /// Parses a certificate (see the module documentation); the error is the problem in
    /// words.
    pub fn from_toml_str(text: &str) -> Result<Self, String> {
        let file: CertificateFile =
            toml::from_str(text).map_err(|e| e.message().trim().replace('\n', " "))?;
        let certificate = match &file.wavelength_nm {
            None => Self::per_channel(&file)?,
            Some(wavelength_nm) => Self::integrated(wavelength_nm, &file)?,
        };
        certificate.check()?;
        Ok(certificate)
    }

    fn per_channel(file: &CertificateFile) -> Result<Self, String> {
        let three = |values: &[f64], name: &str| -> Result<[f64; 3], String> {
            values.try_into().map_err(|_| {
                format!(
                    "{name} must hold 3 values (R, G, B) without wavelength_nm, got {}",
                    values.len()
                )
            })
        };
        Ok(Self {
            reflectance: three(&file.reflectance, "reflectance")?,
            uncertainty: three(&file.uncertainty, "uncertainty")?,
        })
    }

    fn integrated(wavelength_nm: &[f64], file: &CertificateFile) -> Result<Self, String> {
        let n = wavelength_nm.len();
        if file.reflectance.len() != n || file.uncertainty.len() != n {
            return Err(format!(
                "wavelength_nm, reflectance and uncertainty must have the same length, got {}, {} and {}",
                n,
                file.reflectance.len(),
                file.uncertainty.len()
            ));
        }
        if wavelength_nm
            .windows(2)
            .any(|w| w[0].partial_cmp(&w[1]) != Some(std::cmp::Ordering::Less))
        {
            return Err("wavelength_nm must increase".into());
        }
        let (first, last) = (wavelength_nm.first(), wavelength_nm.last());
        let covers = matches!((first, last), (Some(a), Some(b)) if *a <= SPECTRUM_SPAN_NM.0 && *b >= SPECTRUM_SPAN_NM.1);
        if !covers {
            return Err(format!(
                "the spectrum must cover {} to {} nm",
                SPECTRUM_SPAN_NM.0, SPECTRUM_SPAN_NM.1
            ));
        }
        let mut certificate = Self::flat(0.0);
        for c in 0..3 {
            let w = |i: usize| channel_weight(c, wavelength_nm[i]);
            let norm = trapezoid(wavelength_nm, w);
            let norm_abs = trapezoid(wavelength_nm, |i| w(i).abs());
            certificate.reflectance[c] =
                trapezoid(wavelength_nm, |i| w(i) * file.reflectance[i]) / norm;
            certificate.uncertainty[c] =
                trapezoid(wavelength_nm, |i| w(i).abs() * file.uncertainty[i]) / norm_abs;
        }
        Ok(certificate)
    }

    /// The first value out of its range, in words.
    fn check(&self) -> Result<(), String> {
        for c in 0..3 {
            let (r, u) = (self.reflectance[c], self.uncertainty[c]);
            if !(r > 0.0 && r <= 1.0) {
                return Err(format!(
                    "reflectance must be in (0, 1], got {r} (channel {c})"
                ));
            }
            if !(0.0..1.0).contains(&u) {
                return Err(format!(
                    "uncertainty must be in [0, 1), got {u} (channel {c})"
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn three_values_are_the_channels() {
        let c = WhiteCertificate::from_toml_str(
            "reflectance = [0.99, 0.98, 0.97]\nuncertainty = [0.01, 0.02, 0.03]",
        )
        .unwrap();
        assert_eq!(c.reflectance, [0.99, 0.98, 0.97]);
        assert_eq!(c.uncertainty, [0.01, 0.02, 0.03]);
        let err = WhiteCertificate::from_toml_str("reflectance = [0.9]\nuncertainty = [0.1]")
            .unwrap_err();
        assert!(err.contains("3 values"), "{err}");
        let err = WhiteCertificate::from_toml_str(
            "reflectance = [1.2, 0.9, 0.9]\nuncertainty = [0, 0, 0]",
        )
        .unwrap_err();
        assert!(err.contains("(0, 1]") && err.contains("1.2"), "{err}");
    }

    fn spectrum(reflectance: impl Fn(f64) -> f64) -> String {
        let nm: Vec<f64> = (0..=40).map(|k| 380.0 + 10.0 * k as f64).collect();
        let list = |f: &dyn Fn(f64) -> f64| {
            nm.iter()
                .map(|&l| f(l).to_string())
                .collect::<Vec<_>>()
                .join(", ")
        };
        format!(
            "wavelength_nm = [{}]\nreflectance = [{}]\nuncertainty = [{}]",
            list(&|l| l),
            list(&reflectance),
            list(&|_| 0.005)
        )
    }

    #[test]
    fn a_flat_spectrum_integrates_to_its_value_and_a_sloped_one_splits_the_channels() {
        let flat = WhiteCertificate::from_toml_str(&spectrum(|_| 0.97)).unwrap();
        for c in 0..3 {
            assert!((flat.reflectance[c] - 0.97).abs() < 1e-12, "{flat:?}");
            assert!((flat.uncertainty[c] - 0.005).abs() < 1e-12, "{flat:?}");
        }
        // Rising towards the red: red above green above blue.
        let rising =
            WhiteCertificate::from_toml_str(&spectrum(|l| 0.8 + 0.0004 * (l - 380.0))).unwrap();
        let r = rising.reflectance;
        assert!(r[0] > r[1] && r[1] > r[2], "{r:?}");
        let short = "wavelength_nm = [450, 500]\nreflectance = [0.9, 0.9]\nuncertainty = [0, 0]";
        let err = WhiteCertificate::from_toml_str(short).unwrap_err();
        assert!(err.contains("400 to 700 nm"), "{err}");
    }
}
