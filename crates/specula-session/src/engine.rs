//! The acquisition loop (paper 5.3): for each planned sample of a stage that the journal does
//! not hold yet, in execution order: move, HDR capture, calibrate to 1/sr, and write the
//! sample with its captures in one transaction.
//!
//! Faults: a motor fault re-homes the axes and retries the sample; a timeout or a camera
//! fault retries it; a sample during which the link to a remote device was reopened is
//! measured again from the move (a restarted adapter may have lost its state); after [`EngineSettings::max_attempts`] tries, or on an error no retry
//! can fix (an axis limit, a link the client has given up on), the loop stops with an error
//! that names the sample. Nothing half-done reaches the journal, so the same command resumes.
//!
//! Stopping: a raised stop flag (Ctrl-C) is checked between samples, so the sample in
//! progress is finished and written first; a sample the instrument gave up on because of the
//! flag (a remote device's waits look at it) is not retried, not counted as a fault and
//! not written: the stage stops as if between samples.

use crate::journal::{
    unix_now_s, CaptureRecord, Journal, JournalError, PlannedRow, SampleRecord, Stage,
};
use crate::predict::{cos_theta_i, Predictor};
use crate::protocol::client::LinkNotes;
use specula_acquisition::calibration::Calibration;
use specula_acquisition::hdr::{HdrCapturer, HdrMeasurement};
use specula_acquisition::instrument::{Capture, Instrument, InstrumentError};
use specula_acquisition::kinematics::AxisPositions;
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// How a sample's HDR captures are chosen.
#[derive(Debug, Clone, PartialEq)]
pub enum HdrMode {
    /// Adaptive, starting from the predicted rate (one or two captures for most samples).
    Predicted,
    /// The paper's way: every exposure at every light level (the device file's `[capture]`).
    Bracket {
        /// Exposure times of the bracket, seconds.
        exposures_s: Vec<f64>,
        /// Light levels of the bracket, fractions of full power.
        light_levels: Vec<f64>,
    },
}

/// How to measure and how hard to try.
#[derive(Debug, Clone, PartialEq)]
pub struct EngineSettings {
    /// Tries per sample before the run stops.
    pub max_attempts: u32,
    /// How each sample's HDR captures are chosen.
    pub hdr: HdrMode,
}

impl Default for EngineSettings {
    fn default() -> Self {
        Self {
            max_attempts: 3,
            hdr: HdrMode::Predicted,
        }
    }
}

/// Why a stage stopped early.
#[derive(Debug, thiserror::Error)]
pub enum EngineError {
    /// The journal could not be read or written.
    #[error(transparent)]
    Journal(#[from] JournalError),
    /// The device failed on a sample as many times as the settings allow.
    #[error("{stage} sample {seq}: {error} (after {attempts} tries); the journal holds every sample before it: run the same command again to resume")]
    Device {
        /// The stage being measured (e.g. `probe`, `main`).
        stage: String,
        /// The failing sample's position in the stage's execution order.
        seq: u32,
        /// Tries made on the sample.
        attempts: u32,
        /// The device's error on the last try.
        error: InstrumentError,
    },
}

/// What a stage run did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StageOutcome {
    /// Samples in the stage's plan.
    pub planned: usize,
    /// Samples the journal held before this run.
    pub resumed: usize,
    /// Samples measured by this run.
    pub measured: usize,
    /// True when the stop flag ended the run before the stage was complete.
    pub stopped: bool,
}

impl StageOutcome {
    /// True when every planned sample is in the journal (resumed or measured).
    pub fn complete(&self) -> bool {
        self.resumed + self.measured == self.planned
    }
}

/// Progress after each sample, for a progress bar.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// Samples of the stage in the journal, resumed ones included.
    pub done: usize,
    /// Samples in the stage's plan.
    pub planned: usize,
    /// Device time of this stage's finished samples, seconds.
    pub device_s_done: f64,
    /// The time model's estimate for the finished samples, seconds.
    pub predicted_s_done: f64,
    /// The time model's estimate for the samples left, seconds.
    pub predicted_s_left: f64,
}

impl Progress {
    /// Device time left, seconds ([`crate::journal::device_s_left`]).
    pub fn eta_device_s(&self) -> f64 {
        crate::journal::device_s_left(
            self.predicted_s_left,
            self.device_s_done,
            self.predicted_s_done,
        )
    }
}

