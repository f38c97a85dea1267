use super::sample::Tilt;
use super::*;
use specula_core::materials::preset;
use specula_core::{Brdf, Rgb};
use std::sync::Arc;

/// A constant BRDF (Lambertian, albedo pi * value).
struct Constant(Rgb);

impl Brdf for Constant {
    fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
        Some(if wi.z > 0.0 && wo.z > 0.0 {
            self.0
        } else {
            Rgb::ZERO
        })
    }
    fn name(&self) -> String {
        "constant".into()
    }
}

fn silver(seed: u64) -> Simulator {
    let device = Device::utia();
    let config = SimulatorConfig::new(seed, &device);
    let brdf = Arc::new(preset("silver-925").unwrap());
    Simulator::new(
        device,
        MountedSample::new("silver", brdf, Tilt::default()),
        config,
    )
}

fn positions() -> Vec<AxisPositions> {
    (0..12)
        .map(|k| {
            let k = k as f64;
            AxisPositions::from_degrees(10.0 * k, 20.0 + 2.0 * k, 100.0 + 3.0 * k, 15.0 + 1.5 * k)
        })
        .collect()
}

fn capture_at(sim: &mut Simulator, axes: &AxisPositions, exposure_s: f64) -> Capture {
    sim.move_to(axes).unwrap();
    sim.capture(exposure_s, true).unwrap()
}

#[test]
fn same_seed_same_captures_in_any_order_and_after_a_restart() {
    let exposure = 2e-3;
    let mut first = silver(11);
    let forward: Vec<Capture> = positions()
        .iter()
        .map(|a| capture_at(&mut first, a, exposure))
        .collect();

    // A fresh simulator (a restart), the positions in a shuffled order.
    let mut second = silver(11);
    let order = [7, 2, 11, 0, 5, 9, 1, 4, 10, 3, 8, 6];
    for &i in &order {
        let capture = capture_at(&mut second, &positions()[i], exposure);
        assert!(
            capture == forward[i],
            "position {i}: {:?}",
            capture.mean_raw
        );
    }

    // Another seed is another device and other noise.
    let mut other = silver(12);
    let capture = capture_at(&mut other, &positions()[3], exposure);
    assert!(capture != forward[3]);
    // Not saturated, not dark: the noise is really there.
    assert!(forward
        .iter()
        .all(|c| c.saturated_fraction == [0.0; 3] && c.mean_raw[1] > 100.0));
}

#[test]
fn a_repeated_capture_has_fresh_noise_until_the_device_moves() {
    let mut sim = silver(5);
    let axes = positions()[4];
    let a = capture_at(&mut sim, &axes, 1e-3);
    let b = sim.capture(1e-3, true).unwrap();
    assert!(a.pixels != b.pixels, "a second frame is another frame");
    sim.move_to(&positions()[5]).unwrap();
    let again = capture_at(&mut sim, &axes, 1e-3);
    assert!(a == again, "back at the same place, the same first frame");
}

#[test]
fn constant_brdf_gives_its_value_times_the_cosine() {
    let device = Device::utia();
    let value = Rgb::new(0.2, 0.1, 0.05);
    let sample = MountedSample::new("const", Arc::new(Constant(value)), Tilt::default());
    let mut config = SimulatorConfig::new(1, &device);
    config.positioning.sigma_deg = 0.0;
    let sim = Simulator::new(device, sample, config);
    let axes = AxisPositions::from_degrees(0.0, 0.0, 180.0, 45.0);
    let s = sim.scene_radiance(&axes);
    // The disk average of cos(theta_i) differs from cos(45 deg) by the disk's curvature,
    // below 1e-3 relative for a 1.8 deg half-angle.
    let expected = value * 45f64.to_radians().cos();
    assert!(
        ((s - expected) / expected).abs().max_element() < 1e-3,
        "{s} vs {expected}"
    );
    let rate = sim.expected_rate_dn_s(&axes);
    let camera = &sim.config().camera;
    assert_eq!(rate, camera.signal_rate_dn_s(s));
}

#[test]
fn clock_counts_moves_light_changes_and_frames() {
    let mut sim = silver(2);
    let device = Device::utia();
    let time = TimeModel::from_device(&device);
    assert_eq!(sim.simulated_clock_s(), Some(0.0));
    let target = positions()[6];
    sim.move_to(&target).unwrap();
    let moved = time.transition_s(&device.park_axes(), &target);
    assert!((sim.simulated_clock_s().unwrap() - moved).abs() < 1e-12);
    sim.set_light(0.1).unwrap();
    sim.set_light(0.1).unwrap(); // no change, no wait
    sim.capture(0.5, false).unwrap();
    let expected = moved + device.capture.light_change_s + 0.5 + device.capture.readout_s;
    assert!((sim.simulated_clock_s().unwrap() - expected).abs() < 1e-12);
    assert_eq!(sim.capture_count(), 1);
}

