//! The goniometer: its axes, the geometry of its arms and the timing of a capture (paper 4.1).
//!
//! A device is described by a TOML file; `devices/utia.toml` is the default, the paper's UTIA
//! gonioreflectometer (a turntable under the sample, a camera arm with one axis, a light arm
//! with two), and documents every field. Values are in degrees, metres and seconds, as in the
//! file; the kinematics, occlusion and timing modules convert to radians where they compute.

use crate::capture_bracket::CaptureBracket;
use crate::response::{InstrumentResponse, LightProfile};
use serde::{Deserialize, Serialize};
use specula_core::shown::shown;
use std::path::Path;

/// The widest axis range accepted, degrees: two turns each way (a range of +-1e300 deg would
/// make the planner allocate without bound).
pub const MAX_AXIS_DEG: f64 = 720.0;

/// The default device file, the paper's UTIA gonioreflectometer.
pub const UTIA_TOML: &str = include_str!("../devices/utia.toml");

/// The longest length of a device file (distances, radii, part coordinates), metres: a
/// laboratory's size.
pub const MAX_LENGTH_M: f64 = 100.0;
/// The range of [`Device::accuracy_deg`], degrees.
pub const ACCURACY_DEG: (f64, f64) = (0.0, 5.0);
/// The range of an axis's top speed, degrees per second: from a hundredth of a degree per
/// second to ten turns per second.
pub const SPEED_DEG_S: (f64, f64) = (0.01, 3600.0);
/// The range of an axis's acceleration, degrees per second squared.
pub const ACCEL_DEG_S2: (f64, f64) = (0.01, 36000.0);
/// The range of an axis's settling time, seconds: up to ten minutes.
pub const SETTLE_S: (f64, f64) = (0.0, 600.0);

/// A goniometer: a turntable holding the sample, a camera arm and a light arm.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Device {
    /// A name for reports.
    pub name: String,
    /// Angular positioning accuracy of every axis, degrees (0.03 for UTIA, paper 4.1).
    /// Range: 0 to 5.
    pub accuracy_deg: f64,
    /// Where the axes rest before the first sample; each angle within its axis's range.
    pub park: ParkPosition,
    /// The rotary stage turning the sample about its normal.
    pub turntable: Axis,
    /// The camera and its one-axis arm.
    pub camera: CameraArm,
    /// The light and its two-axis arm.
    pub light: LightArm,
    /// The HDR capture made at every sample.
    pub capture: CaptureBracket,
}

/// One rotary axis: its range and its motion (trapezoidal velocity profile, then settling).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Axis {
    /// Lowest reachable angle, degrees.
    pub min_deg: f64,
    /// Highest reachable angle, degrees.
    pub max_deg: f64,
    /// Top speed, degrees per second. Range: 0.01 to 3600.
    pub speed_deg_s: f64,
    /// Acceleration and deceleration, degrees per second squared. Range: 0.01 to 36000.
    pub accel_deg_s2: f64,
    /// Wait after a move of this axis before it is still within the accuracy, seconds.
    /// Range: 0 to 600.
    pub settle_s: f64,
}

/// The axis angles, in degrees, where the device rests before the first sample.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParkPosition {
    /// Turntable angle, degrees.
    pub turntable_deg: f64,
    /// Camera arm angle from the zenith, degrees.
    pub camera_deg: f64,
    /// Light arm azimuth about the lab z axis, degrees.
    pub light_azimuth_deg: f64,
    /// Light arm elevation (angle from the zenith), degrees.
    pub light_elevation_deg: f64,
}

/// A cone from the sample to an optical aperture: the camera's view of the measured area or
/// the light's beam onto it. Anything inside it blocks the measurement.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Cone {
    /// Radius at the sample, metres.
    pub sample_radius_m: f64,
    /// Distance from the sample to the aperture at the cone's far end, metres.
    pub end_distance_m: f64,
    /// Radius of that aperture, metres.
    pub end_radius_m: f64,
}

/// A solid part of an arm, a capsule (a segment thickened by a radius) in the arm's plane.
///
/// A point `[u, v]` lies at `u * pointing + v * arm_axis` from the sample, metres, where
/// `pointing` is the unit direction from the sample to the camera (light) and `arm_axis` the
/// unit direction of the arm's rotation axis (lab +y for the camera, the elevation axis for
/// the light).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Part {
    /// The part's name (e.g. `lens`), as occlusion reports name it.
    pub name: String,
    /// One end of the capsule's axis `[u, v]`, metres.
    pub from_m: [f64; 2],
    /// The other end of the capsule's axis `[u, v]`, metres.
    pub to_m: [f64; 2],
    /// The capsule's radius, metres.
    pub radius_m: f64,
}

