//! Pacing a simulated device in real time: `Paced` sleeps after each call for the device
//! time the call took, divided by a speed-up factor, so that a rehearsal (or a test that
//! interrupts a run) sees a measurement unfold as it would on the device, only faster. With a
//! stop flag ([`Paced::with_stop`]) a raised flag cuts the waits short, so Ctrl-C or SIGTERM
//! is acted on within [`STOP_POLL`] however slow the pacing (the simulated clock, and so
//! the result, does not depend on the waits).

use specula_acquisition::instrument::{
    Capture, Instrument, InstrumentError, InstrumentInfo, MountOutcome, MountTarget,
};
use specula_acquisition::kinematics::AxisPositions;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// How often a wait looks at the stop flag.
pub const STOP_POLL: Duration = Duration::from_millis(50);

/// An instrument slowed to `1 / speedup` of its simulated clock.
pub struct Paced<I: Instrument> {
    inner: I,
    speedup: f64,
    stop: Option<Arc<AtomicBool>>,
}

impl<I: Instrument> Paced<I> {
    /// `speedup` > 0: 1 is real time, 1000 a thousand times faster.
    pub fn new(inner: I, speedup: f64) -> Self {
        Self {
            inner,
            speedup,
            stop: None,
        }
    }

    /// Ends every wait early once `stop` is raised.
    pub fn with_stop(mut self, stop: Arc<AtomicBool>) -> Self {
        self.stop = Some(stop);
        self
    }

    /// Sleeps `wait`, in slices of [`STOP_POLL`] while a stop flag may cut it short.
    fn wait(&self, wait: Duration) {
        let Some(stop) = &self.stop else {
            std::thread::sleep(wait);
            return;
        };
        let end = Instant::now() + wait;
        while !stop.load(Ordering::SeqCst) {
            let left = end.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return;
            }
            std::thread::sleep(left.min(STOP_POLL));
        }
    }

    fn paced<T>(&mut self, call: impl FnOnce(&mut I) -> T) -> T {
        let before = self.inner.simulated_clock_s();
        let result = call(&mut self.inner);
        if let (Some(a), Some(b)) = (before, self.inner.simulated_clock_s()) {
            let wait_s = (b - a) / self.speedup;
            if wait_s.is_finite() && wait_s > 0.0 {
                self.wait(Duration::from_secs_f64(wait_s.min(3600.0)));
            }
        }
        result
    }
}

impl<I: Instrument> Instrument for Paced<I> {
    fn home(&mut self) -> Result<AxisPositions, InstrumentError> {
        self.paced(|i| i.home())
    }

    fn move_to(&mut self, target: &AxisPositions) -> Result<AxisPositions, InstrumentError> {
        self.paced(|i| i.move_to(target))
    }

    fn set_light(&mut self, level: f64) -> Result<(), InstrumentError> {
        self.paced(|i| i.set_light(level))
    }

    fn capture(&mut self, exposure_s: f64, with_pixels: bool) -> Result<Capture, InstrumentError> {
        self.paced(|i| i.capture(exposure_s, with_pixels))
    }

    fn info(&mut self) -> Result<InstrumentInfo, InstrumentError> {
        self.inner.info()
    }

    fn simulated_clock_s(&self) -> Option<f64> {
        self.inner.simulated_clock_s()
    }

    fn mount(&mut self, target: &MountTarget) -> Result<MountOutcome, InstrumentError> {
        self.inner.mount(target)
    }
}
