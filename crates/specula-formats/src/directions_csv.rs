//! A CSV file of direction pairs at which to evaluate a BRDF (`specula eval`).
//!
//! Header `theta_i,phi_i,theta_o,phi_o`, angles in degrees, one pair a row: theta from 0 to
//! 180 (above 90 a direction is below the horizon, where f_r is 0), phi from -360 to 360.

use crate::input::{csv_error, file_error, open_csv, Result};
use glam::DVec3;
use specula_core::Spherical;
use std::path::Path;

/// A light and a camera direction, in degrees from the normal and around it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize)]
pub struct DirectionPair {
    /// The light's polar angle, degrees (column `theta_i`).
    #[serde(rename = "theta_i")]
    pub theta_i_deg: f64,
    /// The light's azimuth, degrees (column `phi_i`).
    #[serde(rename = "phi_i")]
    pub phi_i_deg: f64,
    /// The camera's polar angle, degrees (column `theta_o`).
    #[serde(rename = "theta_o")]
    pub theta_o_deg: f64,
    /// The camera's azimuth, degrees (column `phi_o`).
    #[serde(rename = "phi_o")]
    pub phi_o_deg: f64,
}

/// The range of a polar angle, degrees.
const THETA_DEG: (f64, f64) = (0.0, 180.0);
/// The range of an azimuth, degrees.
const PHI_DEG: (f64, f64) = (-360.0, 360.0);

impl DirectionPair {
    /// The light and camera directions as unit vectors.
    pub fn directions(&self) -> (DVec3, DVec3) {
        (
            Spherical::from_degrees(self.theta_i_deg, self.phi_i_deg).to_vector(),
            Spherical::from_degrees(self.theta_o_deg, self.phi_o_deg).to_vector(),
        )
    }

    /// The first angle outside its range, in words (`theta_i 200: expected degrees from 0
    /// to 180`); NaN is outside every range.
    fn problem(&self) -> Option<String> {
        [
            ("theta_i", self.theta_i_deg, THETA_DEG),
            ("phi_i", self.phi_i_deg, PHI_DEG),
            ("theta_o", self.theta_o_deg, THETA_DEG),
            ("phi_o", self.phi_o_deg, PHI_DEG),
        ]
        .into_iter()
        .find(|(_, value, (min, max))| !(*min..=*max).contains(value))
        .map(|(column, value, (min, max))| {
            format!("{column} {value}: expected degrees from {min} to {max}")
        })
    }
}

/// Every pair of the file, each row read and its angles checked before any is returned;
/// errors name the file and the row.
pub fn read_direction_pairs(path: &Path) -> Result<Vec<DirectionPair>> {
    let mut reader = open_csv(path)?;
    let mut pairs = Vec::new();
    for (row, record) in reader.deserialize::<DirectionPair>().enumerate() {
        let line = row + 2;
        let pair = record.map_err(|cause| {
            csv_error(
                path,
                format!("row {line}: expected numbers under theta_i,phi_i,theta_o,phi_o"),
                cause,
            )
        })?;
        if let Some(problem) = pair.problem() {
            return Err(file_error(path, format!("row {line}: {problem}")));
        }
        pairs.push(pair);
    }
    Ok(pairs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairs_are_read_checked_and_turned_into_directions() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("dirs.csv");
        std::fs::write(
            &path,
            "theta_i,phi_i,theta_o,phi_o\n0,0,30,180\n95,-360,30,360\n",
        )
        .unwrap();
        let pairs = read_direction_pairs(&path).unwrap();
        assert_eq!(pairs.len(), 2);
        let (wi, wo) = pairs[0].directions();
        assert!((wi - DVec3::Z).length() < 1e-12);
        assert!((wo.z - 30f64.to_radians().cos()).abs() < 1e-12 && wo.x < 0.0);

        std::fs::write(
            &path,
            "theta_i,phi_i,theta_o,phi_o\n10,0,10,180\n-30,0,1,1\n",
        )
        .unwrap();
        let err = read_direction_pairs(&path).unwrap_err().to_string();
        assert!(
            err.contains("dirs.csv: row 3: theta_i -30: expected degrees from 0 to 180"),
            "{err}"
        );
        std::fs::write(&path, "theta_i,phi_i,theta_o,phi_o\n1,2,x,4\n").unwrap();
        let err = read_direction_pairs(&path).unwrap_err().to_string();
        assert!(err.contains("row 2: expected numbers"), "{err}");
        let err = read_direction_pairs(&dir.path().join("none.csv"))
            .unwrap_err()
            .to_string();
        assert!(
            err.ends_with("none.csv: cannot read: no such file"),
            "{err}"
        );
        for endless in [
            "theta_i".repeat(100_000),
            format!("theta_i,phi_i,theta_o,phi_o\n{}", "9".repeat(100_000)),
        ] {
            std::fs::write(&path, endless).unwrap();
            let err = read_direction_pairs(&path).unwrap_err().to_string();
            assert!(
                err.contains("is longer than 65536 bytes, the most a line may hold")
                    && err.len() < 300,
                "{err}"
            );
        }
        let err = read_direction_pairs(Path::new("/dev/zero"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("line 1 is longer than 65536 bytes"), "{err}");
    }
}
