//! Ctrl-C: the library's stop flag raised by the user, and the exit code of a stopped run.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};

/// The exit code of a run the user stopped.
pub(crate) const INTERRUPTED_EXIT: u8 = 130;

/// The process's stop flag, raised by Ctrl-C (or SIGTERM): the first press lets the sample
/// in progress finish and the run stop cleanly and resumably (a remote device's waits end at
/// once); a second press ends the process at once (the journal is still consistent: the
/// sample in progress is lost; an adapter ends with the process).
pub(crate) fn stop_on_ctrl_c() -> Result<Arc<AtomicBool>, ctrlc::Error> {
    static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    if let Some(flag) = FLAG.get() {
        return Ok(flag.clone());
    }
    let flag = Arc::new(AtomicBool::new(false));
    let handler_flag = flag.clone();
    ctrlc::set_handler(move || {
        if handler_flag.swap(true, Ordering::SeqCst) {
            eprintln!("\nstopping now; the sample in progress is lost, the journal is intact");
            std::process::exit(i32::from(INTERRUPTED_EXIT));
        }
        eprintln!("\nfinishing the sample in progress, then stopping (Ctrl-C again to stop now)");
    })?;
    Ok(FLAG.get_or_init(|| flag).clone())
}

/// A run the user stopped: `main` prints it as one line and exits with [`INTERRUPTED_EXIT`].
#[derive(Debug)]
pub(crate) struct Interrupted(pub(crate) String);

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "interrupted: {}", self.0)
    }
}

impl std::error::Error for Interrupted {}

/// An error that came once `stop` was raised is the stop's doing (a wait cut short): it is
/// reported as [`Interrupted`], other errors as they are.
pub(crate) fn blame_stop(error: anyhow::Error, stop: &AtomicBool) -> anyhow::Error {
    if stop.load(Ordering::SeqCst) && !error.is::<Interrupted>() {
        Interrupted(format!(
            "{error:#}; what was measured before is kept: run the same command to resume"
        ))
        .into()
    } else {
        error
    }
}
