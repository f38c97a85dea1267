//! What the workflow tells its caller as it goes ([`Observer`]): steps, stages and samples
//! (the CLI draws progress bars from them).

use crate::engine::{Progress, StageOutcome};
use crate::journal::Stage;

/// Hears what the workflow is doing (the CLI draws progress bars).
pub trait Observer {
    /// A step without samples of its own ("calibrating", "alignment check: ...").
    fn step(&mut self, message: &str);
    /// A stage of samples starts, `done` of `planned` already in the journal.
    fn stage_started(&mut self, stage: Stage, planned: usize, done: usize);
    /// A sample of the current stage is in the journal.
    fn sample(&mut self, progress: &Progress);
    /// The current stage ends, complete or stopped.
    fn stage_finished(&mut self, stage: Stage, outcome: &StageOutcome);
}

/// An observer that ignores everything.
pub struct Quiet;

impl Observer for Quiet {
    fn step(&mut self, _: &str) {}
    fn stage_started(&mut self, _: Stage, _: usize, _: usize) {}
    fn sample(&mut self, _: &Progress) {}
    fn stage_finished(&mut self, _: Stage, _: &StageOutcome) {}
}