/// Whether another try may succeed after `error`: a motor fault (after homing), a timeout or
/// a camera fault. The acquisition and the checks retry these alike.
pub fn is_retryable(error: &InstrumentError) -> bool {
    matches!(
        error,
        InstrumentError::MotorFault(_)
            | InstrumentError::Timeout(_)
            | InstrumentError::CameraFault(_)
    )
}

/// Runs stages of a session on an instrument.
pub struct Engine<'a> {
    /// The device the samples are measured on.
    pub instrument: &'a mut dyn Instrument,
    /// The session journal the plan is read from and the samples written to.
    pub journal: &'a mut Journal,
    /// Takes the HDR captures and counts them.
    pub hdr: &'a mut HdrCapturer,
    /// Turns merged raw rates into BRDF values, 1/sr.
    pub calibration: &'a Calibration,
    /// Tries per sample and the HDR mode.
    pub settings: EngineSettings,
    /// Raised (by Ctrl-C) to stop after the sample in progress.
    pub stop: Arc<AtomicBool>,
    /// Retries and reconnections of a remote device, copied into the journal's events.
    pub link_notes: Option<LinkNotes>,
    /// The stages this engine has run: a stage run again (a sequential measurement's next
    /// batch) continues, and is not a resumption.
    pub ran: Vec<Stage>,
}

