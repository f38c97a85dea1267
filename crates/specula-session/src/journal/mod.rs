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
mod error;
mod lock;
mod samples;
mod schema;
mod status;
mod status_text;

pub use check::{ChecksumMismatch, Damage};
use error::sql_error;
pub use error::JournalError;
use lock::{lock_identity, lock_path, take_lock};
use rusqlite::{params, Connection, OpenFlags, OptionalExtension};
pub use samples::{CaptureRecord, PlannedRow, SampleRecord};
pub use schema::SCHEMA_VERSION;
use serde::de::DeserializeOwned;
use serde::Serialize;
pub use status::{device_s_left, SessionState, SessionStatus, StageStatus, EVENT_COMPLETE};
use std::fs::File;
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

mod records;

pub use records::{
    BatchRecord, ChecksRecord, CreatedRecord, DeviceRecord, FitRecord, HdrChoice, MeasureSettings,
    NewestVersionRecord, PlanOrder, PlanRecord, Record, SequenceRecord, SequentialSettings,
    SessionRecord, SourceRecord, Stage, VersionRecord,
};

/// What a committed sample survives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Durability {
    /// A crash or kill of the process, and a power cut (a disk flush per sample).
    PowerCut,
    /// A crash or kill of the process; a power cut may lose the last samples.
    Crash,
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
        check::refuse_missing(path)?;
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

    /// Stores a metadata value as JSON (replacing an earlier one).
    pub fn put_meta<T: Serialize + ?Sized>(
        &self,
        key: &str,
        value: &T,
    ) -> Result<(), JournalError> {
        let text = self.json(key, value)?;
        self.conn
            .execute(
                "INSERT INTO meta (key, value) VALUES (?1, ?2)
                 ON CONFLICT (key) DO UPDATE SET value = excluded.value",
                params![key, text],
            )
            .map_err(|e| self.err(e))?;
        Ok(())
    }

    /// `value` as the JSON text the `meta` table keeps under `key`.
    fn json<T: Serialize + ?Sized>(&self, key: &str, value: &T) -> Result<String, JournalError> {
        serde_json::to_string(value).map_err(|cause| JournalError::Json {
            path: self.name(),
            key: key.to_string(),
            cause,
        })
    }

    /// The typed record `R` as the JSON text the `meta` table keeps.
    fn record_json<R: Record>(&self, value: &R) -> Result<String, JournalError> {
        self.json(R::KEY, value)
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_acquisition::kinematics::AxisPositions;
    use specula_core::{HalfDiff, Rgb};

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
        let missing = dir.path().join("never-measured.sqlite");
        let err = Journal::open_read_only(&missing)
            .err()
            .expect("a missing journal refused");
        assert!(matches!(err, JournalError::Missing { .. }), "{err}");
        assert!(
            err.to_string()
                .contains("never-measured.sqlite: no such session journal"),
            "{err}"
        );
        assert!(!missing.exists(), "reading creates nothing");
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
