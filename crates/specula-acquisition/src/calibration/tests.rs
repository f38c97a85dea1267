use super::*;
use crate::device::Device;
use crate::simulator::sample::{MountedSample, Tilt};
use crate::simulator::{Simulator, SimulatorConfig};
use std::sync::Arc;

fn simulator(seed: u64) -> Simulator {
    let device = Device::utia();
    let config = SimulatorConfig::new(seed, &device);
    let white = Arc::new(DiffuseTarget::white(0.99));
    Simulator::new(
        device,
        MountedSample::new("white", white, Tilt::default()),
        config,
    )
}

#[test]
fn least_squares_recovers_an_exact_matrix() {
    let truth = DMat3::from_cols_array(&[1.2, -0.1, 0.05, -0.2, 1.3, -0.15, 0.0, -0.2, 1.1]);
    let camera: Vec<DVec3> = colorchecker::PATCHES
        .iter()
        .map(|p| p.reflectance())
        .collect();
    let reference: Vec<DVec3> = camera.iter().map(|u| truth * *u).collect();
    let fitted = fit_colour_matrix(&camera, &reference).unwrap();
    assert!((fitted - truth)
        .to_cols_array()
        .iter()
        .all(|d| d.abs() < 1e-12));

    let greys: Vec<DVec3> = (1..6).map(|k| DVec3::splat(k as f64 * 0.1)).collect();
    let err = fit_colour_matrix(&greys, &greys).unwrap_err().to_string();
    assert!(err.contains("three dimensions"), "{err}");
}

#[test]
fn calibration_recovers_the_simulated_camera() {
    let mut sim = simulator(21);
    let camera = sim.config().camera.clone();
    let options = CalibrationOptions::default();
    let cal = calibrate(&mut sim, mount_by_device, &options).unwrap();

    // The noise model (EMVA 1288 from dark frames and the photon transfer curve).
    let truth = camera.noise_model();
    let noise = cal.noise;
    assert!(
        (noise.black_level_dn - truth.black_level_dn).abs() < 0.05,
        "{noise:?}"
    );
    assert!(
        (noise.gain_dn_per_e / truth.gain_dn_per_e - 1.0).abs() < 0.03,
        "{noise:?}"
    );
    assert!(
        (noise.read_noise_dn / truth.read_noise_dn - 1.0).abs() < 0.05,
        "{noise:?}"
    );
    assert!(
        (noise.dark_current_dn_s / truth.dark_current_dn_s - 1.0).abs() < 0.15,
        "{noise:?}"
    );

    // The known gain: responsivity times conversion gain, per channel.
    for c in 0..3 {
        let known = camera.responsivity_e_s[c] * camera.gain_dn_per_e;
        let error = cal.gain_dn_s_per_sr[c] / known - 1.0;
        assert!(error.abs() < 0.003, "channel {c}: gain off by {error}");
    }

    // The known crosstalk: the colour matrix is its inverse.
    let crosstalk = DMat3::from_cols_array_2d(&camera.crosstalk).transpose();
    let recovered = cal.matrix().inverse();
    let worst = (recovered - crosstalk)
        .to_cols_array()
        .iter()
        .fold(0.0f64, |m, d| m.max(d.abs()));
    assert!(
        worst < 0.01,
        "crosstalk off by {worst}: {recovered} vs {crosstalk}"
    );
    assert!(cal.colour_rms_error < 0.005, "{}", cal.colour_rms_error);

    // A coloured diffuse sample at another geometry comes out in 1/sr.
    let target = DiffuseTarget {
        name: "test tile".into(),
        reflectance: Rgb::new(0.6, 0.3, 0.1),
    };
    sim.mount_sample(MountedSample::new(
        target.name.clone(),
        Arc::new(target.clone()),
        Tilt::default(),
    ));
    let axes = AxisPositions::from_degrees(30.0, 20.0, 150.0, 60.0);
    sim.move_to(&axes).unwrap();
    let (wi, _) = sim.actual_axes(&axes).directions();
    let mut hdr = HdrCapturer::new(HdrSettings::for_device(&sim.info().unwrap()), cal.noise);
    let value = hdr.measure(&mut sim, None).unwrap().value;
    let (brdf, sigma) = cal.brdf_with_sigma(&value, wi.z);
    let relative = cal.relative_sigma(value.rate_dn_s, value.sigma_dn_s);
    for c in 0..3 {
        let expected = sigma[c] / brdf[c];
        assert!(
            (relative[c] / expected - 1.0).abs() < 1e-12,
            "{relative} {sigma} {brdf}"
        );
    }
    let expected = target.reflectance / PI;
    let relative = ((brdf - expected) / expected).abs().max_element();
    assert!(relative < 0.01, "{brdf} vs {expected}");
    assert!(
        sigma.max_element() < 0.002 * expected.max_element(),
        "{sigma}"
    );
    let predicted = cal.predicted_rate_dn_s(expected, wi.z);
    assert!((predicted / value.brightest_rate_dn_s() - 1.0).abs() < 0.01);
}

