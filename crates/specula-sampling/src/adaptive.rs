//! The adaptive samples of paper Fig. 13 as a file, to draw against the probe: a CSV with a
//! `theta_h` column (degrees) and, where they were measured, `r`, `g` and `b` columns
//! (f_r in 1/sr); other columns are passed over.

use crate::error::SamplingError;
use specula_core::{ProbePoint, Rgb};
use std::path::Path;

/// The adaptive samples a file holds, in increasing theta_h.
#[derive(Debug, Clone, PartialEq)]
pub enum AdaptiveSamples {
    /// Positions with their measured values.
    Measured(Vec<ProbePoint>),
    /// Positions only, degrees: their values are to be read off the probe.
    Positions(Vec<f64>),
}

impl AdaptiveSamples {
    /// Reads the file; every value must be a finite number, and there must be a row.
    pub fn read_csv(path: &Path) -> Result<Self, SamplingError> {
        let csv_error = |place: String| SamplingError::csv(path, place);
        let mut reader = SamplingError::open_csv(path)?;
        let headers = reader
            .headers()
            .map_err(csv_error("cannot read the header".to_string()))?
            .clone();
        let column = |wanted: &str| headers.iter().position(|h| h.trim() == wanted);
        let Some(theta_h) = column("theta_h") else {
            return Err(SamplingError::NoColumn {
                path: path.to_path_buf(),
                column: "theta_h",
                found: specula_core::shown::excerpt(&headers.iter().collect::<Vec<_>>().join(",")),
            });
        };
        let rgb = match (column("r"), column("g"), column("b")) {
            (Some(r), Some(g), Some(b)) => Some([r, g, b]),
            _ => None,
        };
        let mut rows = Vec::new();
        for (line, record) in reader.records().enumerate() {
            let row = line + 2;
            let record = record.map_err(csv_error(format!("row {row}")))?;
            let number = |i: usize| {
                let text = record.get(i).unwrap_or("").trim();
                text.parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| SamplingError::NotANumber {
                        path: path.to_path_buf(),
                        row,
                        text: text.to_string(),
                    })
            };
            let t = number(theta_h)?;
            let value = match rgb {
                Some([r, g, b]) => Some(Rgb::new(number(r)?, number(g)?, number(b)?)),
                None => None,
            };
            rows.push((t, value));
        }
        if rows.is_empty() {
            return Err(SamplingError::NoRows {
                path: path.to_path_buf(),
            });
        }
        rows.sort_by(|a, b| a.0.total_cmp(&b.0));
        Ok(match rgb {
            Some(_) => Self::Measured(
                rows.into_iter()
                    .map(|(t, v)| ProbePoint::new(t, v.unwrap_or_default()))
                    .collect(),
            ),
            None => Self::Positions(rows.into_iter().map(|(t, _)| t).collect()),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<AdaptiveSamples, SamplingError> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("adaptive.csv");
        std::fs::write(&path, text).unwrap();
        AdaptiveSamples::read_csv(&path)
    }

    #[test]
    fn positions_alone_or_with_values_in_increasing_theta_h() {
        assert_eq!(
            read("theta_h\n3\n0\n0.5\n").unwrap(),
            AdaptiveSamples::Positions(vec![0.0, 0.5, 3.0])
        );
        assert_eq!(
            read("b,theta_h,g,r,note\n3,2,2,1,x\n6,1,5,4,y\n").unwrap(),
            AdaptiveSamples::Measured(vec![
                ProbePoint::new(1.0, Rgb::new(4.0, 5.0, 6.0)),
                ProbePoint::new(2.0, Rgb::new(1.0, 2.0, 3.0)),
            ])
        );
    }

    #[test]
    fn bad_files_name_the_file_and_the_problem() {
        let message = |text: &str| read(text).unwrap_err().to_string();
        let err = message("position\n1\n");
        assert!(
            err.contains("adaptive.csv: no theta_h column (header: position)"),
            "{err}"
        );
        let err = message("theta_h,r,g,b\n1,2,3,4\n2,2,inf,4\n");
        assert!(err.contains("row 3: 'inf' is not a number"), "{err}");
        assert!(message("theta_h\n").contains("adaptive.csv: no rows"));
    }
}
