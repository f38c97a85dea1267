//! Seeing damage to a session journal (issue 16): a file truncated, bytes flipped, a row
//! edited or deleted outside specula. A damaged journal is an error that says so and what
//! is wrong; it is never read as a shorter or different measurement, and never silently
//! replaced by a new session.
//!
//! On every open: the file must not be empty, SQLite's `PRAGMA quick_check` must pass, each
//! stage's plan must be numbered `0..n` without gaps, and every sample and capture must
//! belong to a planned sample. On every read of samples: each row's checksum (SHA-256 of its
//! values, first 8 bytes) must match, so a value changed on disk is refused.

use super::{JournalError, SampleRecord};
use rusqlite::Connection;
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// The path the session's lock is taken on: the journal's canonical path (symlinks and `..`
/// resolved), so two spellings of one file take one lock. A journal not yet created is named
/// by its directory's canonical path and its file name.
pub(crate) fn canonical_path(path: &Path) -> std::io::Result<PathBuf> {
    if path.exists() {
        return std::fs::canonicalize(path);
    }
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .ok_or_else(|| std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a file name"))?;
    Ok(std::fs::canonicalize(parent)?.join(name))
}

/// A directory is no journal (SQLite would say "disk I/O error").
pub(crate) fn refuse_directory(path: &Path) -> Result<(), JournalError> {
    if path.is_dir() {
        return Err(JournalError::Directory {
            path: path.display().to_string(),
        });
    }
    Ok(())
}

/// A journal opened to be read must exist (SQLite's own message, "unable to open database
/// file", does not say why).
pub(crate) fn refuse_missing(path: &Path) -> Result<(), JournalError> {
    if !path.exists() {
        return Err(JournalError::Missing {
            path: path.display().to_string(),
        });
    }
    Ok(())
}

/// An existing file of 0 bytes is a journal truncated (SQLite would take it for a new one).
pub(crate) fn refuse_empty_file(path: &Path) -> Result<(), JournalError> {
    match std::fs::metadata(path) {
        Ok(meta) if meta.is_file() && meta.len() == 0 => Err(JournalError::Damaged {
            path: path.display().to_string(),
            problem: "the file is empty (0 bytes): a truncated journal".into(),
        }),
        _ => Ok(()),
    }
}

/// The whole-file checks of every open (see the module documentation).
pub(crate) fn check_file(conn: &Connection, path: &Path) -> Result<(), JournalError> {
    let damaged = |problem: String| JournalError::Damaged {
        path: path.display().to_string(),
        problem: problem.into(),
    };
    let sql = |e: rusqlite::Error| damaged(damage(&e).unwrap_or_else(|| e.to_string()));
    let verdict: Vec<String> = conn
        .prepare("PRAGMA quick_check")
        .and_then(|mut s| s.query_map([], |r| r.get(0))?.collect())
        .map_err(sql)?;
    if verdict != ["ok"] {
        let first = one_line(verdict.first().map_or("", String::as_str));
        return Err(damaged(format!(
            "SQLite's quick_check found {} problem(s), the first: {first}",
            verdict.len()
        )));
    }
    let gaps: Option<(String, i64, i64)> = conn
        .query_row(
            "SELECT stage, count(*), max(seq) FROM plan GROUP BY stage
             HAVING min(seq) != 0 OR max(seq) + 1 != count(*) LIMIT 1",
            [],
            |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)),
        )
        .map(Some)
        .or_else(|e| match e {
            rusqlite::Error::QueryReturnedNoRows => Ok(None),
            e => Err(e),
        })
        .map_err(sql)?;
    if let Some((stage, rows, max_seq)) = gaps {
        return Err(damaged(format!(
            "the {stage} plan has {rows} rows numbered up to {max_seq}: planned samples are missing"
        )));
    }
    let orphans = |what: &str, query: &str| -> Result<(), JournalError> {
        let count: i64 = conn.query_row(query, [], |r| r.get(0)).map_err(sql)?;
        if count > 0 {
            return Err(damaged(format!("{count} {what}")));
        }
        Ok(())
    };
    orphans(
        "samples outside the plan",
        "SELECT count(*) FROM samples s LEFT JOIN plan p ON p.stage = s.stage AND p.seq = s.seq
         WHERE p.seq IS NULL",
    )?;
    orphans(
        "captures of no sample",
        "SELECT count(*) FROM captures c LEFT JOIN samples s ON s.stage = c.stage AND s.seq = c.seq
         WHERE s.seq IS NULL",
    )
}

