//! What a session was measured from, kept in the journal so that a resume or a reconnection
//! to anything else is refused (issue 16): the content hash of every input (the simulated
//! truth, the device model, the calibration) and the device's identity (its `hello` name and
//! its `info` reply).
//!
//! A truth is hashed by what it *is*, not by its name or file: its values at a fixed set of
//! half-difference angles, so an edited material file or another file of the same name is
//! another truth, whatever it is called.

use crate::journal::{Journal, JournalError, Record};
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use specula_acquisition::instrument::InstrumentInfo;
use specula_core::{Brdf, HalfDiff};

/// SHA-256 content hashes of a session's inputs, hex.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct InputHashes {
    /// The simulated truth's values ([`brdf_fingerprint`]); `None` for a real device.
    pub truth: Option<String>,
    /// The device model's TOML.
    pub device_model: String,
    /// The calibration given for a real device; `None` for the simulated one (calibrated
    /// in the session).
    pub calibration: Option<String>,
}

/// Who the device is: what it says in `hello` (`None` for an in-process device) and `info`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DeviceIdentity {
    /// The server's name from `hello`; `None` for an in-process device.
    pub server: Option<String>,
    /// The device's `info` reply.
    pub info: InstrumentInfo,
}

impl Record for InputHashes {
    const KEY: &'static str = "inputs";
}

impl Record for DeviceIdentity {
    const KEY: &'static str = "device_identity";
}

/// Why a session cannot go on with these inputs.
#[derive(Debug, thiserror::Error)]
pub enum InputsError {
    /// The journal could not be read or written.
    #[error(transparent)]
    Journal(#[from] JournalError),
    /// An input's content differs from the one the session was measured from.
    #[error("{path}: this session was measured from other inputs: {changes}; give the same inputs or use another --session")]
    Changed {
        /// The session journal.
        path: String,
        /// Which inputs differ from the ones the session was started with.
        changes: String,
    },
}

/// SHA-256 of bytes, hex.
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// The content hash of a BRDF: SHA-256 of its values (bit for bit, "not measured" marked)
/// at 16 theta_h (dense near the specular peak, as the paper's sampling) x 8 theta_d x 8
/// phi_d x 2 phi_h half-difference angles.
pub fn brdf_fingerprint(brdf: &dyn Brdf) -> String {
    let mut bytes = Vec::with_capacity(2048 * 25);
    for i in 0..16 {
        let theta_h_deg = 90.0 * (i as f64 / 16.0).powi(2);
        for j in 0..8 {
            let theta_d_deg = 85.0 * j as f64 / 8.0;
            for k in 0..8 {
                let phi_d_deg = 180.0 * k as f64 / 8.0;
                for phi_h_deg in [0.0, 45.0] {
                    let hd = HalfDiff::from_degrees(theta_h_deg, phi_h_deg, theta_d_deg, phi_d_deg);
                    match brdf.eval_half_diff(hd) {
                        Some(v) => {
                            bytes.push(1);
                            for c in [v.x, v.y, v.z] {
                                bytes.extend_from_slice(&c.to_bits().to_le_bytes());
                            }
                        }
                        None => bytes.push(0),
                    }
                }
            }
        }
    }
    sha256_hex(&bytes)
}

/// Stores the inputs of a new session, or checks a resumed one's against them.
pub fn check_inputs(journal: &Journal, asked: &InputHashes) -> Result<(), InputsError> {
    let stored: InputHashes = journal.record_or_insert(|| asked.clone())?;
    let mut changes = Vec::new();
    let mut compare = |what: &str, a: &Option<String>, b: &Option<String>| {
        if a != b {
            changes.push(format!(
                "{what} {} then, {} now",
                short(a.as_deref()),
                short(b.as_deref())
            ));
        }
    };
    compare("truth (content sha256)", &stored.truth, &asked.truth);
    compare(
        "device model (sha256)",
        &Some(stored.device_model.clone()),
        &Some(asked.device_model.clone()),
    );
    compare(
        "calibration (sha256)",
        &stored.calibration,
        &asked.calibration,
    );
    if changes.is_empty() {
        return Ok(());
    }
    Err(InputsError::Changed {
        path: journal.path().display().to_string(),
        changes: changes.join(", "),
    })
}

/// Stores the device's identity in a new session, or checks that a resumed one measures the
/// same device.
pub fn check_device(journal: &Journal, asked: &DeviceIdentity) -> Result<(), InputsError> {
    let stored: DeviceIdentity = journal.record_or_insert(|| asked.clone())?;
    let mut changes = Vec::new();
    if stored.server != asked.server {
        changes.push(format!(
            "device name in hello '{}' then, '{}' now",
            stored.server.as_deref().unwrap_or("(none)"),
            asked.server.as_deref().unwrap_or("(none)")
        ));
    }
    let (a, b) = (&stored.info, &asked.info);
    if (&a.model, &a.serial) != (&b.model, &b.serial) {
        changes.push(format!(
            "device '{}' serial '{}' then, '{}' serial '{}' now",
            a.model, a.serial, b.model, b.serial
        ));
    } else if a != b {
        changes.push(
            "the device's info reply (bit depth, white level, light levels or exposures)".into(),
        );
    }
    if changes.is_empty() {
        return Ok(());
    }
    Err(InputsError::Changed {
        path: journal.path().display().to_string(),
        changes: changes.join(", "),
    })
}

/// The first 12 hex digits of a hash, or "none".
fn short(hash: Option<&str>) -> String {
    hash.map_or("none".into(), |h| h.chars().take(12).collect())
}
