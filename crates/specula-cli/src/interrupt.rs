//! Ctrl-C and SIGTERM: the library's stop flag raised by the user or by a process manager,
//! and the exit code of a stopped run (128 plus the signal's number: 130 for SIGINT, 143 for
//! SIGTERM, 129 for SIGHUP).

use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
use signal_hook::iterator::Signals;
use std::sync::atomic::{AtomicBool, AtomicU8, Ordering};
use std::sync::{Arc, OnceLock};

/// The exit code of a run stopped by Ctrl-C (SIGINT).
pub(crate) const INTERRUPTED_EXIT: u8 = 130;

/// The exit code of the first stopping signal received; Ctrl-C's until one arrives.
static STOP_EXIT: AtomicU8 = AtomicU8::new(INTERRUPTED_EXIT);

/// The exit code of a stopped run: 128 plus the number of the signal that stopped it.
pub(crate) fn stop_exit_code() -> u8 {
    STOP_EXIT.load(Ordering::SeqCst)
}

/// The process's stop flag, raised by Ctrl-C, SIGTERM or SIGHUP: the first signal lets the
/// sample in progress finish and the run stop cleanly and resumably (a remote device's waits
/// end at once); a second one ends the process at once (the journal is still consistent: the
/// sample in progress is lost; an adapter ends with the process).
pub(crate) fn stop_on_ctrl_c() -> std::io::Result<Arc<AtomicBool>> {
    static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    if let Some(flag) = FLAG.get() {
        return Ok(flag.clone());
    }
    let flag = Arc::new(AtomicBool::new(false));
    let mut signals = Signals::new([SIGINT, SIGTERM, SIGHUP])?;
    let handler_flag = flag.clone();
    std::thread::spawn(move || {
        for signal in signals.forever() {
            if handler_flag.load(Ordering::SeqCst) {
                eprintln!("\nstopping now; the sample in progress is lost, the journal is intact");
                std::process::exit(i32::from(stop_exit_code()));
            }
            let code = u8::try_from(128 + signal).unwrap_or(u8::MAX);
            STOP_EXIT.store(code, Ordering::SeqCst);
            handler_flag.store(true, Ordering::SeqCst);
            eprintln!(
                "\nfinishing the step in progress (a sample, a tile, a material), then stopping (Ctrl-C again to stop now)"
            );
        }
    });
    Ok(FLAG.get_or_init(|| flag).clone())
}

/// A run the user stopped: `main` prints it as one line and exits with [`stop_exit_code`].
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

/// As [`blame_stop`], for work that keeps nothing to resume (a plan, a render, an
/// evaluation): once `stop` was raised its error is reported as [`Interrupted`].
pub(crate) fn blame_stop_unresumable(error: anyhow::Error, stop: &AtomicBool) -> anyhow::Error {
    if stop.load(Ordering::SeqCst) && !error.is::<Interrupted>() {
        Interrupted(format!("{error:#}")).into()
    } else {
        error
    }
}
