//! The session journal: one SQLite file per measurement session (paper 5.3: a measurement runs
//! for hours), written so that a crash, a power cut or a `kill -9` loses at most the sample
//! in progress and a rerun resumes without measuring a finished sample twice.
//!
//! What it holds (schema version [`SCHEMA_VERSION`]):
//! - `meta`: key -> JSON value: the session's settings, the device model, the calibration,
//!   the instrument's description, the probe's fit, the alignment and orientation checks;
//! - `plan`: every planned sample of every stage (`probe`, `main`, ...) in execution order,
//!   with its half-difference angles, axis positions and predicted step time; a stage's plan
//!   is written once, in one transaction, and never changes;
//! - `samples`: every finished sample (the calibrated BRDF value, the read-back positions, the
//!   device time it took, the wall-clock time, the attempts), keyed by (stage, seq) so that
//!   SQLite itself refuses a second measurement of the same sample, with a checksum of the
//!   row (see `check`) so that a value changed on disk is seen when it is read;
//! - `captures`: every raw capture of a sample (exposure, light level, raw statistics, time),
//!   written in the sample's transaction;
//! - `events`: faults, retries, reconnections, interruptions and resumptions.
//!
//! Durability: WAL mode and one transaction per sample, so a sample is either wholly there or
//! not at all. With [`Durability::PowerCut`] (the default, `synchronous = FULL`) a committed
//! sample also survives a power cut; [`Durability::Crash`] (`synchronous = NORMAL`, for
//! simulated devices, whose samples cost nothing to redo) survives a crash or a `kill -9`
//! of the process but may lose the last samples to a power cut, and saves a disk flush per
//! sample.
//! Only one process may write a session at a time: an advisory lock on `S.sqlite.lock` beside
//! the journal's canonical path (so a symlink to it takes the same lock, and two runs creating
//! one new journal do not race), and on Unix an advisory lock (`flock`) on the journal file
//! itself, taken before SQLite opens it, so that another name of the same file (a hard link)
//! is refused too, without a `-wal` file left beside that name;
//! `specula session status` reads it while a measurement runs.
//!
//! Damage: every open checks the file (`check`: SQLite's `quick_check`, the
//! plan numbering, samples and captures belonging to the plan) and refuses an existing empty
//! file, so a damaged journal is an error that says so, never a silent new session.

mod check;
pub use check::{ChecksumMismatch, Damage};
use rusqlite::{params, Connection, OpenFlags, OptionalExtension, Transaction};
use serde::de::DeserializeOwned;
use serde::Serialize;
use specula_acquisition::kinematics::AxisPositions;
use specula_core::{HalfDiff, Rgb};
use std::collections::BTreeMap;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

mod records;

pub use records::{
    ChecksRecord, CreatedRecord, DeviceRecord, FitRecord, HdrChoice, MeasureSettings,
    NewestVersionRecord, PlanOrder, PlanRecord, Record, SessionRecord, SourceRecord, Stage,
    VersionRecord,
};

/// The version of the tables below; a journal of another version is refused.
pub const SCHEMA_VERSION: i64 = 2;

const SCHEMA: &str = "
CREATE TABLE IF NOT EXISTS meta (
    key   TEXT PRIMARY KEY,
    value TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS plan (
    stage               TEXT    NOT NULL,
    seq                 INTEGER NOT NULL,
    theta_h_rad         REAL    NOT NULL,
    phi_h_rad           REAL    NOT NULL,
    theta_d_rad         REAL    NOT NULL,
    phi_d_rad           REAL    NOT NULL,
    turntable_rad       REAL    NOT NULL,
    camera_rad          REAL    NOT NULL,
    light_azimuth_rad   REAL    NOT NULL,
    light_elevation_rad REAL    NOT NULL,
    predicted_s         REAL    NOT NULL,
    PRIMARY KEY (stage, seq)
);
CREATE TABLE IF NOT EXISTS samples (
    stage               TEXT    NOT NULL,
    seq                 INTEGER NOT NULL,
    r                   REAL    NOT NULL,
    g                   REAL    NOT NULL,
    b                   REAL    NOT NULL,
    rate_r              REAL    NOT NULL,
    rate_g              REAL    NOT NULL,
    rate_b              REAL    NOT NULL,
    sigma_r             REAL    NOT NULL,
    sigma_g             REAL    NOT NULL,
    sigma_b             REAL    NOT NULL,
    lower_bound         INTEGER NOT NULL,
    turntable_rad       REAL    NOT NULL,
    camera_rad          REAL    NOT NULL,
    light_azimuth_rad   REAL    NOT NULL,
    light_elevation_rad REAL    NOT NULL,
    device_s            REAL    NOT NULL,
    wall_s              REAL    NOT NULL,
    finished_unix_s     REAL    NOT NULL,
    attempts            INTEGER NOT NULL,
    checksum            INTEGER NOT NULL,
    PRIMARY KEY (stage, seq),
    FOREIGN KEY (stage, seq) REFERENCES plan (stage, seq)
);
CREATE TABLE IF NOT EXISTS captures (
    id                  INTEGER PRIMARY KEY,
    stage               TEXT    NOT NULL,
    seq                 INTEGER NOT NULL,
    exposure_s          REAL    NOT NULL,
    light_level         REAL    NOT NULL,
    mean_r              REAL    NOT NULL,
    mean_g              REAL    NOT NULL,
    mean_b              REAL    NOT NULL,
    saturated_r         REAL    NOT NULL,
    saturated_g         REAL    NOT NULL,
    saturated_b         REAL    NOT NULL,
    pixel_count         INTEGER NOT NULL,
    used                INTEGER NOT NULL,
    unix_s              REAL    NOT NULL,
    FOREIGN KEY (stage, seq) REFERENCES samples (stage, seq)
);
CREATE INDEX IF NOT EXISTS captures_by_sample ON captures (stage, seq);
CREATE TABLE IF NOT EXISTS events (
    id      INTEGER PRIMARY KEY,
    unix_s  REAL NOT NULL,
    kind    TEXT NOT NULL,
    message TEXT NOT NULL
);
";

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

/// What a committed sample survives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Durability {
    /// A crash or kill of the process, and a power cut (a disk flush per sample).
    PowerCut,
    /// A crash or kill of the process; a power cut may lose the last samples.
    Crash,
}

