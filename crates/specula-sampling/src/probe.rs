//! The probe of section 5.2: a dense theta_h column of a material, taken at fixed
//! `theta_d = 40`, `phi_d = 90`, `phi_h = 45` degrees with up to 90 samples placed by the
//! square-root mapping (paper eq. 1), from which k is fitted and samples are placed. Where
//! and how densely it is taken is [`ProbeSpec`] (in `specula-core`).
//!
//! File form: CSV with the header `theta_h,r,g,b`, theta_h in degrees, f_r in 1/sr.

use crate::column::{scalar_of, Column, ColumnError};
use crate::error::SamplingError;
use specula_core::{Brdf, ProbePoint, ProbeSpec, Rgb};
use std::path::Path;

/// The probe's samples: theta_h in degrees (increasing) and f_r in 1/sr.
#[derive(Debug, Clone, PartialEq)]
pub struct Probe {
    theta_h_deg: Vec<f64>,
    rgb: Vec<Rgb>,
}

#[derive(serde::Serialize, serde::Deserialize)]
struct ProbeRow {
    theta_h: f64,
    r: f64,
    g: f64,
    b: f64,
}

impl Probe {
    /// A probe from samples; checked as a [`Column`] is (increasing theta_h in `[0, 90]`,
    /// finite non-negative values, at least two samples).
    pub fn new(theta_h_deg: Vec<f64>, rgb: Vec<Rgb>) -> Result<Self, ColumnError> {
        assert_eq!(theta_h_deg.len(), rgb.len(), "one value per position");
        for (&theta_h_deg, v) in theta_h_deg.iter().zip(&rgb) {
            if !(v.is_finite() && v.min_element() >= 0.0) {
                return Err(ColumnError::BadValue {
                    theta_h_deg,
                    value: if v.is_finite() {
                        v.min_element()
                    } else {
                        f64::NAN
                    },
                });
            }
        }
        let probe = Self { theta_h_deg, rgb };
        probe.try_column()?;
        Ok(probe)
    }

    /// Takes the probe from a BRDF. Samples the BRDF reports as not measured are left out.
    pub fn take(brdf: &dyn Brdf, settings: &ProbeSpec) -> Result<Self, SamplingError> {
        if settings.samples < 2 {
            return Err(SamplingError::ProbeSamples(settings.samples));
        }
        // phi_h is an azimuth either way round, as the front ends accept it.
        let azimuth = specula_core::request::AZIMUTH_DEG;
        for (what, value, min, max) in [
            ("theta_d", settings.theta_d_deg, 0.0, 90.0),
            ("phi_d", settings.phi_d_deg, 0.0, 360.0),
            ("phi_h", settings.phi_h_deg, azimuth.min, azimuth.max),
        ] {
            if !(min..=max).contains(&value) {
                return Err(SamplingError::ProbeAngle {
                    what,
                    value_deg: value,
                    min_deg: min,
                    max_deg: max,
                });
            }
        }
        let (theta_h_deg, rgb): (Vec<f64>, Vec<Rgb>) = settings
            .theta_h_deg()
            .into_iter()
            .filter_map(|theta_h| {
                brdf.eval_half_diff(settings.half_diff(theta_h))
                    .map(|v| (theta_h, v))
            })
            .unzip();
        Self::new(theta_h_deg, rgb).map_err(|cause| SamplingError::Probe {
            origin: brdf.name(),
            problem: "the probe has too few measured samples",
            cause,
        })
    }

    /// The sample positions theta_h, deg, increasing.
    pub fn theta_h_deg(&self) -> &[f64] {
        &self.theta_h_deg
    }

    /// The measured f_r per sample, 1/sr, in the order of [`Probe::theta_h_deg`].
    pub fn rgb(&self) -> &[Rgb] {
        &self.rgb
    }

    /// The samples as points (theta_h in degrees, f_r in 1/sr), in increasing theta_h.
    pub fn points(&self) -> Vec<ProbePoint> {
        self.theta_h_deg
            .iter()
            .zip(&self.rgb)
            .map(|(&theta_h_deg, &value)| ProbePoint::new(theta_h_deg, value))
            .collect()
    }

    /// Number of samples (at least two).
    pub fn len(&self) -> usize {
        self.rgb.len()
    }

    /// Always false: a probe has at least two samples.
    pub fn is_empty(&self) -> bool {
        false
    }

    fn try_column(&self) -> Result<Column, ColumnError> {
        Column::new(
            self.theta_h_deg.clone(),
            self.rgb.iter().map(|v| scalar_of(*v)).collect(),
        )
    }

    /// The probe as a column of the mean of R, G and B.
    pub fn column(&self) -> Column {
        self.try_column().expect("checked when the probe was made")
    }

    /// Writes the CSV file (header `theta_h,r,g,b`).
    pub fn write_csv(&self, path: &Path) -> Result<(), SamplingError> {
        let mut writer = csv::Writer::from_writer(Vec::new());
        for (&theta_h, v) in self.theta_h_deg.iter().zip(&self.rgb) {
            writer
                .serialize(ProbeRow {
                    theta_h,
                    r: v.x,
                    g: v.y,
                    b: v.z,
                })
                .map_err(SamplingError::csv_write(path))?;
        }
        let bytes = writer
            .into_inner()
            .map_err(|e| SamplingError::io(path, "write")(e.into_error()))?;
        specula_core::atomic_file::write_bytes(path, &bytes)
            .map_err(SamplingError::io(path, "write"))
    }