#[test]
fn calibration_file_round_trip_and_errors() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cal.toml");
    let cal = Calibration {
        device: "sim".into(),
        white_reflectance: 0.99,
        white_certificate: Some(white::WhiteCertificate {
            reflectance: [0.99, 0.985, 0.98],
            uncertainty: [0.004, 0.004, 0.005],
        }),
        light_elevation_deg: 45.0,
        gain_dn_s_per_sr: [1e6, 2e6, 3e6],
        colour_matrix: [[1.1, -0.1, 0.0], [0.0, 1.0, 0.0], [0.0, -0.05, 1.05]],
        colour_rms_error: 0.001,
        colour_reference: "test".into(),
        noise: crate::simulator::camera::CameraModel::default().noise_model(),
        response: None,
    };
    cal.save(&path).unwrap();
    assert_eq!(Calibration::load(&path).unwrap(), cal);
    // A rate converts to 1/sr and back.
    let brdf = cal.brdf([2e5, 3e5, 1e5], 0.8);
    let camera = cal.matrix().inverse() * (brdf * 0.8) * DVec3::from(cal.gain_dn_s_per_sr);
    assert!((camera - DVec3::new(2e5, 3e5, 1e5)).abs().max_element() < 1e-6);
    // A value's relative noise goes through the colour matrix, channel by channel: with
    // every camera channel at 1 unit of 0.01 standard deviation, red is 1.1 - 0.1 = 1 with
    // sqrt(1.1^2 + 0.1^2) times 0.01, green 1 with 0.01, blue 1.05 - 0.05 = 1 with
    // sqrt(1.05^2 + 0.05^2) times 0.01.
    let rate = [1e6, 2e6, 3e6];
    let relative = cal.relative_sigma(rate, [1e4, 2e4, 3e4]);
    let expected = DVec3::new(1.22f64.sqrt(), 1.0, 1.105f64.sqrt()) * 0.01;
    assert!(
        (relative - expected).abs().max_element() < 1e-12,
        "{relative} {expected}"
    );
    // A camera channel saturated in every capture leaves a lower bound in every channel it
    // mixes into (green into all three here).
    assert_eq!(
        cal.relative_sigma(rate, [1e4, f64::INFINITY, 3e4]),
        DVec3::splat(f64::INFINITY)
    );

    std::fs::write(&path, "gain_dn_s_per_sr = 3\n").unwrap();
    let err = Calibration::load(&path).unwrap_err().to_string();
    assert!(err.starts_with(&path.display().to_string()), "{err}");
    let missing = Calibration::load(&dir.path().join("none.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        missing.contains("none.toml") && missing.contains("cannot read"),
        "{missing}"
    );
}

/// Calibrates a simulated device with a light disk of `radius_m` at 1.1 m and measures its
/// response with the reference mirror.
fn measured_response(seed: u64, radius_m: f64, emission: Vec<f64>) -> (f64, response::ResponseFit) {
    let mut device = Device::utia();
    device.light.beam.end_radius_m = radius_m;
    device.light.emission_profile = emission;
    let truth = device.response().light.radius_deg;
    let config = SimulatorConfig::new(seed, &device);
    let white = Arc::new(DiffuseTarget::white(0.99));
    let mut sim = Simulator::new(
        device.clone(),
        MountedSample::new("white", white, Tilt::default()),
        config,
    );
    let cal = calibrate(&mut sim, mount_by_device, &CalibrationOptions::default()).unwrap();
    let info = sim.info().unwrap();
    let mut hdr = HdrCapturer::new(HdrSettings::for_device(&info), cal.noise);
    // The fit starts from the device file's radius: give it a wrong one (1.5x).
    let prior = device.response().with_light_radius_deg(1.5 * truth);
    let fit = response::measure_response(
        &mut sim,
        mount_by_device,
        &mut hdr,
        &cal,
        &prior,
        &response::ResponseOptions::default(),
    )
    .unwrap();
    (truth, fit)
}

