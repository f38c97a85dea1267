//! The planned and finished samples of each stage and their captures: the `plan`,
//! `samples` and `captures` tables, one transaction per sample.

use super::{check, sql_error, Journal, JournalError, Record, Stage};
use rusqlite::{params, Transaction};
use specula_acquisition::kinematics::AxisPositions;
use specula_core::{HalfDiff, Rgb};
use std::collections::BTreeMap;

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

impl Journal {
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

    /// Appends `rows` to a stage's plan and keeps `record` (the decision that chose them), in
    /// one transaction: a sequential measurement's next batch. The rows' `seq` must continue
    /// the stored plan's; a crash leaves the journal with both or neither.
    pub fn append_plan<R: Record>(
        &mut self,
        stage: Stage,
        rows: &[PlannedRow],
        record: &R,
    ) -> Result<(), JournalError> {
        let stored = self.plan(stage)?.len();
        if let Some((i, row)) = rows
            .iter()
            .enumerate()
            .find(|(i, row)| row.seq as usize != stored + i)
        {
            return Err(JournalError::PlanMismatch {
                path: self.name(),
                stage: stage.name().to_string(),
                problem: format!(
                    "appended sample {} has seq {}, expected {}",
                    i,
                    row.seq,
                    stored + i
                ),
            });
        }
        let text = self.record_json(record)?;
        let path = self.path.clone();
        let tx = self.conn.transaction().map_err(|e| sql_error(&path, e))?;
        insert_plan(&tx, stage, rows).map_err(|e| sql_error(&path, e))?;
        tx.execute(
            "INSERT INTO meta (key, value) VALUES (?1, ?2)
             ON CONFLICT (key) DO UPDATE SET value = excluded.value",
            params![R::KEY, text],
        )
        .map_err(|e| sql_error(&path, e))?;
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
            .prepare(&format!(
                "SELECT {CAPTURE_COLUMNS} FROM captures WHERE stage = ?1 AND seq = ?2 ORDER BY id"
            ))
            .map_err(|e| self.err(e))?;
        let rows = statement
            .query_map(params![stage, seq], |r| capture_of_row(r, 0))
            .map_err(|e| self.err(e))?;
        rows.collect::<Result<_, _>>().map_err(|e| self.err(e))
    }

    /// The captures of every finished sample of a stage, by seq, each sample's in the order
    /// they were taken.
    pub fn stage_captures(
        &self,
        stage: Stage,
    ) -> Result<BTreeMap<u32, Vec<CaptureRecord>>, JournalError> {
        let mut statement = self
            .conn
            .prepare(&format!(
                "SELECT seq, {CAPTURE_COLUMNS} FROM captures WHERE stage = ?1 ORDER BY id"
            ))
            .map_err(|e| self.err(e))?;
        let rows = statement
            .query_map(params![stage], |r| {
                Ok((r.get::<_, u32>(0)?, capture_of_row(r, 1)?))
            })
            .map_err(|e| self.err(e))?;
        let mut by_seq: BTreeMap<u32, Vec<CaptureRecord>> = BTreeMap::new();
        for row in rows {
            let (seq, capture) = row.map_err(|e| self.err(e))?;
            by_seq.entry(seq).or_default().push(capture);
        }
        Ok(by_seq)
    }
}

/// The columns of a capture, in the order [`capture_of_row`] reads them.
const CAPTURE_COLUMNS: &str = "exposure_s, light_level, mean_r, mean_g, mean_b, saturated_r, \
    saturated_g, saturated_b, pixel_count, used, unix_s";

/// A capture from a row whose [`CAPTURE_COLUMNS`] start at column `first`.
fn capture_of_row(r: &rusqlite::Row, first: usize) -> rusqlite::Result<CaptureRecord> {
    let get = |i: usize| r.get::<_, f64>(first + i);
    Ok(CaptureRecord {
        exposure_s: get(0)?,
        light_level: get(1)?,
        mean_raw: [get(2)?, get(3)?, get(4)?],
        saturated_fraction: [get(5)?, get(6)?, get(7)?],
        pixel_count: r.get(first + 8)?,
        used: r.get(first + 9)?,
        unix_s: get(10)?,
    })
}

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
