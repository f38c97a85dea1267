//! The journal's tables (schema version [`SCHEMA_VERSION`]) and their creation or check
//! when a journal is opened for writing.

use super::{sql_error, unix_now_s, Journal, JournalError};
use rusqlite::{params, OptionalExtension};

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

impl Journal {
    /// WAL, full sync, the tables, and the schema version check.
    pub(super) fn prepare(&mut self) -> Result<(), JournalError> {
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

    pub(super) fn schema_version(&self) -> Result<Option<i64>, JournalError> {
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
}
