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

impl specula_report::Progress for Terminal {
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
