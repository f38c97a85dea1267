//! Progress bars for long work, drawn on stderr and hidden when stderr is not a terminal.

use indicatif::{ProgressBar, ProgressStyle};

/// A progress bar over `total` steps with a label, an ETA and a step count.
pub(crate) fn bar(total: u64, label: &str) -> ProgressBar {
    let bar = ProgressBar::new(total);
    bar.set_style(
        ProgressStyle::with_template("{msg:>12} [{bar:40}] {pos}/{len} ({eta} left)")
            .expect("static template is valid")
            .progress_chars("=> "),
    );
    bar.set_message(label.to_string());
    bar
}

/// A spinner for work of unknown length.
pub(crate) fn spinner(label: &str) -> ProgressBar {
    let spinner = ProgressBar::new_spinner();
    spinner.set_message(label.to_string());
    spinner.enable_steady_tick(std::time::Duration::from_millis(120));
    spinner
}

/// The report layer's progress on the terminal: a bar for a step of known length, else a
/// spinner.
#[derive(Default)]
pub(crate) struct Terminal {
    current: std::sync::Mutex<Option<ProgressBar>>,
}

impl specula_core::progress::Progress for Terminal {
    fn start(&self, label: &str, total: Option<u64>) {
        let shown = match total {
            Some(total) => bar(total, label),
            None => spinner(label),
        };
        if let Ok(mut current) = self.current.lock() {
            *current = Some(shown);
        }
    }

    fn set(&self, done: u64) {
        if let Ok(current) = self.current.lock() {
            if let Some(bar) = current.as_ref() {
                bar.set_position(done);
            }
        }
    }

    fn finish(&self) {
        if let Ok(mut current) = self.current.lock() {
            if let Some(bar) = current.take() {
                bar.finish_and_clear();
            }
        }
    }
}

/// The environment variable that sets the seconds between progress lines without a
/// terminal ([`LogLines`]); 60 by default.
pub(crate) const LOG_INTERVAL_VAR: &str = "SPECULA_PROGRESS_INTERVAL_S";

/// The default seconds between progress lines without a terminal.
const LOG_INTERVAL_S: f64 = 60.0;

/// Where a long stage is, for its progress line.
#[derive(Debug, Clone, Default)]
pub(crate) struct StageState {
    /// The stage's name.
    pub(crate) stage: String,
    /// Samples done, resumed ones included.
    pub(crate) done: usize,
    /// Samples planned.
    pub(crate) planned: usize,
    /// The device time left, seconds, once known.
    pub(crate) eta_s: Option<f64>,
}

impl StageState {
    /// `progress: main 120/3400 samples, 2h 10m left (device time)`.
    fn line(&self) -> String {
        let eta = self
            .eta_s
            .map_or("time left not yet known".to_string(), |s| {
                format!(
                    "{} left (device time)",
                    specula_core::shown::duration_text(s)
                )
            });
        format!(
            "progress: {} {}/{} samples, {eta}",
            self.stage, self.done, self.planned
        )
    }
}

/// Progress as lines on stderr when it is not a terminal (a log file, a service's journal):
/// the bars draw nothing there, so a thread prints the stage, the samples done of those
/// planned and the time left at least every interval of wall time ([`LOG_INTERVAL_VAR`]),
/// however long one sample takes. Stops when dropped.
pub(crate) struct LogLines {
    state: std::sync::Arc<std::sync::Mutex<StageState>>,
    stop: std::sync::Arc<std::sync::atomic::AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl LogLines {
    /// Lines for `state` every interval when stderr is not a terminal; `None` on a
    /// terminal.
    pub(crate) fn start(state: StageState) -> Option<Self> {
        use std::io::IsTerminal;
        if std::io::stderr().is_terminal() {
            return None;
        }
        let interval_s = std::env::var(LOG_INTERVAL_VAR)
            .ok()
            .and_then(|v| v.parse::<f64>().ok())
            .filter(|s| s.is_finite() && *s > 0.0)
            .unwrap_or(LOG_INTERVAL_S);
        let interval = std::time::Duration::from_secs_f64(interval_s);
        eprintln!("{}", state.line());
        let state = std::sync::Arc::new(std::sync::Mutex::new(state));
        let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let (shared, stopped) = (state.clone(), stop.clone());
        let thread = std::thread::spawn(move || {
            let poll = std::time::Duration::from_millis(50).min(interval);
            let mut last = std::time::Instant::now();
            while !stopped.load(std::sync::atomic::Ordering::SeqCst) {
                std::thread::sleep(poll);
                if last.elapsed() >= interval {
                    last = std::time::Instant::now();
                    if let Ok(state) = shared.lock() {
                        eprintln!("{}", state.line());
                    }
                }
            }
        });
        Some(Self {
            state,
            stop,
            thread: Some(thread),
        })
    }

    /// Updates the samples done and the time left.
    pub(crate) fn update(&self, done: usize, eta_s: f64) {
        if let Ok(mut state) = self.state.lock() {
            state.done = done;
            state.eta_s = Some(eta_s);
        }
    }
}

impl Drop for LogLines {
    fn drop(&mut self) {
        self.stop.store(true, std::sync::atomic::Ordering::SeqCst);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}