/// One planned sample of a stage, in execution order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlannedRow {
    /// Position in the stage's execution order, from 0.
    pub seq: u32,
    /// The sample in half-difference angles, radians.
    pub hd: HalfDiff,
    /// Where the axes go for it.
    pub axes: AxisPositions,
    /// The time model's estimate of its step (move, settle, capture), seconds.
    pub predicted_s: f64,
}

/// One raw capture of a sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CaptureRecord {
    /// Exposure time, seconds.
    pub exposure_s: f64,
    /// Light level, fraction of full power.
    pub light_level: f64,
    /// Mean raw value per channel (R, G, B) over the region, black level included, DN.
    pub mean_raw: [f64; 3],
    /// Fraction of the region's pixels at the white level, per channel.
    pub saturated_fraction: [f64; 3],
    /// Number of pixels in the region.
    pub pixel_count: u32,
    /// Whether the HDR merge used it (not saturated, above the noise).
    pub used: bool,
    /// When it was taken, seconds since the Unix epoch.
    pub unix_s: f64,
}

/// A finished sample with its captures.
#[derive(Debug, Clone, PartialEq)]
pub struct SampleRecord {
    /// The stage the sample belongs to (e.g. `probe`, `main`).
    pub stage: String,
    /// Position in the stage's execution order, from 0.
    pub seq: u32,
    /// The calibrated BRDF value, 1/sr per channel.
    pub value: Rgb,
    /// The HDR merge: each channel's dark-subtracted raw rate at full light, DN/s.
    pub rate_dn_s: [f64; 3],
    /// One standard deviation of each rate, DN/s (infinite for a lower bound).
    pub sigma_dn_s: [f64; 3],
    /// A channel saturated in every capture: the value is only a lower bound.
    pub lower_bound: bool,
    /// The positions the encoders read back after the move.
    pub readback: AxisPositions,
    /// Device time of the step (move, settle, light changes, captures) from the time model,
    /// seconds.
    pub device_s: f64,
    /// Wall-clock time the step took here, seconds.
    pub wall_s: f64,
    /// When the sample was written, seconds since the Unix epoch.
    pub finished_unix_s: f64,
    /// How many tries the sample needed (1 when nothing failed).
    pub attempts: u32,
    /// The sample's raw captures, in the order they were taken.
    pub captures: Vec<CaptureRecord>,
}

/// The columns of a sample's real-valued fields, in the order of [`SampleRecord::reals`]:
/// the one list the journal's INSERT, SELECT and checksum follow.
const SAMPLE_REAL_COLUMNS: [&str; 16] = [
    "r",
    "g",
    "b",
    "rate_r",
    "rate_g",
    "rate_b",
    "sigma_r",
    "sigma_g",
    "sigma_b",
    "turntable_rad",
    "camera_rad",
    "light_azimuth_rad",
    "light_elevation_rad",
    "device_s",
    "wall_s",
    "finished_unix_s",
];

impl SampleRecord {
    /// The real-valued fields, in the order of [`SAMPLE_REAL_COLUMNS`].
    pub(crate) fn reals(&self) -> [f64; 16] {
        let (v, a) = (self.value, self.readback);
        [
            v.x,
            v.y,
            v.z,
            self.rate_dn_s[0],
            self.rate_dn_s[1],
            self.rate_dn_s[2],
            self.sigma_dn_s[0],
            self.sigma_dn_s[1],
            self.sigma_dn_s[2],
            a.turntable_rad,
            a.camera_rad,
            a.light_azimuth_rad,
            a.light_elevation_rad,
            self.device_s,
            self.wall_s,
            self.finished_unix_s,
        ]
    }

    /// A sample without captures from its key, its [`SampleRecord::reals`], its lower-bound
    /// flag and its tries.
    fn from_reals(stage: Stage, seq: u32, r: [f64; 16], lower_bound: bool, attempts: u32) -> Self {
        Self {
            stage: stage.name().to_string(),
            seq,
            value: Rgb::new(r[0], r[1], r[2]),
            rate_dn_s: [r[3], r[4], r[5]],
            sigma_dn_s: [r[6], r[7], r[8]],
            lower_bound,
            readback: AxisPositions::new(r[9], r[10], r[11], r[12]),
            device_s: r[13],
            wall_s: r[14],
            finished_unix_s: r[15],
            attempts,
            captures: Vec::new(),
        }
    }
}

/// Progress of one stage.
#[derive(Debug, Clone, PartialEq)]
pub struct StageStatus {
    /// The stage.
    pub stage: Stage,
    /// Samples in the stage's plan.
    pub planned: usize,
    /// Samples of the stage in the journal.
    pub done: usize,
    /// Device time of the finished samples, seconds.
    pub device_s_done: f64,
    /// The time model's estimate for the samples left, seconds.
    pub predicted_s_left: f64,
    /// The time model's estimate for the finished samples, seconds.
    pub predicted_s_done: f64,
    /// Wall-clock time of the finished samples, seconds.
    pub wall_s_done: f64,
    /// Raw captures of the finished samples.
    pub captures: usize,
}

impl StageStatus {
    /// Device time left, seconds, as the progress bar estimates it
    /// ([`device_s_left`]).
    pub fn eta_device_s(&self) -> f64 {
        device_s_left(
            self.predicted_s_left,
            self.device_s_done,
            self.predicted_s_done,
        )
    }
}