#[test]
fn out_of_range_requests_are_typed_errors_and_faults_can_be_scheduled() {
    let mut sim = silver(3);
    let beyond = AxisPositions::from_degrees(0.0, 80.0, 0.0, 30.0);
    match sim.move_to(&beyond) {
        Err(InstrumentError::Limit(message)) => assert!(message.contains("camera"), "{message}"),
        other => panic!("{other:?}"),
    }
    assert!(matches!(sim.set_light(1.5), Err(InstrumentError::Limit(_))));
    assert!(matches!(
        sim.capture(100.0, false),
        Err(InstrumentError::CameraFault(_))
    ));

    sim.schedule_fault(2, InstrumentError::Disconnected("cable".into()));
    assert!(sim.info().is_ok());
    assert_eq!(
        sim.capture(1e-3, false),
        Err(InstrumentError::Disconnected("cable".into()))
    );
    assert!(sim.capture(1e-3, false).is_ok(), "a fault happens once");
}

#[test]
fn dark_frames_with_the_light_off() {
    let mut sim = silver(4);
    sim.move_to(&AxisPositions::from_degrees(0.0, 30.0, 180.0, 30.0))
        .unwrap();
    sim.set_light(0.0).unwrap();
    let dark = sim.capture(1e-3, false).unwrap();
    let black = sim.config().camera.black_level_dn;
    for c in 0..3 {
        assert!(
            (dark.mean_raw[c] - black).abs() < 0.2,
            "{:?}",
            dark.mean_raw
        );
    }
}

#[test]
fn lens_flare_adds_a_reddish_spot_that_the_other_camera_side_avoids() {
    let device = Device::utia();
    let mut config = SimulatorConfig::new(9, &device);
    config.flare = Some(LensFlare::default());
    let brdf = Arc::new(Constant(Rgb::splat(0.01)));
    let sample = MountedSample::new("grey", brdf, Tilt::default());
    let mut sim = Simulator::new(device.clone(), sample, config);
    // A mirror configuration in the x-z plane, and the same pair of directions with the
    // camera on the other side of the zenith and the sample turned by 180 deg.
    let wi = specula_core::Spherical::from_degrees(30.0, 180.0).to_vector();
    let wo = specula_core::Spherical::from_degrees(30.0, 0.0).to_vector();
    let all = crate::kinematics::solutions(&device, wi, wo);
    let flared: Vec<bool> = all.iter().map(|a| sim.ghost(a, 1.0).is_some()).collect();
    assert!(
        flared.iter().any(|&f| f) && flared.iter().any(|&f| !f),
        "{flared:?}"
    );
    let with = all[flared.iter().position(|&f| f).unwrap()];
    let without = all[flared.iter().position(|&f| !f).unwrap()];
    let a = capture_at(&mut sim, &with, 0.01);
    let b = capture_at(&mut sim, &without, 0.01);
    let black = sim.config().camera.black_level_dn;
    let excess: Vec<f64> = (0..3)
        .map(|c| (a.mean_raw[c] - black) / (b.mean_raw[c] - black) - 1.0)
        .collect();
    assert!(
        excess[0] > excess[1] && excess[1] > excess[2] && excess[2] >= -0.01,
        "{excess:?}"
    );
    assert!(excess[0] > 0.2, "{excess:?}");
}

#[test]
fn the_checks_setup_captures_with_the_simulators_own_sensor_model() {
    let brdf = Arc::new(preset("silver-925").unwrap());
    let sample = MountedSample::new("silver", brdf, Tilt::default());
    let flare = LensFlare {
        strength_sr: 0.2,
        ..LensFlare::default()
    };
    let (mut sim, hdr) =
        Simulator::with_hdr(Device::utia(), sample, 7, Some(flare.clone())).unwrap();
    assert_eq!(sim.config().seed, 7);
    assert_eq!(sim.config().flare, Some(flare));
    assert_eq!(hdr.noise, sim.config().camera.noise_model());
    assert_eq!(hdr.settings, HdrSettings::for_device(&sim.info().unwrap()));
    assert_eq!(hdr.stats.samples, 0);
}
