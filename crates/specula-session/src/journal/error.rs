//! Why the journal cannot be used, in one line naming the file.

use super::check::{self, Damage};
use std::path::Path;

/// Why the journal cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum JournalError {
    /// Causes are in the messages, not error `source`s, so that error chains do not print
    /// them again (as `MerlError` in specula-core).
    #[error("{path}: {cause}")]
    Sqlite {
        /// The journal file.
        path: String,
        /// SQLite's error.
        cause: rusqlite::Error,
    },
    /// The journal was written with another schema version.
    #[error("{path}: journal schema version {found}, this specula reads version {expected}")]
    Version {
        /// The journal file.
        path: String,
        /// The schema version in the file.
        found: i64,
        /// The schema version this build reads.
        expected: i64,
    },
    /// Another process holds the journal's lock.
    #[error("{path}: another specula process is writing this session (lock file {lock})")]
    Locked {
        /// The journal file.
        path: String,
        /// The lock file held by the other process.
        lock: String,
    },
    /// Another process writes the same journal file, perhaps under another name.
    #[error("{path}: another specula process is writing this journal file (under this name or another one: a hard link)")]
    InUse {
        /// The journal file.
        path: String,
    },
    /// The path is a directory.
    #[error("{path}: is a directory; a session is a file (e.g. {path}/NAME.session.sqlite)")]
    Directory {
        /// The path given.
        path: String,
    },
    /// A journal to read does not exist.
    #[error("{path}: no such session journal (the .session.sqlite file `specula measure` writes)")]
    Missing {
        /// The path given.
        path: String,
    },
    /// The lock file could not be created.
    #[error("{path}: cannot create the lock file: {cause}")]
    Lock {
        /// The journal file.
        path: String,
        /// The I/O error.
        cause: std::io::Error,
    },
    /// The file is an SQLite database without a Specula schema version.
    #[error("{path}: not a specula session journal (no schema version)")]
    NotAJournal {
        /// The file.
        path: String,
    },
    /// A meta record holds JSON that does not parse as its type.
    #[error("{path}: meta '{key}' holds unreadable JSON: {cause}")]
    Json {
        /// The journal file.
        path: String,
        /// The record's key in the meta table.
        key: String,
        /// serde_json's error.
        cause: serde_json::Error,
    },
    /// The stage's plan in the journal is not the one asked for.
    #[error("{path}: the {stage} plan in the journal differs from the one asked for ({problem}); use a new --session file for a different measurement")]
    PlanMismatch {
        /// The journal file.
        path: String,
        /// The stage.
        stage: String,
        /// The first difference found.
        problem: String,
    },
    /// A sample was written twice.
    #[error("{path}: sample {seq} of stage {stage} is already measured")]
    Duplicate {
        /// The journal file.
        path: String,
        /// The sample's stage.
        stage: String,
        /// The sample's position in the stage's execution order.
        seq: u32,
    },
    /// The journal's integrity check failed.
    #[error("{path}: the journal is damaged ({problem}); it was changed outside specula or its disk failed: restore it from a copy or measure into a new --session")]
    Damaged {
        /// The journal file.
        path: String,
        /// What the integrity check found.
        problem: Damage,
    },
    /// A sample to be written holds a NaN or an infinity.
    #[error("{path}: {stage} sample {seq}: {field} is {value:e}, not a finite number; nothing was written")]
    NotFinite {
        /// The journal file.
        path: String,
        /// The sample's stage.
        stage: String,
        /// The sample's position in the stage's execution order.
        seq: u32,
        /// The field that is not finite.
        field: &'static str,
        /// Its value.
        value: f64,
    },
}

/// The journal error of an SQLite error on the journal at `path`: damage when SQLite says
/// the file is damaged.
pub(super) fn sql_error(path: &Path, cause: rusqlite::Error) -> JournalError {
    let path = path.display().to_string();
    match check::damage(&cause) {
        Some(problem) => JournalError::Damaged {
            path,
            problem: problem.into(),
        },
        None => JournalError::Sqlite { path, cause },
    }
}