/// Device time left, seconds: the time model's estimate for the samples left, scaled by how
/// the finished samples compared with their estimate (the model assumes a fixed bracket;
/// predicted exposures take less).
pub fn device_s_left(predicted_s_left: f64, device_s_done: f64, predicted_s_done: f64) -> f64 {
    if predicted_s_done > 0.0 && device_s_done > 0.0 {
        predicted_s_left * device_s_done / predicted_s_done
    } else {
        predicted_s_left
    }
}

/// What `specula session status` shows.
#[derive(Debug, Clone, PartialEq)]
pub struct SessionStatus {
    /// The journal's schema version.
    pub schema_version: i64,
    /// Progress of each stage in the journal.
    pub stages: Vec<StageStatus>,
    /// Events by kind (fault, retry, reconnect, interrupted, resumed, ...).
    pub events: BTreeMap<String, usize>,
    /// The most recent events, newest last: (unix time, kind, message).
    pub recent_events: Vec<(f64, String, String)>,
}

/// The event kind the workflow logs once it has written the reconstructed table.
pub const EVENT_COMPLETE: &str = "complete";

/// How far a session got.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SessionState {
    /// The reconstructed table is written ([`EVENT_COMPLETE`]).
    Complete,
    /// Every planned stage is wholly measured; the reconstruction is not written yet.
    Measured,
    /// Running, stopped or interrupted before every planned sample was measured, or nothing
    /// planned yet.
    InProgress,
}

impl SessionStatus {
    /// How far the session got.
    pub fn state(&self) -> SessionState {
        if self.events.contains_key(EVENT_COMPLETE) {
            SessionState::Complete
        } else if !self.stages.is_empty() && self.stages.iter().all(|s| s.done == s.planned) {
            SessionState::Measured
        } else {
            SessionState::InProgress
        }
    }
}

/// An open session journal.
pub struct Journal {
    /// Dropped first: the identity lock's descriptor must outlive SQLite's (closing any
    /// descriptor of a file drops the process's POSIX locks on it, SQLite's included).
    conn: Connection,
    path: PathBuf,
    /// Held while this process may write the session.
    lock: Option<File>,
    /// The journal file itself, locked while this process may write it (Unix).
    identity: Option<File>,
}

/// Seconds since the Unix epoch, now.
pub fn unix_now_s() -> f64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.as_secs_f64())
        .unwrap_or(0.0)
}

impl Journal {
    /// Opens the session at `path` for writing, creating it if it does not exist; takes the
    /// session's lock so that no second process writes it at the same time.
    pub fn open(path: &Path) -> Result<Journal, JournalError> {
        check::refuse_directory(path)?;
        let lock = take_lock(path)?;
        check::refuse_empty_file(path)?;
        let existing = lock_identity(path)?;
        let conn = Connection::open(path).map_err(|e| sql_error(path, e))?;
        let mut journal = Journal {
            conn,
            path: path.to_path_buf(),
            lock: Some(lock),
            identity: existing,
        };
        journal.prepare()?;
        if journal.identity.is_none() {
            // A journal created just now: no other name can have reached it before.
            journal.identity = lock_identity(path)?;
        }
        check::check_file(&journal.conn, path)?;
        Ok(journal)
    }

    /// Opens an existing session read-only (for `specula session status`), even while
    /// another process measures into it.
    pub fn open_read_only(path: &Path) -> Result<Journal, JournalError> {
        check::refuse_directory(path)?;
        check::refuse_empty_file(path)?;
        let flags = OpenFlags::SQLITE_OPEN_READ_ONLY | OpenFlags::SQLITE_OPEN_NO_MUTEX;
        let conn = Connection::open_with_flags(path, flags).map_err(|e| sql_error(path, e))?;
        let journal = Journal {
            conn,
            path: path.to_path_buf(),
            lock: None,
            identity: None,
        };
        let version = journal.schema_version()?;
        match version {
            None => Err(JournalError::NotAJournal {
                path: journal.name(),
            }),
            Some(v) if v != SCHEMA_VERSION => Err(JournalError::Version {
                path: journal.name(),
                found: v,
                expected: SCHEMA_VERSION,
            }),
            Some(_) => {
                check::check_file(&journal.conn, path)?;
                Ok(journal)
            }
        }
    }

    /// Refuses a journal file another process is writing, under any name (a hard link
    /// included; its writer's newest samples may be in a `-wal` file named after the other
    /// name, out of this name's sight). Call it before reading a session to resume it.
    pub fn refuse_in_use(path: &Path) -> Result<(), JournalError> {
        check::refuse_directory(path)?;
        lock_identity(path).map(drop)
    }

    pub(crate) fn path(&self) -> &Path {
        &self.path
    }

    /// Closes a finished session: the journal goes back to one file (rollback mode, so that
    /// later readers leave no `-wal` or `-shm` file beside it) and the lock file is removed
    /// while still held. A resumed run opens it in WAL mode again.
    pub fn close(self) -> Result<(), JournalError> {
        self.conn
            .pragma_update(None, "journal_mode", "DELETE")
            .map_err(|e| self.err(e))?;
        if self.lock.is_some() {
            // A process waiting on the removed file sees that it is gone ([`take_lock`]).
            lock_path(&self.path)
                .and_then(std::fs::remove_file)
                .map_err(|cause| JournalError::Lock {
                    path: self.name(),
                    cause,
                })?;
        }
        Ok(())
    }

    /// Sets what a committed sample survives (default [`Durability::PowerCut`]).
    pub fn set_durability(&self, durability: Durability) -> Result<(), JournalError> {
        let mode = match durability {
            Durability::PowerCut => "FULL",
            Durability::Crash => "NORMAL",
        };
        self.conn
            .pragma_update(None, "synchronous", mode)
            .map_err(|e| self.err(e))
    }

    fn name(&self) -> String {
        self.path.display().to_string()
    }

    fn err(&self, source: rusqlite::Error) -> JournalError {
        sql_error(&self.path, source)
    }

