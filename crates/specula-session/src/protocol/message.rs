//! The messages of the driver protocol: one JSON object per line each way (see
//! `docs/book/src/driver-protocol.md`, the specification for adapter writers).
//!
//! Request:  `{"id": 7, "method": "move_to", "params": {"target": {...}}}`
//! Reply:    `{"id": 7, "result": {...}}` or `{"id": 7, "error": {"kind": "motor_fault",
//! "message": "..."}}`, optionally with `"clock_s"`, a simulated device's clock.

use serde::{Deserialize, Serialize};
use serde_json::Value;
use specula_acquisition::instrument::InstrumentError;
use specula_acquisition::kinematics::AxisPositions;

/// The protocol's version; `hello` carries it and the two sides must agree.
pub const PROTOCOL_VERSION: u32 = 1;

/// The longest line either side accepts, bytes (a capture with pixels of a 64 x 64 region
/// is about 200 kB).
pub const MAX_LINE_BYTES: u64 = 64 << 20;

/// A request from Specula to the device.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Request {
    /// Chosen by the client, increasing; the reply carries it back.
    pub id: u64,
    /// The method's name (`hello`, `info`, `move`, `light`, `capture`, ...).
    pub method: String,
    /// The method's arguments, an object (absent or `null` when it has none).
    #[serde(default, skip_serializing_if = "Value::is_null")]
    pub params: Value,
}

/// A reply from the device.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Reply {
    /// The request's id; `null` when the request could not be read at all.
    pub id: Option<u64>,
    /// The method's result when it succeeded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub result: Option<Value>,
    /// Why it failed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<WireError>,
    /// A simulated device's clock after the request, seconds (absent for real hardware).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clock_s: Option<f64>,
}

/// An error on the wire: one of the device's kinds (`timeout`, `limit`, `motor_fault`,
/// `camera_fault`, `disconnected`) or a protocol kind (`bad_request`, `unknown_method`,
/// `unauthorized`, `version`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WireError {
    /// The error's kind, one of those listed above.
    pub kind: String,
    /// A human-readable explanation.
    pub message: String,
}

/// Arguments of `hello`: the first request on every connection.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HelloParams {
    /// The protocol version the client speaks ([`PROTOCOL_VERSION`]).
    pub protocol: u32,
    /// The shared secret, when the server asks for one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub token: Option<String>,
}

/// Result of `hello`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HelloResult {
    /// The protocol version the server speaks.
    pub protocol: u32,
    /// A free-form name of the server or adapter.
    pub server: String,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(crate) struct MoveParams {
    pub(crate) target: AxisPositions,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(crate) struct LightParams {
    pub(crate) level: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(crate) struct CaptureParams {
    pub(crate) exposure_s: f64,
    #[serde(default)]
    pub(crate) with_pixels: bool,
}

impl WireError {
    pub(crate) fn new(kind: &str, message: impl Into<String>) -> Self {
        Self {
            kind: kind.to_string(),
            message: message.into(),
        }
    }

    /// The device's error as it goes on the wire.
    pub fn from_instrument(error: &InstrumentError) -> Self {
        let (kind, message) = match error {
            InstrumentError::Timeout(m) => ("timeout", m),
            InstrumentError::Limit(m) => ("limit", m),
            InstrumentError::MotorFault(m) => ("motor_fault", m),
            InstrumentError::CameraFault(m) => ("camera_fault", m),
            InstrumentError::Disconnected(m) => ("disconnected", m),
        };
        Self::new(kind, message.clone())
    }

    /// The device's error this wire error stands for; `None` for a protocol kind.
    pub fn to_instrument(&self) -> Option<InstrumentError> {
        let m = self.message.clone();
        Some(match self.kind.as_str() {
            "timeout" => InstrumentError::Timeout(m),
            "limit" => InstrumentError::Limit(m),
            "motor_fault" => InstrumentError::MotorFault(m),
            "camera_fault" => InstrumentError::CameraFault(m),
            "disconnected" => InstrumentError::Disconnected(m),
            _ => return None,
        })
    }
}

impl Reply {
    pub(crate) fn ok(id: u64, result: Value) -> Self {
        Self {
            id: Some(id),
            result: Some(result),
            error: None,
            clock_s: None,
        }
    }

    pub(crate) fn failed(id: Option<u64>, error: WireError) -> Self {
        Self {
            id,
            result: None,
            error: Some(error),
            clock_s: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn lines_look_as_documented() {
        let request = Request {
            id: 7,
            method: "move_to".into(),
            params: serde_json::to_value(MoveParams {
                target: AxisPositions::new(0.5, -0.25, 1.0, 0.75),
            })
            .unwrap(),
        };
        assert_eq!(
            serde_json::to_value(&request).unwrap(),
            json!({"id": 7, "method": "move_to", "params": {"target": {
                "turntable_rad": 0.5, "camera_rad": -0.25,
                "light_azimuth_rad": 1.0, "light_elevation_rad": 0.75}}})
        );
        let home: Request = serde_json::from_str(r#"{"id":1,"method":"home"}"#).unwrap();
        assert_eq!(home.params, Value::Null);
        let error = Reply::failed(
            Some(3),
            WireError::from_instrument(&InstrumentError::MotorFault("x".into())),
        );
        assert_eq!(
            serde_json::to_string(&error).unwrap(),
            r#"{"id":3,"error":{"kind":"motor_fault","message":"x"}}"#
        );
    }

    #[test]
    fn every_device_error_crosses_the_wire() {
        let all = [
            InstrumentError::Timeout("a".into()),
            InstrumentError::Limit("b".into()),
            InstrumentError::MotorFault("c".into()),
            InstrumentError::CameraFault("d".into()),
            InstrumentError::Disconnected("e".into()),
        ];
        for e in all {
            assert_eq!(WireError::from_instrument(&e).to_instrument(), Some(e));
        }
        assert_eq!(WireError::new("unauthorized", "no").to_instrument(), None);
    }
}