    /// Reads a CSV file written by [`Probe::write_csv`] (or by hand, or by a device).
    pub fn read_csv(path: &Path) -> Result<Self, SamplingError> {
        let csv_error = |place: String| SamplingError::csv(path, place);
        let mut reader = SamplingError::open_csv(path)?;
        let headers = reader
            .headers()
            .map_err(csv_error("cannot read the header".to_string()))?;
        if headers.iter().map(str::trim).collect::<Vec<_>>() != ["theta_h", "r", "g", "b"] {
            return Err(SamplingError::ProbeHeader {
                path: path.to_path_buf(),
                found: specula_core::shown::excerpt(&headers.iter().collect::<Vec<_>>().join(",")),
            });
        }
        let mut theta_h_deg = Vec::new();
        let mut rgb = Vec::new();
        for (i, record) in reader.deserialize::<ProbeRow>().enumerate() {
            let row = record.map_err(csv_error(format!("row {}: expected four numbers", i + 2)))?;
            theta_h_deg.push(row.theta_h);
            rgb.push(Rgb::new(row.r, row.g, row.b));
        }
        Self::new(theta_h_deg, rgb).map_err(|cause| SamplingError::Probe {
            origin: path.display().to_string(),
            problem: "not a usable probe",
            cause,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;
    use specula_core::HalfDiff;

    /// f = (1 + theta_h_deg) * (1, 2, 3), a known function of theta_h only.
    struct Ramp;
    impl Brdf for Ramp {
        fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
            let hd = HalfDiff::from_directions(wi, wo);
            Some(Rgb::new(1.0, 2.0, 3.0) * (1.0 + hd.theta_h.to_degrees()))
        }
        fn name(&self) -> String {
            "ramp".into()
        }
    }

    #[test]
    fn takes_samples_at_the_square_root_positions() {
        let probe = Probe::take(&Ramp, &ProbeSpec::default()).unwrap();
        assert_eq!(probe.len(), 90);
        for (i, (&x, v)) in probe.theta_h_deg().iter().zip(probe.rgb()).enumerate() {
            let t = 90.0 * i as f64 / 89.0;
            assert!((x - t * t / 90.0).abs() < 1e-9);
            assert!((v.x - (1.0 + x)).abs() < 1e-6, "{x}: {v}");
        }
        let column = probe.column();
        assert!((column.values()[10] - 2.0 * (1.0 + column.theta_h_deg()[10])).abs() < 1e-6);
    }

    #[test]
    fn csv_round_trips() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("probe.csv");
        let probe = Probe::take(
            &Ramp,
            &ProbeSpec {
                samples: 17,
                ..Default::default()
            },
        )
        .unwrap();
        probe.write_csv(&path).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.starts_with("theta_h,r,g,b\n"), "{text}");
        assert_eq!(Probe::read_csv(&path).unwrap(), probe);
    }

    #[test]
    fn bad_files_name_the_file_and_the_problem() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.csv");
        std::fs::write(&path, "theta,r,g,b\n0,1,1,1\n").unwrap();
        let err = format!("{:#}", Probe::read_csv(&path).unwrap_err());
        assert!(err.contains("bad.csv") && err.contains("header"), "{err}");
        std::fs::write(&path, "theta_h,r,g,b\n0,1,1,1\n1,x,1,1\n").unwrap();
        let err = format!("{:#}", Probe::read_csv(&path).unwrap_err());
        assert!(err.contains("row 3"), "{err}");
        std::fs::write(&path, "theta_h,r,g,b\n5,1,1,1\n1,1,1,1\n").unwrap();
        let err = format!("{:#}", Probe::read_csv(&path).unwrap_err());
        assert!(err.contains("increase"), "{err}");
        let err = format!(
            "{:#}",
            Probe::read_csv(&dir.path().join("missing.csv")).unwrap_err()
        );
        assert!(
            err.ends_with("missing.csv: cannot read: no such file"),
            "{err}"
        );
        let err = Probe::read_csv(Path::new("/dev/zero"))
            .unwrap_err()
            .to_string();
        assert_eq!(
            err,
            "/dev/zero: cannot read the header: line 1 is longer than 65536 bytes, the most a line may hold"
        );
        std::fs::write(&path, format!("theta_h,{}\n", "\x1b".repeat(200_000 / 3))).unwrap();
        let err = Probe::read_csv(&path).unwrap_err().to_string();
        assert!(err.len() < 300 && !err.contains('\x1b'), "{err}");
    }

    #[test]
    fn settings_are_checked() {
        let bad = ProbeSpec {
            theta_d_deg: 95.0,
            ..Default::default()
        };
        assert!(Probe::take(&Ramp, &bad).is_err());
        let few = ProbeSpec {
            samples: 1,
            ..Default::default()
        };
        assert!(Probe::take(&Ramp, &few).is_err());
    }
}
