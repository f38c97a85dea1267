//! Pacing a simulated device in real time: `Paced` sleeps after each call for the device
//! time the call took, divided by a speed-up factor, so that a rehearsal (or a test that
//! interrupts a run) sees a measurement unfold as it would on the device, only faster.

use specula_acquisition::instrument::{Capture, Instrument, InstrumentError, InstrumentInfo};
use specula_acquisition::kinematics::AxisPositions;
use std::time::Duration;

/// An instrument slowed to `1 / speedup` of its simulated clock.
pub struct Paced<I: Instrument> {
    inner: I,
    speedup: f64,
}

impl<I: Instrument> Paced<I> {
    /// `speedup` > 0: 1 is real time, 1000 a thousand times faster.
    pub fn new(inner: I, speedup: f64) -> Self {
        Self { inner, speedup }
    }

    fn paced<T>(&mut self, call: impl FnOnce(&mut I) -> T) -> T {
        let before = self.inner.simulated_clock_s();
        let result = call(&mut self.inner);
        if let (Some(a), Some(b)) = (before, self.inner.simulated_clock_s()) {
            let wait_s = (b - a) / self.speedup;
            if wait_s.is_finite() && wait_s > 0.0 {
                std::thread::sleep(Duration::from_secs_f64(wait_s.min(3600.0)));
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
}