/// The camera and its arm, turning about the lab y axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraArm {
    /// Sensor to sample, metres (2 m for UTIA).
    pub distance_m: f64,
    /// The view cone from the measured area to the lens.
    pub view: Cone,
    /// Radius of the lens's entrance pupil, metres: the camera's angular spread seen from
    /// the sample ([`crate::response`]); 0 for a pinhole.
    #[serde(default)]
    pub aperture_radius_m: f64,
    /// The camera axis; its range bounds theta_v (75 deg for UTIA, paper 5.3).
    pub axis: Axis,
    /// Lens, body and arm.
    pub parts: Vec<Part>,
}

/// The light and its arm: azimuth about the lab z axis, then elevation about a horizontal
/// axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LightArm {
    /// Light's exit aperture to sample, metres (1.1 m for UTIA).
    pub distance_m: f64,
    /// The beam cone from the sample to the light's exit aperture; the aperture is the
    /// emitting disk ([`crate::response`]).
    pub beam: Cone,
    /// Relative radiance of the exit aperture at evenly spaced radii from its centre to its
    /// edge, linear in between; empty (the default) for a uniform disk.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub emission_profile: Vec<f64>,
    /// The light arm's azimuth axis, about the lab z axis.
    pub azimuth: Axis,
    /// The light arm's elevation axis, about a horizontal axis (angle from the zenith).
    pub elevation: Axis,
    /// Light head and arm.
    pub parts: Vec<Part>,
}

/// A device file that cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum DeviceError {
    /// The device file cannot be read.
    #[error("cannot read device file {path}: {source}")]
    Read {
        /// The device file's path.
        path: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The device file is not valid TOML for a device.
    #[error("device file {path}, line {line}: {message}")]
    Parse {
        /// The device file's path.
        path: String,
        /// The 1-based line of the error (1 when the parser gives no position).
        line: usize,
        /// What the parser found wrong.
        message: String,
    },
    /// The device file parses but a value is out of range or inconsistent.
    #[error("device file {path}: {problem}")]
    Invalid {
        /// The device file's path.
        path: String,
        /// The value out of its range or inconsistent with another.
        problem: String,
    },
    /// The capture bracket of a device file is unusable.
    #[error("device file {path}: {problem}")]
    Capture {
        /// The device file's path.
        path: String,
        /// What is wrong with the bracket.
        problem: crate::capture_bracket::CaptureProblem,
    },
}

impl Device {
    /// The paper's UTIA gonioreflectometer (`devices/utia.toml`).
    pub fn utia() -> Device {
        Device::from_toml_str(UTIA_TOML, "devices/utia.toml")
            .expect("the embedded device file is valid (tested)")
    }

    /// The device description at `path` (a front end's `--device` / `device=`), or the
    /// paper's UTIA gonioreflectometer ([`Device::utia`]) when none is given.
    pub fn load_or_utia(path: Option<&Path>) -> Result<Device, DeviceError> {
        path.map_or_else(|| Ok(Device::utia()), Device::load)
    }

    /// Reads a device TOML file.
    pub fn load(path: &Path) -> Result<Device, DeviceError> {
        let name = path.display().to_string();
        let text = specula_core::bounded_read::read_toml_text(path).map_err(|source| {
            DeviceError::Read {
                path: name.clone(),
                source,
            }
        })?;
        Device::from_toml_str(&text, &name)
    }