/// What an SQLite error says about damage to the file, if it is damage: a corrupt or
/// foreign file, or a value of the wrong type or unreadable text where specula wrote one.
pub(crate) fn damage(error: &rusqlite::Error) -> Option<String> {
    use rusqlite::ErrorCode;
    let problem = match error {
        rusqlite::Error::SqliteFailure(code, message)
            if matches!(
                code.code,
                ErrorCode::DatabaseCorrupt | ErrorCode::NotADatabase
            ) =>
        {
            Some(format!(
                "SQLite: {}",
                message
                    .as_deref()
                    .unwrap_or("database disk image is malformed")
            ))
        }
        rusqlite::Error::FromSqlConversionFailure(column, kind, cause) => Some(format!(
            "column {column} holds an unreadable {kind} value ({cause})"
        )),
        rusqlite::Error::InvalidColumnType(column, name, kind) => Some(format!(
            "column {column} ({name}) holds a {kind} value where specula writes another type"
        )),
        rusqlite::Error::Utf8Error(column, cause) => Some(format!(
            "column {column} holds text that is not UTF-8 ({cause})"
        )),
        _ => None,
    };
    problem.map(|p| one_line(&p))
}

/// A message on one line (SQLite quotes the damaged schema, newlines and all).
fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The checksum stored with a sample: SHA-256 of its stage, seq and every value (bit for
/// bit, zeros without their sign), first 8 bytes as an integer. Captures are not part of it.
pub(crate) fn sample_checksum(s: &SampleRecord) -> i64 {
    let mut hash = Sha256::new();
    hash.update(s.stage.as_bytes());
    hash.update([0]);
    hash.update(s.seq.to_le_bytes());
    for v in s.reals() {
        // + 0.0 turns -0.0 into 0.0: SQLite stores a whole REAL as an integer, losing the
        // sign of a zero.
        hash.update((v + 0.0).to_bits().to_le_bytes());
    }
    hash.update([u8::from(s.lower_bound)]);
    hash.update(s.attempts.to_le_bytes());
    let digest = hash.finalize();
    let mut first = [0u8; 8];
    first.copy_from_slice(&digest[..8]);
    i64::from_le_bytes(first)
}

/// What is damaged in a journal.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum Damage {
    /// Found by SQLite's or the file's checks, in words.
    #[error("{0}")]
    Found(String),
    /// A sample's values do not match their checksum.
    #[error(transparent)]
    Checksum(#[from] ChecksumMismatch),
}

impl From<String> for Damage {
    fn from(problem: String) -> Self {
        Damage::Found(problem)
    }
}

impl From<&str> for Damage {
    fn from(problem: &str) -> Self {
        Damage::Found(problem.to_string())
    }
}

/// A sample whose values do not match the checksum stored with them.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{stage} sample {seq}: its values do not match their checksum")]
pub struct ChecksumMismatch {
    /// The sample's stage.
    pub stage: String,
    /// The sample's number in its stage's plan.
    pub seq: u32,
}

/// Checks a sample read back against its stored checksum.
pub(crate) fn verify_sample(s: &SampleRecord, stored: i64) -> Result<(), ChecksumMismatch> {
    if sample_checksum(s) == stored {
        Ok(())
    } else {
        Err(ChecksumMismatch {
            stage: s.stage.to_string(),
            seq: s.seq,
        })
    }
}

/// The first value of a sample that must be finite and is not (a standard deviation may be
/// infinite: a lower bound has no upper error).
pub(crate) fn non_finite_field(s: &SampleRecord) -> Option<(&'static str, f64)> {
    let a = s.readback;
    let sigma_ok = s.sigma_dn_s.iter().all(|v| !v.is_nan());
    let fields = [
        ("value.r", s.value.x),
        ("value.g", s.value.y),
        ("value.b", s.value.z),
        ("rate_r", s.rate_dn_s[0]),
        ("rate_g", s.rate_dn_s[1]),
        ("rate_b", s.rate_dn_s[2]),
        ("turntable_rad", a.turntable_rad),
        ("camera_rad", a.camera_rad),
        ("light_azimuth_rad", a.light_azimuth_rad),
        ("light_elevation_rad", a.light_elevation_rad),
        ("device_s", s.device_s),
        ("wall_s", s.wall_s),
    ];
    if !sigma_ok {
        return Some(("sigma", f64::NAN));
    }
    fields.into_iter().find(|(_, v)| !v.is_finite())
}