impl Engine<'_> {
    /// Measures every sample of `stage`'s plan (already in the journal) that the journal does
    /// not hold, in execution order. `on_sample` hears the progress after each.
    pub fn run_stage(
        &mut self,
        stage: Stage,
        predictor: &Predictor,
        on_sample: &mut dyn FnMut(Progress),
    ) -> Result<StageOutcome, EngineError> {
        let plan = self.journal.plan(stage)?;
        let mut done: BTreeMap<u32, SampleRecord> = self.journal.samples(stage)?;
        let mut outcome = StageOutcome {
            planned: plan.len(),
            resumed: done.len(),
            ..StageOutcome::default()
        };
        let mut device_s_done: f64 = done.values().map(|s| s.device_s).sum();
        let mut predicted_s_done: f64 = plan
            .iter()
            .filter(|r| done.contains_key(&r.seq))
            .map(|r| r.predicted_s)
            .sum();
        let mut predicted_s_left: f64 =
            plan.iter().map(|r| r.predicted_s).sum::<f64>() - predicted_s_done;
        let continued = self.ran.contains(&stage);
        if !continued {
            self.ran.push(stage);
        }
        if !continued && outcome.resumed > 0 && outcome.resumed < plan.len() {
            self.journal.log_event(
                "resumed",
                &format!(
                    "{stage}: {} of {} samples already measured",
                    outcome.resumed,
                    plan.len()
                ),
            )?;
        }
        for row in &plan {
            if done.contains_key(&row.seq) {
                continue;
            }
            let previous = row
                .seq
                .checked_sub(1)
                .and_then(|p| done.get(&p).map(|record| (&plan[p as usize], record)));
            let prediction = predictor.predict(row, previous);
            let measured = if self.stopped() {
                None
            } else {
                self.measure_sample(stage, row, prediction)?
            };
            let Some(record) = measured else {
                outcome.stopped = true;
                self.journal.log_event(
                    "interrupted",
                    &format!("{stage}: stopped by the user after {} samples", done.len()),
                )?;
                break;
            };
            self.journal.record_sample(&record)?;
            device_s_done += record.device_s;
            predicted_s_done += row.predicted_s;
            predicted_s_left -= row.predicted_s;
            done.insert(row.seq, record);
            outcome.measured += 1;
            on_sample(Progress {
                done: done.len(),
                planned: plan.len(),
                device_s_done,
                predicted_s_done,
                predicted_s_left: predicted_s_left.max(0.0),
            });
        }
        Ok(outcome)
    }

    /// Whether the stop flag is raised.
    fn stopped(&self) -> bool {
        self.stop.load(Ordering::SeqCst)
    }

    /// One sample, with retries; `None` when the stop flag ended it.
    fn measure_sample(
        &mut self,
        stage: Stage,
        row: &PlannedRow,
        prediction: Option<f64>,
    ) -> Result<Option<SampleRecord>, EngineError> {
        let started = Instant::now();
        let clock_start = self.instrument.simulated_clock_s();
        let mut attempts = 0;
        let (readback, measurement) = loop {
            attempts += 1;
            let result = self.try_sample(&row.axes, prediction);
            let reconnected = self.copy_link_notes()?;
            if result.is_err() && self.stopped() {
                return Ok(None);
            }
            match result {
                Ok(done) if !reconnected => break done,
                Ok(_) => {
                    // A new link may lead to a restarted adapter that lost the position and
                    // the light level: home, and measure the sample again from the move.
                    self.journal.log_event(
                        "redo",
                        &format!(
                            "{stage} sample {}: the link was reopened during the sample",
                            row.seq
                        ),
                    )?;
                    let error = if attempts >= self.settings.max_attempts {
                        InstrumentError::Disconnected(
                            "the link was reopened during every try".into(),
                        )
                    } else {
                        match self.recover(true) {
                            Ok(()) => continue,
                            Err(_) if self.stopped() => return Ok(None),
                            Err(e) => e,
                        }
                    };
                    return Err(EngineError::Device {
                        stage: stage.to_string(),
                        seq: row.seq,
                        attempts,
                        error,
                    });
                }
                Err(error) => {
                    self.journal.log_event(
                        "fault",
                        &format!("{stage} sample {} try {attempts}: {error}", row.seq),
                    )?;
                    let retryable = is_retryable(&error);
                    let mut error = error;
                    if retryable && attempts < self.settings.max_attempts {
                        match self.recover(matches!(error, InstrumentError::MotorFault(_))) {
                            Ok(()) => continue,
                            Err(_) if self.stopped() => return Ok(None),
                            Err(recovery) => error = recovery,
                        }
                    }
                    return Err(EngineError::Device {
                        stage: stage.to_string(),
                        seq: row.seq,
                        attempts,
                        error,
                    });
                }
            }
        };
        let wall_s = started.elapsed().as_secs_f64();
        let device_s = match (clock_start, self.instrument.simulated_clock_s()) {
            (Some(a), Some(b)) => b - a,
            _ => wall_s,
        };
        let value = self
            .calibration
            .brdf(measurement.value.rate_dn_s, cos_theta_i(row).max(1e-6));
        let now = unix_now_s();
        Ok(Some(SampleRecord {
            stage: stage.to_string(),
            seq: row.seq,
            value,
            rate_dn_s: measurement.value.rate_dn_s,
            sigma_dn_s: measurement.value.sigma_dn_s,
            lower_bound: measurement.value.saturated.iter().any(|&s| s),
            readback,
            device_s,
            wall_s,
            finished_unix_s: now,
            attempts,
            captures: measurement
                .captures
                .iter()
                .map(|c| capture_record(c, now))
                .collect(),
        }))
    }

    /// Move, then HDR capture.
    fn try_sample(
        &mut self,
        axes: &AxisPositions,
        prediction: Option<f64>,
    ) -> Result<(AxisPositions, HdrMeasurement), InstrumentError> {
        let readback = self.instrument.move_to(axes)?;
        let measurement = match &self.settings.hdr {
            HdrMode::Predicted => self.hdr.measure(&mut *self.instrument, prediction)?,
            HdrMode::Bracket {
                exposures_s,
                light_levels,
            } => self
                .hdr
                .bracket(&mut *self.instrument, exposures_s, light_levels)?,
        };
        Ok((readback, measurement))
    }

    /// Gets the device ready for another try: the light level is no longer known, and with
    /// `home` (after a motor fault or a new link) the axes go to their reference first.
    fn recover(&mut self, home: bool) -> Result<(), InstrumentError> {
        self.hdr.forget_light_level();
        if home {
            self.instrument.home()?;
            self.journal
                .log_event("recovered", "homed the axes")
                .map_err(|e| InstrumentError::Disconnected(e.to_string()))?;
        }
        Ok(())
    }

    /// Copies the link's notes into the journal; true when the link was reopened.
    fn copy_link_notes(&mut self) -> Result<bool, JournalError> {
        let Some(notes) = &self.link_notes else {
            return Ok(false);
        };
        let drained: Vec<(String, String)> = notes
            .lock()
            .map(|mut n| n.drain(..).collect())
            .unwrap_or_default();
        let mut reconnected = false;
        for (kind, message) in drained {
            reconnected |= kind == "reconnect";
            self.journal.log_event(&kind, &message)?;
        }
        Ok(reconnected)
    }
}

/// A capture as the journal keeps it: without pixels, with whether the merge used it.
fn capture_record(capture: &Capture, unix_s: f64) -> CaptureRecord {
    CaptureRecord {
        exposure_s: capture.exposure_s,
        light_level: capture.light_level,
        mean_raw: capture.mean_raw,
        saturated_fraction: capture.saturated_fraction,
        pixel_count: capture.pixel_count,
        used: capture.light_level > 0.0 && capture.saturated_fraction.contains(&0.0),
        unix_s,
    }
}