    /// WAL, full sync, the tables, and the schema version check.
    fn prepare(&mut self) -> Result<(), JournalError> {
        self.conn
            .pragma_update(None, "journal_mode", "WAL")
            .map_err(|e| self.err(e))?;
        self.conn
            .pragma_update(None, "synchronous", "FULL")
            .map_err(|e| self.err(e))?;
        self.conn
            .pragma_update(None, "foreign_keys", "ON")
            .map_err(|e| self.err(e))?;
        let existing: i64 = self
            .conn
            .query_row("SELECT count(*) FROM sqlite_master", [], |r| r.get(0))
            .map_err(|e| self.err(e))?;
        if existing > 0 {
            match self.schema_version()? {
                Some(v) if v == SCHEMA_VERSION => return Ok(()),
                Some(v) => {
                    return Err(JournalError::Version {
                        path: self.name(),
                        found: v,
                        expected: SCHEMA_VERSION,
                    })
                }
                None => return Err(JournalError::NotAJournal { path: self.name() }),
            }
        }
        let tx = self
            .conn
            .transaction()
            .map_err(|e| sql_error(&self.path, e))?;
        tx.execute_batch(SCHEMA)
            .map_err(|e| sql_error(&self.path, e))?;
        tx.execute(
            "INSERT INTO meta (key, value) VALUES ('schema_version', ?1)",
            params![SCHEMA_VERSION.to_string()],
        )
        .map_err(|e| sql_error(&self.path, e))?;
        tx.execute(
            "INSERT INTO meta (key, value) VALUES ('created_unix_s', ?1)",
            params![unix_now_s().to_string()],
        )
        .map_err(|e| sql_error(&self.path, e))?;
        tx.commit().map_err(|e| sql_error(&self.path, e))
    }

    fn schema_version(&self) -> Result<Option<i64>, JournalError> {
        let has_meta: i64 = self
            .conn
            .query_row(
                "SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = 'meta'",
                [],
                |r| r.get(0),
            )
            .map_err(|e| self.err(e))?;
        if has_meta == 0 {
            return Ok(None);
        }
        let text: Option<String> = self
            .conn
            .query_row(
                "SELECT value FROM meta WHERE key = 'schema_version'",
                [],
                |r| r.get(0),
            )
            .optional()
            .map_err(|e| self.err(e))?;
        Ok(text.and_then(|t| t.parse().ok()))
    }

    /// Stores a metadata value as JSON (replacing an earlier one).
    pub fn put_meta<T: Serialize + ?Sized>(
        &self,
        key: &str,
        value: &T,
    ) -> Result<(), JournalError> {
        let text = serde_json::to_string(value).map_err(|cause| JournalError::Json {
            path: self.name(),
            key: key.to_string(),
            cause,
        })?;
        self.conn
            .execute(
                "INSERT INTO meta (key, value) VALUES (?1, ?2)
                 ON CONFLICT (key) DO UPDATE SET value = excluded.value",
                params![key, text],
            )
            .map_err(|e| self.err(e))?;
        Ok(())
    }

    /// A metadata value, if stored.
    pub fn meta<T: DeserializeOwned>(&self, key: &str) -> Result<Option<T>, JournalError> {
        let text: Option<String> = self
            .conn
            .query_row("SELECT value FROM meta WHERE key = ?1", params![key], |r| {
                r.get(0)
            })
            .optional()
            .map_err(|e| self.err(e))?;
        text.map(|t| {
            serde_json::from_str(&t).map_err(|cause| JournalError::Json {
                path: self.name(),
                key: key.to_string(),
                cause,
            })
        })
        .transpose()
    }

    /// Stores `value` under `key` the first time; later, returns what is stored (a resumed
    /// session keeps its first settings, fit and plan).
    pub fn meta_or_insert<T: Serialize + DeserializeOwned>(
        &self,
        key: &str,
        value: impl FnOnce() -> T,
    ) -> Result<T, JournalError> {
        if let Some(stored) = self.meta(key)? {
            return Ok(stored);
        }
        let value = value();
        self.put_meta(key, &value)?;
        Ok(value)
    }

    /// The typed record `R`, if the journal holds it.
    pub fn record<R: Record + DeserializeOwned>(&self) -> Result<Option<R>, JournalError> {
        self.meta(R::KEY)
    }

    /// Keep the typed record `R` (replacing the one held).
    pub fn put_record<R: Record>(&self, value: &R) -> Result<(), JournalError> {
        self.put_meta(R::KEY, value)
    }

    /// The typed record `R` held, or `value()` kept and returned when there is none.
    pub fn record_or_insert<R: Record + DeserializeOwned>(
        &self,
        value: impl FnOnce() -> R,
    ) -> Result<R, JournalError> {
        self.meta_or_insert(R::KEY, value)
    }

    /// Writes a stage's plan in one transaction. If the stage already has a plan (a resumed
    /// session), it must be the same samples; the stored one is kept.
    pub fn set_plan(&mut self, stage: Stage, rows: &[PlannedRow]) -> Result<(), JournalError> {
        let stored = self.plan(stage)?;
        if !stored.is_empty() {
            return self.check_same_plan(stage, &stored, rows);
        }
        let path = self.path.clone();
        let tx = self.conn.transaction().map_err(|e| sql_error(&path, e))?;
        insert_plan(&tx, stage, rows).map_err(|e| sql_error(&path, e))?;
        tx.commit().map_err(|e| sql_error(&path, e))
    }

    fn check_same_plan(
        &self,
        stage: Stage,
        stored: &[PlannedRow],
        asked: &[PlannedRow],
    ) -> Result<(), JournalError> {
        let mismatch = |problem: String| JournalError::PlanMismatch {
            path: self.name(),
            stage: stage.name().to_string(),
            problem,
        };
        if stored.len() != asked.len() {
            return Err(mismatch(format!(
                "{} samples stored, {} asked for",
                stored.len(),
                asked.len()
            )));
        }
        for (a, b) in stored.iter().zip(asked) {
            if a != b {
                return Err(mismatch(format!("sample {} differs", a.seq)));
            }
        }
        Ok(())
    }