#[test]
fn the_mirror_scan_recovers_the_light_disk() {
    // The fitted radius within 0.5 % of the true disk (the issue asks 2 %; deblurring needs
    // more: a radius 1 % off takes a GGX alpha 0.011 conductor from 0.006 to 0.027 relative
    // RMSE), with the simulator's noise and positioning error, for the UTIA disk and a
    // smaller one, and for a disk whose emission falls towards its edge (the profile is
    // known from the device file, the radius is not).
    for (seed, radius_m, emission) in [
        (3, 0.035, vec![]),
        (4, 0.02, vec![]),
        (5, 0.035, vec![1.0, 0.9, 0.5]),
    ] {
        let (truth, fit) = measured_response(seed, radius_m, emission);
        let fitted = fit.response.light.radius_deg;
        assert!(
            (fitted / truth - 1.0).abs() < 0.005,
            "radius {radius_m}: fitted {fitted} deg, true {truth} deg"
        );
        // A wrong shape (a radius off by 10 %) leaves a residual of about a third of the peak
        // at the edges; noise and the simulator's quadrature leave under a tenth.
        assert!(fit.rms_relative < 0.1, "residual {}", fit.rms_relative);
        assert_eq!(fit.scan.len(), 701);
    }
}

#[test]
fn a_calibrated_device_measures_a_known_diffuse_sample_as_it_is() {
    let mut sim = simulator(5);
    let device = sim.device().clone();
    let cal = calibrate(&mut sim, mount_by_device, &CalibrationOptions::default()).unwrap();
    let grey = Arc::new(DiffuseTarget::white(0.4));
    sim.mount_sample(MountedSample::new("grey", grey.clone(), Tilt::default()));
    let theta_h = truth_check::TRUTH_CHECK_THETA_H_DEG;
    let checks =
        truth_check::check_against_truth(&mut sim, &device, &cal, grey.as_ref(), &theta_h).unwrap();
    assert!(checks.len() >= 4, "{checks:?}");
    assert!(checks
        .windows(2)
        .all(|w| w[0].theta_h_deg < w[1].theta_h_deg));
    for check in &checks {
        assert!(theta_h.contains(&check.theta_h_deg));
        assert_eq!(check.truth, Rgb::splat(0.4 / PI));
        // A diffuse sample is not blurred by the light's disk: the calibration alone.
        assert!((check.green_ratio() - 1.0).abs() < 0.05, "{check:?}");
    }
}

#[test]
fn a_certificate_sets_each_channels_gain() {
    // The same device and seed, the white's reflectance certified per channel: each
    // channel's gain scales by the flat value over the certified one, and the file keeps the
    // certificate.
    let flat = calibrate(
        &mut simulator(8),
        mount_by_device,
        &CalibrationOptions::default(),
    )
    .unwrap();
    let certificate = white::WhiteCertificate {
        reflectance: [0.99, 0.9, 0.95],
        uncertainty: [0.004, 0.004, 0.005],
    };
    let options = CalibrationOptions {
        white_certificate: Some(certificate),
        ..CalibrationOptions::default()
    };
    let certified = calibrate(&mut simulator(8), mount_by_device, &options).unwrap();
    for c in 0..3 {
        let ratio = certified.gain_dn_s_per_sr[c] / flat.gain_dn_s_per_sr[c];
        let expected = 0.99 / certificate.reflectance[c];
        assert!(
            (ratio / expected - 1.0).abs() < 1e-12,
            "channel {c}: {ratio}"
        );
    }
    assert_eq!(certified.white_certificate, Some(certificate));
    assert!((certified.white_reflectance - (0.99 + 0.9 + 0.95) / 3.0).abs() < 1e-12);
}
