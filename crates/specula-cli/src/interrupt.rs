//! Ctrl-C: the library's stop flag raised by the user, and the exit code of a forced stop.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};

/// The process's stop flag, raised by Ctrl-C (or SIGTERM): the first press lets the sample
/// in progress finish and the run stop cleanly and resumably; a second press ends the
/// process at once (the journal is still consistent: the sample in progress is lost).
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
            std::process::exit(130);
        }
        eprintln!("\nfinishing the sample in progress, then stopping (Ctrl-C again to stop now)");
    })?;
    Ok(FLAG.get_or_init(|| flag).clone())
}
