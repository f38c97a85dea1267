//! Long calls off the GIL, interruptible with Ctrl-C.
//!
//! The work runs on a thread of its own while the calling thread waits without the GIL and
//! asks Python every [`POLL`] whether a signal arrived (`Python::check_signals`). On
//! Ctrl-C the stop flag is raised: work that watches it (a simulated measurement stops after
//! its current sample, the journal resumable; the accuracy harness between materials) ends
//! early and the call raises `KeyboardInterrupt` once it has. Work that cannot watch a flag
//! is left to finish on its thread and its result is dropped, so the call returns at once.

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{channel, RecvTimeoutError};
use std::sync::Arc;
use std::time::Duration;

/// How often the waiting thread looks for a signal.
const POLL: Duration = Duration::from_millis(50);

/// Whether the work watches the stop flag.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Stop {
    /// The work ends early when the flag is raised: wait for it.
    Cooperative,
    /// The work cannot stop: return at once and drop its result.
    Abandon,
}

/// Runs `work(stop_flag)` on its own thread, without the GIL, until it returns or Ctrl-C.
pub(crate) fn run<T: Send + 'static>(
    py: Python<'_>,
    stop: Stop,
    work: impl FnOnce(Arc<AtomicBool>) -> T + Send + 'static,
) -> PyResult<T> {
    let flag = Arc::new(AtomicBool::new(false));
    let (sender, mut receiver) = channel();
    let worker_flag = flag.clone();
    std::thread::spawn(move || {
        // The receiver is gone only when the call was abandoned.
        let _ = sender.send(work(worker_flag));
    });
    let mut interrupted: Option<PyErr> = None;
    loop {
        let (received, back) = py.detach(move || (receiver.recv_timeout(POLL), receiver));
        receiver = back;
        match received {
            Ok(value) => {
                return match interrupted {
                    Some(error) => Err(error),
                    None => Ok(value),
                }
            }
            Err(RecvTimeoutError::Disconnected) => {
                return Err(PyRuntimeError::new_err(
                    "specula: the worker thread panicked",
                ))
            }
            Err(RecvTimeoutError::Timeout) => {
                if interrupted.is_none() {
                    if let Err(error) = py.check_signals() {
                        flag.store(true, Ordering::SeqCst);
                        if stop == Stop::Abandon {
                            return Err(error);
                        }
                        interrupted = Some(error);
                    }
                }
            }
        }
    }
}
