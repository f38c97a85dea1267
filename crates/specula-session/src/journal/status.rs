//! How far a session is: progress by stage, capture counts and events.

use super::{Journal, JournalError, Stage};
use rusqlite::params;
use std::collections::BTreeMap;

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

impl Journal {
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