    /// A stage's plan in execution order (empty when the stage has none yet).
    pub fn plan(&self, stage: Stage) -> Result<Vec<PlannedRow>, JournalError> {
        let mut statement = self
            .conn
            .prepare(
                "SELECT seq, theta_h_rad, phi_h_rad, theta_d_rad, phi_d_rad, turntable_rad,
                        camera_rad, light_azimuth_rad, light_elevation_rad, predicted_s
                 FROM plan WHERE stage = ?1 ORDER BY seq",
            )
            .map_err(|e| self.err(e))?;
        let rows = statement
            .query_map(params![stage], |r| {
                Ok(PlannedRow {
                    seq: r.get(0)?,
                    hd: HalfDiff {
                        theta_h: r.get(1)?,
                        phi_h: r.get(2)?,
                        theta_d: r.get(3)?,
                        phi_d: r.get(4)?,
                    },
                    axes: AxisPositions::new(r.get(5)?, r.get(6)?, r.get(7)?, r.get(8)?),
                    predicted_s: r.get(9)?,
                })
            })
            .map_err(|e| self.err(e))?;
        rows.collect::<Result<_, _>>().map_err(|e| self.err(e))
    }

    /// Writes a finished sample and its captures in one transaction. A sample already in the
    /// journal is refused ([`JournalError::Duplicate`]) and the journal left as it was.
    pub fn record_sample(&mut self, sample: &SampleRecord) -> Result<(), JournalError> {
        if let Some((field, value)) = check::non_finite_field(sample) {
            return Err(JournalError::NotFinite {
                path: self.name(),
                stage: sample.stage.clone(),
                seq: sample.seq,
                field,
                value,
            });
        }
        let path = self.path.clone();
        let tx = self.conn.transaction().map_err(|e| sql_error(&path, e))?;
        match insert_sample(&tx, sample) {
            Ok(()) => {}
            Err(rusqlite::Error::SqliteFailure(code, _))
                if code.extended_code == rusqlite::ffi::SQLITE_CONSTRAINT_PRIMARYKEY =>
            {
                return Err(JournalError::Duplicate {
                    path: path.display().to_string(),
                    stage: sample.stage.clone(),
                    seq: sample.seq,
                });
            }
            Err(e) => return Err(sql_error(&path, e)),
        }
        tx.commit().map_err(|e| sql_error(&path, e))
    }

    /// The finished samples of a stage, by seq, without their captures.
    pub fn samples(&self, stage: Stage) -> Result<BTreeMap<u32, SampleRecord>, JournalError> {
        let mut statement = self
            .conn
            .prepare(&format!(
                "SELECT seq, {}, lower_bound, attempts, checksum
                     FROM samples WHERE stage = ?1 ORDER BY seq",
                SAMPLE_REAL_COLUMNS.join(", ")
            ))
            .map_err(|e| self.err(e))?;
        let rows = statement
            .query_map(params![stage], |r| {
                let mut reals = [0.0; 16];
                for (i, value) in reals.iter_mut().enumerate() {
                    *value = r.get(1 + i)?;
                }
                let record =
                    SampleRecord::from_reals(stage, r.get(0)?, reals, r.get(17)?, r.get(18)?);
                Ok((record, r.get::<_, i64>(19)?))
            })
            .map_err(|e| self.err(e))?;
        let mut samples = BTreeMap::new();
        for row in rows {
            let (record, checksum) = row.map_err(|e| self.err(e))?;
            check::verify_sample(&record, checksum).map_err(|problem| JournalError::Damaged {
                path: self.name(),
                problem: problem.into(),
            })?;
            samples.insert(record.seq, record);
        }
        Ok(samples)
    }

    /// The captures of one sample, in the order they were taken.
    pub fn captures(&self, stage: Stage, seq: u32) -> Result<Vec<CaptureRecord>, JournalError> {
        let mut statement = self
            .conn
            .prepare(
                "SELECT exposure_s, light_level, mean_r, mean_g, mean_b, saturated_r,
                        saturated_g, saturated_b, pixel_count, used, unix_s
                 FROM captures WHERE stage = ?1 AND seq = ?2 ORDER BY id",
            )
            .map_err(|e| self.err(e))?;
        let rows = statement
            .query_map(params![stage, seq], |r| {
                Ok(CaptureRecord {
                    exposure_s: r.get(0)?,
                    light_level: r.get(1)?,
                    mean_raw: [r.get(2)?, r.get(3)?, r.get(4)?],
                    saturated_fraction: [r.get(5)?, r.get(6)?, r.get(7)?],
                    pixel_count: r.get(8)?,
                    used: r.get(9)?,
                    unix_s: r.get(10)?,
                })
            })
            .map_err(|e| self.err(e))?;
        rows.collect::<Result<_, _>>().map_err(|e| self.err(e))
    }

    /// Notes an event (fault, retry, reconnect, interrupted, resumed, ...).
    pub fn log_event(&self, kind: &str, message: &str) -> Result<(), JournalError> {
        self.conn
            .execute(
                "INSERT INTO events (unix_s, kind, message) VALUES (?1, ?2, ?3)",
                params![unix_now_s(), kind, message],
            )
            .map_err(|e| self.err(e))?;
        Ok(())
    }

