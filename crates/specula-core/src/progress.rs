//! How long work shows its progress and is stopped, the same in every library crate: an
//! entry point that may run for long takes a stop flag (`&AtomicBool`, raised by Ctrl-C in
//! the CLI and by KeyboardInterrupt in Python) and a [`Progress`] to report to, and ends
//! with [`Stopped`] when the flag was raised before it finished.

use std::sync::atomic::{AtomicBool, Ordering};

/// Where long work shows its progress (a terminal bar in the CLI, nothing in Python).
/// Worker threads report through it, hence `Sync`.
pub trait Progress: Sync {
    /// A step starts: `label`, over `total` units when known (else a spinner).
    fn start(&self, label: &str, total: Option<u64>);
    /// `done` units of the current step are done.
    fn set(&self, done: u64);
    /// The current step is finished.
    fn finish(&self);
}

/// No progress shown (tests, and callers without a terminal).
pub struct NoProgress;

impl Progress for NoProgress {
    fn start(&self, _label: &str, _total: Option<u64>) {}
    fn set(&self, _done: u64) {}
    fn finish(&self) {}
}

/// Work that ended early because its stop flag was raised: how far it got.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("stopped: {done} of {total} {what} done")]
pub struct Stopped {
    /// Units finished before the stop.
    pub done: u64,
    /// Units asked for.
    pub total: u64,
    /// What the units are (`materials`, `pictures`).
    pub what: &'static str,
}

/// Whether `stop` has been raised.
pub fn is_raised(stop: &AtomicBool) -> bool {
    stop.load(Ordering::SeqCst)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stop_says_how_far_the_work_got() {
        let stop = AtomicBool::new(false);
        assert!(!is_raised(&stop));
        stop.store(true, Ordering::SeqCst);
        assert!(is_raised(&stop));
        let stopped = Stopped {
            done: 2,
            total: 5,
            what: "materials",
        };
        assert_eq!(stopped.to_string(), "stopped: 2 of 5 materials done");
    }
}