    /// Parses and checks a device description; `origin` names it in errors.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Device, DeviceError> {
        let device: Device = toml::from_str(text).map_err(|e| DeviceError::Parse {
            path: origin.to_string(),
            line: e
                .span()
                .map_or(1, |span| text[..span.start].matches('\n').count() + 1),
            message: e.message().trim().replace('\n', " "),
        })?;
        device.validate().map_err(|problem| DeviceError::Invalid {
            path: origin.to_string(),
            problem,
        })?;
        device
            .capture
            .validate()
            .map_err(|problem| DeviceError::Capture {
                path: origin.to_string(),
                problem,
            })?;
        Ok(device)
    }

    /// The description as TOML (without the comments of the default file).
    pub fn to_toml_string(&self) -> String {
        toml::to_string_pretty(self).expect("a device always serialises")
    }

    /// The angular radius of the light's disk seen from the sample, degrees:
    /// `atan(beam end radius / light distance)` (1.8 deg on the UTIA device).
    pub fn light_radius_deg(&self) -> f64 {
        (self.light.beam.end_radius_m / self.light.distance_m)
            .atan()
            .to_degrees()
    }

    /// What one capture integrates on this device (see [`crate::response`]): the light's
    /// exit aperture and emission profile, the camera's pupil, the measured area.
    pub fn response(&self) -> InstrumentResponse {
        InstrumentResponse {
            light: LightProfile {
                radius_deg: self.light_radius_deg(),
                emission: self.light.emission_profile.clone(),
            },
            camera_aperture_deg: (self.camera.aperture_radius_m / self.camera.distance_m)
                .atan()
                .to_degrees(),
            footprint_radius_m: self.camera.view.sample_radius_m,
            light_distance_m: self.light.distance_m,
            camera_distance_m: self.camera.distance_m,
        }
    }

    /// The four axes: turntable, camera, light azimuth, light elevation (the order of
    /// `kinematics::AxisPositions::as_array`).
    pub fn axes(&self) -> [&Axis; 4] {
        [
            &self.turntable,
            &self.camera.axis,
            &self.light.azimuth,
            &self.light.elevation,
        ]
    }

    /// The first problem that makes the description unusable, if any, apart from its capture
    /// bracket (which `CaptureBracket::validate` checks). Every number has a range (in the
    /// fields' documentation): lengths up to [`MAX_LENGTH_M`], speeds, accelerations and
    /// settling times of real stages, park angles inside their axes, so that a typo such as
    /// `settle_s = 1e300` is refused here rather than planned into 300-digit hours.
    fn validate(&self) -> Result<(), String> {
        let in_range = |value: f64, (min, max): (f64, f64), what: &str| {
            if (min..=max).contains(&value) {
                Ok(())
            } else {
                Err(format!(
                    "{what} must be from {} to {}, got {}",
                    shown(min),
                    shown(max),
                    shown(value)
                ))
            }
        };
        let above_zero = |value: f64, max: f64, what: &str| {
            if value > 0.0 && value <= max {
                Ok(())
            } else {
                Err(format!(
                    "{what} must be above 0 and at most {}, got {}",
                    shown(max),
                    shown(value)
                ))
            }
        };
        let positive = |value: f64, what: &str| above_zero(value, MAX_LENGTH_M, what);
        let non_negative = |value: f64, what: &str| in_range(value, (0.0, MAX_LENGTH_M), what);
        in_range(self.accuracy_deg, ACCURACY_DEG, "accuracy_deg")?;
        let named = [
            ("turntable", &self.turntable),
            ("camera.axis", &self.camera.axis),
            ("light.azimuth", &self.light.azimuth),
            ("light.elevation", &self.light.elevation),
        ];
        for (name, axis) in named {
            if !(axis.min_deg.is_finite()
                && axis.max_deg.is_finite()
                && axis.min_deg < axis.max_deg)
            {
                return Err(format!(
                    "{name}: min_deg ({}) must be below max_deg ({})",
                    shown(axis.min_deg),
                    shown(axis.max_deg)
                ));
            }
            if axis.min_deg < -MAX_AXIS_DEG || axis.max_deg > MAX_AXIS_DEG {
                return Err(format!(
                    "{name}: the range [{}, {}] deg must stay within [-{MAX_AXIS_DEG}, {MAX_AXIS_DEG}] deg (two turns each way)",
                    shown(axis.min_deg),
                    shown(axis.max_deg)
                ));
            }
            in_range(
                axis.speed_deg_s,
                SPEED_DEG_S,
                &format!("{name}.speed_deg_s"),
            )?;
            in_range(
                axis.accel_deg_s2,
                ACCEL_DEG_S2,
                &format!("{name}.accel_deg_s2"),
            )?;
            in_range(axis.settle_s, SETTLE_S, &format!("{name}.settle_s"))?;
        }
        let park = &self.park;
        for (name, angle_deg, axis) in [
            ("park.turntable_deg", park.turntable_deg, &self.turntable),
            ("park.camera_deg", park.camera_deg, &self.camera.axis),
            (
                "park.light_azimuth_deg",
                park.light_azimuth_deg,
                &self.light.azimuth,
            ),
            (
                "park.light_elevation_deg",
                park.light_elevation_deg,
                &self.light.elevation,
            ),
        ] {
            in_range(angle_deg, (axis.min_deg, axis.max_deg), name)?;
        }
        if self.camera.axis.min_deg < -90.0 || self.camera.axis.max_deg > 90.0 {
            return Err("camera.axis must stay within [-90, 90] degrees".into());
        }
        if self.light.elevation.min_deg < -90.0 || self.light.elevation.max_deg > 90.0 {
            return Err("light.elevation must stay within [-90, 90] degrees".into());
        }
        positive(self.camera.distance_m, "camera.distance_m")?;
        non_negative(self.camera.aperture_radius_m, "camera.aperture_radius_m")?;
        let emission = &self.light.emission_profile;
        if emission.iter().any(|e| !(e.is_finite() && *e >= 0.0))
            || (!emission.is_empty() && emission.iter().all(|e| *e == 0.0))
        {
            return Err(
                "light.emission_profile must hold non-negative numbers, not all zero".into(),
            );
        }
        positive(self.light.distance_m, "light.distance_m")?;
        for (name, cone) in [
            ("camera.view", &self.camera.view),
            ("light.beam", &self.light.beam),
        ] {
            non_negative(cone.sample_radius_m, &format!("{name}.sample_radius_m"))?;
            positive(cone.end_distance_m, &format!("{name}.end_distance_m"))?;
            non_negative(cone.end_radius_m, &format!("{name}.end_radius_m"))?;
        }
        for part in self.camera.parts.iter().chain(&self.light.parts) {
            let inside = part
                .from_m
                .iter()
                .chain(&part.to_m)
                .all(|x| x.abs() <= MAX_LENGTH_M);
            if !inside {
                return Err(format!(
                    "part '{}' has a coordinate that is not a number from -{MAX_LENGTH_M} to {MAX_LENGTH_M} m",
                    specula_core::shown::excerpt(&part.name)
                ));
            }
            non_negative(
                part.radius_m,
                &format!(
                    "part '{}' radius_m",
                    specula_core::shown::excerpt(&part.name)
                ),
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_device_is_the_papers() {
        let d = Device::utia();
        assert_eq!(d.accuracy_deg, 0.03);
        assert_eq!(d.light.distance_m, 1.1);
        assert_eq!(d.camera.distance_m, 2.0);
        assert_eq!(d.camera.axis.max_deg, 75.0);
        assert_eq!(d.camera.axis.min_deg, -75.0);
        assert!(!d.camera.parts.is_empty() && !d.light.parts.is_empty());
        // The light's disk: 1.8 deg across its radius, the response's.
        assert!(
            (d.light_radius_deg() - 1.82).abs() < 0.01,
            "{}",
            d.light_radius_deg()
        );
        assert_eq!(d.response().light.radius_deg, d.light_radius_deg());
    }

    #[test]
    fn toml_round_trip() {
        let d = Device::utia();
        let back = Device::from_toml_str(&d.to_toml_string(), "round trip").unwrap();
        assert_eq!(d, back);
    }

    #[test]
    fn bad_files_name_the_problem() {
        let broken = UTIA_TOML.replace("speed_deg_s = 20.0", "speed_deg_s = -1.0");
        let err = Device::from_toml_str(&broken, "x.toml")
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("x.toml") && err.contains("turntable.speed_deg_s"),
            "{err}"
        );

        let unknown = UTIA_TOML.replace("[park]", "wobble = 3\n[park]");
        let err = Device::from_toml_str(&unknown, "y.toml")
            .unwrap_err()
            .to_string();
        assert!(err.contains("y.toml") && err.contains("wobble"), "{err}");
        assert_eq!(err.lines().count(), 1, "one line: {err}");
        let line = UTIA_TOML.lines().position(|l| l == "[park]").unwrap() + 1;
        assert!(err.contains(&format!("line {line}:")), "{err}");

        let missing = Device::load(Path::new("/nonexistent/device.toml")).unwrap_err();
        assert!(missing.to_string().contains("/nonexistent/device.toml"));
    }
}
