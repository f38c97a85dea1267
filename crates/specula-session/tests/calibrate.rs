//! `calibrate_device`: each target mounted by the device when it can, else by the operator,
//! in the documented order, with the same result either way.

use specula_acquisition::calibration::colorchecker::PATCHES;
use specula_acquisition::calibration::CalibrationOptions;
use specula_acquisition::device::Device;
use specula_acquisition::instrument::{
    Capture, Instrument, InstrumentError, InstrumentInfo, MountOutcome, MountTarget,
};
use specula_acquisition::kinematics::AxisPositions;
use specula_session::calibrate::calibrate_device;
use specula_session::ideal::simulated_instrument;
use std::sync::{Arc, Mutex};

/// The simulated device shared between the device's methods and the operator's hands.
type Shared = Arc<Mutex<Box<dyn Instrument>>>;

/// A device that cannot mount targets itself (an adapter without `mount`).
struct NoChanger(Shared);

impl NoChanger {
    fn with<T>(&self, f: impl FnOnce(&mut dyn Instrument) -> T) -> T {
        f(self.0.lock().unwrap().as_mut())
    }
}

impl Instrument for NoChanger {
    fn home(&mut self) -> Result<AxisPositions, InstrumentError> {
        self.with(|i| i.home())
    }
    fn move_to(&mut self, target: &AxisPositions) -> Result<AxisPositions, InstrumentError> {
        self.with(|i| i.move_to(target))
    }
    fn set_light(&mut self, level: f64) -> Result<(), InstrumentError> {
        self.with(|i| i.set_light(level))
    }
    fn capture(&mut self, exposure_s: f64, with_pixels: bool) -> Result<Capture, InstrumentError> {
        self.with(|i| i.capture(exposure_s, with_pixels))
    }
    fn info(&mut self) -> Result<InstrumentInfo, InstrumentError> {
        self.with(|i| i.info())
    }
}

fn simulator() -> Box<dyn Instrument> {
    let truth = Arc::new(specula_core::materials::preset("silver-925").unwrap());
    simulated_instrument(Device::utia(), truth, 4, false)
}

#[test]
fn without_a_changer_the_operator_mounts_every_target_in_order_to_the_same_result() {
    let device = Device::utia();
    let options = CalibrationOptions::default();
    let mut asked_of_operator = 0;
    let by_device = calibrate_device(
        simulator().as_mut(),
        &mut |_| {
            asked_of_operator += 1;
            Ok(())
        },
        &device,
        &options,
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(
        asked_of_operator, 0,
        "the simulator mounts each target itself"
    );

    let shared: Shared = Arc::new(Mutex::new(simulator()));
    let hands = shared.clone();
    let mut asked = Vec::new();
    let by_operator = calibrate_device(
        &mut NoChanger(shared),
        &mut |target: &MountTarget| {
            asked.push(target.clone());
            let outcome = hands.lock().unwrap().mount(target)?;
            assert_eq!(outcome, MountOutcome::Mounted);
            Ok(())
        },
        &device,
        &options,
        &mut |_| {},
    )
    .unwrap();

    let mut expected = vec![MountTarget::White];
    expected.extend(PATCHES.iter().map(|p| MountTarget::Colorchecker {
        patch: p.name.to_string(),
    }));
    expected.extend([MountTarget::Mirror, MountTarget::Sample]);
    assert_eq!(asked, expected);
    assert_eq!(by_operator, by_device);
    assert_eq!(by_operator.checks.len(), 6, "{:?}", by_operator.checks);
}