    /// Progress by stage, capture counts and events.
    pub fn status(&self) -> Result<SessionStatus, JournalError> {
        let mut stages = Vec::new();
        let names: Vec<String> = self.column("SELECT DISTINCT stage FROM plan ORDER BY rowid")?;
        for stage in names.iter().filter_map(|name| Stage::from_name(name)) {
            stages.push(self.stage_status(stage)?);
        }
        let mut events = BTreeMap::new();
        let mut statement = self
            .conn
            .prepare("SELECT kind, count(*) FROM events GROUP BY kind")
            .map_err(|e| self.err(e))?;
        let counts = statement
            .query_map([], |r| {
                Ok((r.get::<_, String>(0)?, r.get::<_, i64>(1)? as usize))
            })
            .map_err(|e| self.err(e))?;
        for count in counts {
            let (kind, n) = count.map_err(|e| self.err(e))?;
            events.insert(kind, n);
        }
        let mut statement = self
            .conn
            .prepare("SELECT unix_s, kind, message FROM events ORDER BY id DESC LIMIT 5")
            .map_err(|e| self.err(e))?;
        let mut recent_events = statement
            .query_map([], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)))
            .map_err(|e| self.err(e))?
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| self.err(e))?;
        recent_events.reverse();
        Ok(SessionStatus {
            schema_version: self.schema_version()?.unwrap_or(0),
            stages,
            events,
            recent_events,
        })
    }

    fn stage_status(&self, stage: Stage) -> Result<StageStatus, JournalError> {
        let (planned, predicted_s_left, predicted_s_done): (i64, f64, f64) = self
            .conn
            .query_row(
                "SELECT count(*), coalesce(sum(CASE WHEN s.seq IS NULL THEN p.predicted_s END), 0),
                        coalesce(sum(CASE WHEN s.seq IS NOT NULL THEN p.predicted_s END), 0)
                 FROM plan p LEFT JOIN samples s ON s.stage = p.stage AND s.seq = p.seq
                 WHERE p.stage = ?1",
                params![stage],
                |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)),
            )
            .map_err(|e| self.err(e))?;
        let (done, device_s_done, wall_s_done): (i64, f64, f64) = self
            .conn
            .query_row(
                "SELECT count(*), coalesce(sum(device_s), 0), coalesce(sum(wall_s), 0)
                 FROM samples WHERE stage = ?1",
                params![stage],
                |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)),
            )
            .map_err(|e| self.err(e))?;
        let captures: i64 = self
            .conn
            .query_row(
                "SELECT count(*) FROM captures WHERE stage = ?1",
                params![stage],
                |r| r.get(0),
            )
            .map_err(|e| self.err(e))?;
        Ok(StageStatus {
            stage,
            planned: planned as usize,
            done: done as usize,
            device_s_done,
            predicted_s_left,
            predicted_s_done,
            wall_s_done,
            captures: captures as usize,
        })
    }

    fn column(&self, sql: &str) -> Result<Vec<String>, JournalError> {
        let mut statement = self.conn.prepare(sql).map_err(|e| self.err(e))?;
        let rows = statement
            .query_map([], |r| r.get(0))
            .map_err(|e| self.err(e))?;
        rows.collect::<Result<_, _>>().map_err(|e| self.err(e))
    }
}

fn sql_error(path: &Path, cause: rusqlite::Error) -> JournalError {
    let path = path.display().to_string();
    match check::damage(&cause) {
        Some(problem) => JournalError::Damaged {
            path,
            problem: problem.into(),
        },
        None => JournalError::Sqlite { path, cause },
    }
}

/// The lock file beside the journal, locked exclusively for as long as it is open (the OS
/// releases it when the process dies, however it dies).
/// A lock taken on a file that [`Journal::close`] removed meanwhile is no lock: the file is
/// opened again until the locked file is the one at the path.
fn take_lock(path: &Path) -> Result<File, JournalError> {
    let lock_path = lock_path(path).map_err(|cause| JournalError::Lock {
        path: path.display().to_string(),
        cause,
    })?;
    let open = || {
        File::options()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&lock_path)
            .map_err(|cause| JournalError::Lock {
                path: path.display().to_string(),
                cause,
            })
    };
    let mut file = open()?;
    // A few tries: a child process forked by another thread of this process holds a copy
    // of a just-closed lock until it execs (the descriptor is close-on-exec).
    for _ in 0..LOCK_TRIES {
        match file.try_lock() {
            Ok(()) if is_at_path(&file, &lock_path) => return Ok(file),
            Ok(()) => file = open()?,
            Err(std::fs::TryLockError::WouldBlock) => std::thread::sleep(LOCK_PAUSE),
            Err(std::fs::TryLockError::Error(cause)) => {
                return Err(JournalError::Lock {
                    path: path.display().to_string(),
                    cause,
                })
            }
        }
    }
    Err(JournalError::Locked {
        path: path.display().to_string(),
        lock: lock_path.display().to_string(),
    })
}

/// Locks the journal file itself, whatever its name (`flock` on Unix: SQLite's own locks
/// are POSIX record locks, which it does not conflict with); `None` when there is no file yet
/// (or elsewhere than Unix, where the file's own lock would bar SQLite's reads).
fn lock_identity(path: &Path) -> Result<Option<File>, JournalError> {
    if !cfg!(unix) || !path.exists() {
        return Ok(None);
    }
    let file = File::open(path).map_err(|cause| JournalError::Lock {
        path: path.display().to_string(),
        cause,
    })?;
    for _ in 0..LOCK_TRIES {
        match file.try_lock() {
            Ok(()) => return Ok(Some(file)),
            Err(std::fs::TryLockError::WouldBlock) => std::thread::sleep(LOCK_PAUSE),
            Err(std::fs::TryLockError::Error(cause)) => {
                return Err(JournalError::Lock {
                    path: path.display().to_string(),
                    cause,
                })
            }
        }
    }
    Err(JournalError::InUse {
        path: path.display().to_string(),
    })
}

/// `S.sqlite.lock` beside the journal `S.sqlite`, named after its canonical path (so that
/// two spellings of one journal take one lock).
fn lock_path(path: &Path) -> std::io::Result<PathBuf> {
    let mut lock_path = check::canonical_path(path)?.into_os_string();
    lock_path.push(".lock");
    Ok(PathBuf::from(lock_path))
}

/// Whether the open `file` is still the file at `path` (not removed or replaced).
fn is_at_path(file: &File, path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (file.metadata(), std::fs::metadata(path)) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = file;
        path.exists()
    }
}

const LOCK_TRIES: usize = 10;
const LOCK_PAUSE: std::time::Duration = std::time::Duration::from_millis(25);

fn insert_plan(tx: &Transaction, stage: Stage, rows: &[PlannedRow]) -> rusqlite::Result<()> {
    let mut statement = tx.prepare(
        "INSERT INTO plan (stage, seq, theta_h_rad, phi_h_rad, theta_d_rad, phi_d_rad,
                           turntable_rad, camera_rad, light_azimuth_rad, light_elevation_rad,
                           predicted_s)
         VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11)",
    )?;
    for row in rows {
        let a = row.axes;
        statement.execute(params![
            stage,
            row.seq,
            row.hd.theta_h,
            row.hd.phi_h,
            row.hd.theta_d,
            row.hd.phi_d,
            a.turntable_rad,
            a.camera_rad,
            a.light_azimuth_rad,
            a.light_elevation_rad,
            row.predicted_s
        ])?;
    }
    Ok(())
}

fn insert_sample(tx: &Transaction, s: &SampleRecord) -> rusqlite::Result<()> {
    use rusqlite::types::Value;
    let sql = format!(
        "INSERT INTO samples (stage, seq, {}, lower_bound, attempts, checksum)
         VALUES ({})",
        SAMPLE_REAL_COLUMNS.join(", "),
        (1..=SAMPLE_REAL_COLUMNS.len() + 5)
            .map(|i| format!("?{i}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let mut values = vec![Value::from(s.stage.clone()), Value::from(s.seq)];
    values.extend(s.reals().map(Value::from));
    values.extend([
        Value::from(s.lower_bound),
        Value::from(s.attempts),
        Value::from(check::sample_checksum(s)),
    ]);
    tx.execute(&sql, rusqlite::params_from_iter(values))?;
    let mut statement = tx.prepare(
        "INSERT INTO captures (stage, seq, exposure_s, light_level, mean_r, mean_g, mean_b,
                               saturated_r, saturated_g, saturated_b, pixel_count, used, unix_s)
         VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13)",
    )?;
    for c in &s.captures {
        statement.execute(params![
            s.stage,
            s.seq,
            c.exposure_s,
            c.light_level,
            c.mean_raw[0],
            c.mean_raw[1],
            c.mean_raw[2],
            c.saturated_fraction[0],
            c.saturated_fraction[1],
            c.saturated_fraction[2],
            c.pixel_count,
            c.used,
            c.unix_s
        ])?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(seq: u32) -> PlannedRow {
        PlannedRow {
            seq,
            hd: HalfDiff::from_degrees(seq as f64, 45.0, 40.0, 90.0),
            axes: AxisPositions::from_degrees(seq as f64, 10.0, 20.0, 30.0),
            predicted_s: 2.5,
        }
    }

    fn sample(stage: Stage, seq: u32) -> SampleRecord {
        SampleRecord {
            stage: stage.name().into(),
            seq,
            value: Rgb::new(0.1 * seq as f64, 1e-7, 1234.5),
            rate_dn_s: [1e5, 2e-3, 7.0],
            sigma_dn_s: [10.0, 1e-4, f64::INFINITY],
            lower_bound: true,
            readback: AxisPositions::from_degrees(seq as f64 + 0.01, 10.0, 20.0, 30.0),
            device_s: 3.0,
            wall_s: 0.01,
            finished_unix_s: unix_now_s(),
            attempts: 1,
            captures: vec![
                CaptureRecord {
                    exposure_s: 0.01,
                    light_level: 1.0,
                    mean_raw: [4095.0, 4000.0, 100.0],
                    saturated_fraction: [1.0, 0.5, 0.0],
                    pixel_count: 1849,
                    used: false,
                    unix_s: 1.0,
                },
                CaptureRecord {
                    exposure_s: 0.001,
                    light_level: 0.05,
                    mean_raw: [300.0, 290.0, 64.0],
                    saturated_fraction: [0.0; 3],
                    pixel_count: 1849,
                    used: true,
                    unix_s: 2.0,
                },
            ],
        }
    }

    #[test]
    fn samples_and_captures_round_trip_exactly() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.sqlite");
        let mut journal = Journal::open(&path).unwrap();
        let plan: Vec<PlannedRow> = (0..5).map(row).collect();
        journal.set_plan(Stage::Main, &plan).unwrap();
        assert_eq!(journal.plan(Stage::Main).unwrap(), plan);
        let s = sample(Stage::Main, 3);
        journal.record_sample(&s).unwrap();
        drop(journal);

        let journal = Journal::open(&path).unwrap();
        let stored = journal.samples(Stage::Main).unwrap();
        assert_eq!(stored.len(), 1);
        let back = &stored[&3];
        assert_eq!(back.value, s.value, "f64 values are stored bit for bit");
        assert_eq!(back.readback, s.readback);
        assert_eq!(
            (back.rate_dn_s, back.sigma_dn_s, back.lower_bound),
            (s.rate_dn_s, s.sigma_dn_s, true)
        );
        assert_eq!(journal.captures(Stage::Main, 3).unwrap(), s.captures);
        let status = journal.status().unwrap();
        assert_eq!(status.stages.len(), 1);
        let main = &status.stages[0];
        assert_eq!((main.planned, main.done, main.captures), (5, 1, 2));
        assert!((main.predicted_s_left - 4.0 * 2.5).abs() < 1e-12);
        assert!((main.device_s_done - 3.0).abs() < 1e-12);
    }

    #[test]
    fn a_session_is_measured_when_every_stage_is_and_complete_once_written() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.sqlite");
        let mut journal = Journal::open(&path).unwrap();
        assert_eq!(journal.status().unwrap().state(), SessionState::InProgress);
        journal.set_plan(Stage::Probe, &[row(0)]).unwrap();
        journal.set_plan(Stage::Main, &[row(1), row(2)]).unwrap();
        journal.record_sample(&sample(Stage::Probe, 0)).unwrap();
        journal.record_sample(&sample(Stage::Main, 1)).unwrap();
        assert_eq!(journal.status().unwrap().state(), SessionState::InProgress);
        journal.record_sample(&sample(Stage::Main, 2)).unwrap();
        assert_eq!(journal.status().unwrap().state(), SessionState::Measured);
        journal.log_event(EVENT_COMPLETE, "wrote x.binary").unwrap();
        assert_eq!(journal.status().unwrap().state(), SessionState::Complete);
    }

    #[test]
    fn a_sample_is_never_recorded_twice() {
        let dir = tempfile::tempdir().unwrap();
        let mut journal = Journal::open(&dir.path().join("s.sqlite")).unwrap();
        journal.set_plan(Stage::Main, &[row(0)]).unwrap();
        journal.record_sample(&sample(Stage::Main, 0)).unwrap();
        let err = journal.record_sample(&sample(Stage::Main, 0)).unwrap_err();
        assert!(
            matches!(err, JournalError::Duplicate { seq: 0, .. }),
            "{err}"
        );
        // The failed transaction left nothing behind: still two captures.
        assert_eq!(journal.captures(Stage::Main, 0).unwrap().len(), 2);
        // A sample outside the plan is refused by the foreign key.
        assert!(journal.record_sample(&sample(Stage::Main, 9)).is_err());
        assert!(journal.samples(Stage::Main).unwrap().contains_key(&0));
        assert!(!journal.samples(Stage::Main).unwrap().contains_key(&9));
    }

    #[test]
    fn a_stage_plan_is_written_once() {
        let dir = tempfile::tempdir().unwrap();
        let mut journal = Journal::open(&dir.path().join("s.sqlite")).unwrap();
        let plan: Vec<PlannedRow> = (0..3).map(row).collect();
        journal.set_plan(Stage::Probe, &plan).unwrap();
        journal.set_plan(Stage::Probe, &plan).unwrap();
        let mut other = plan.clone();
        other[1].axes.camera_rad += 1e-6;
        let err = journal
            .set_plan(Stage::Probe, &other)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("sample 1 differs") && err.contains("probe"),
            "{err}"
        );
        let err = journal
            .set_plan(Stage::Probe, &plan[..2])
            .unwrap_err()
            .to_string();
        assert!(err.contains("3 samples stored, 2 asked for"), "{err}");
    }

    #[cfg(unix)]
    #[test]
    fn a_hard_link_to_an_open_journal_is_refused_before_sqlite_opens_it() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.sqlite");
        let writer = Journal::open(&path).unwrap();
        let link = dir.path().join("h.sqlite");
        std::fs::hard_link(&path, &link).unwrap();
        let err = Journal::open(&link).err().expect("a second writer refused");
        assert!(matches!(err, JournalError::InUse { .. }), "{err}");
        assert!(err.to_string().contains("h.sqlite"), "{err}");
        assert!(Journal::refuse_in_use(&link).is_err());
        assert!(
            !dir.path().join("h.sqlite-wal").exists(),
            "no -wal beside the link"
        );
        drop(writer);
        assert!(Journal::open(&link).is_ok(), "free once the first closes");
        let err = Journal::open(dir.path())
            .err()
            .expect("a directory refused");
        assert!(matches!(err, JournalError::Directory { .. }), "{err}");
    }

    #[test]
    fn meta_is_json_and_first_value_wins() {
        let dir = tempfile::tempdir().unwrap();
        let journal = Journal::open(&dir.path().join("s.sqlite")).unwrap();
        assert_eq!(journal.meta::<f64>("k_hat").unwrap(), None);
        assert_eq!(journal.meta_or_insert("k_hat", || 4.78).unwrap(), 4.78);
        assert_eq!(journal.meta_or_insert("k_hat", || 9.0).unwrap(), 4.78);
        journal.put_meta("device", "name = \"x\"").unwrap();
        assert_eq!(
            journal.meta::<String>("device").unwrap().unwrap(),
            "name = \"x\""
        );
        let wrong: Result<Option<Vec<u8>>, _> = journal.meta("device");
        assert!(wrong.unwrap_err().to_string().contains("device"));
    }

    #[test]
    fn one_writer_at_a_time_and_readers_alongside() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.sqlite");
        let mut writer = Journal::open(&path).unwrap();
        let err = Journal::open(&path).err().expect("second writer refused");
        assert!(err.to_string().contains("another specula process"), "{err}");
        writer.set_plan(Stage::Main, &[row(0), row(1)]).unwrap();
        writer.record_sample(&sample(Stage::Main, 1)).unwrap();
        let reader = Journal::open_read_only(&path).unwrap();
        assert_eq!(reader.status().unwrap().stages[0].done, 1);
        drop(writer);
        Journal::open(&path).expect("the lock goes with the writer");
    }

    #[test]
    fn foreign_files_are_refused_with_their_name() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("other.sqlite");
        {
            let conn = Connection::open(&path).unwrap();
            conn.execute_batch("CREATE TABLE t (x INTEGER);").unwrap();
        }
        let err = Journal::open(&path).err().unwrap().to_string();
        assert!(
            err.contains("other.sqlite") && err.contains("not a specula"),
            "{err}"
        );
        let text = dir.path().join("text.sqlite");
        std::fs::write(
            &text,
            "hello, this is not a database at all, not even close....",
        )
        .unwrap();
        let err = Journal::open_read_only(&text).err().unwrap().to_string();
        assert!(err.contains("text.sqlite"), "{err}");
        {
            let journal = Journal::open(&dir.path().join("v.sqlite")).unwrap();
            journal.put_meta("schema_version", &99).unwrap();
        }
        let err = Journal::open(&dir.path().join("v.sqlite"))
            .err()
            .unwrap()
            .to_string();
        assert!(err.contains("version 99"), "{err}");
    }
}
