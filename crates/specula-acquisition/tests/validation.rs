//! Device models and calibrations are checked when they are loaded (issue 16): a value out
//! of its range is a one-line error naming the file, the field and the range, never a run
//! that ends in zero tables, a NaN or an allocation of gigabytes.

use specula_acquisition::calibration::Calibration;
use specula_acquisition::device::{Device, UTIA_TOML};
use std::path::{Path, PathBuf};

const CALIBRATION: &str = "
device = \"lab camera, 1\"
white_reflectance = 0.99
light_elevation_deg = 45.0
gain_dn_s_per_sr = [200000.0, 210000.0, 190000.0]
colour_matrix = [[1.2, -0.1, 0.0], [-0.1, 1.1, 0.0], [0.0, -0.2, 1.3]]
colour_rms_error = 0.01
colour_reference = \"ColorChecker\"

[noise]
black_level_dn = 64.0
dark_current_dn_s = 0.5
gain_dn_per_e = 0.25
read_noise_dn = 2.0
white_level_dn = 4095.0
";

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn calibration_error(text: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "cam.toml", text);
    let message = Calibration::load(&path).unwrap_err().to_string();
    assert!(
        message.starts_with(&path.display().to_string()),
        "{message}"
    );
    assert!(!message.contains('\n'), "{message}");
    message
}

#[test]
fn a_calibration_out_of_range_is_refused_naming_the_field() {
    let dir = tempfile::tempdir().unwrap();
    Calibration::load(&write(dir.path(), "ok.toml", CALIBRATION)).expect("a sound calibration");
    let cases = [
        (
            "[200000.0, 210000.0, 190000.0]",
            "[-200000.0, 210000.0, 190000.0]",
            "gain_dn_s_per_sr[0] must be from 0.01 to 1e12, got -200000",
        ),
        (
            "[200000.0, 210000.0, 190000.0]",
            "[200000.0, 0.0, 190000.0]",
            "gain_dn_s_per_sr[1] must be from 0.01 to 1e12, got 0",
        ),
        (
            "[200000.0, 210000.0, 190000.0]",
            "[200000.0, 210000.0, nan]",
            "gain_dn_s_per_sr[2] must be from 0.01 to 1e12, got NaN",
        ),
        (
            "[[1.2, -0.1, 0.0], [-0.1, 1.1, 0.0], [0.0, -0.2, 1.3]]",
            "[[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]",
            "colour_matrix must be invertible",
        ),
        (
            "[[1.2, -0.1, 0.0], [-0.1, 1.1, 0.0], [0.0, -0.2, 1.3]]",
            "[[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 1.0]]",
            "colour_matrix must be invertible",
        ),
        (
            "black_level_dn = 64.0",
            "black_level_dn = 5000.0",
            "noise.white_level_dn must be above noise.black_level_dn (5000) and at most 1e9",
        ),
        (
            "gain_dn_per_e = 0.25",
            "gain_dn_per_e = -1.0",
            "noise.gain_dn_per_e",
        ),
        (
            "[200000.0, 210000.0, 190000.0]",
            "[1e300, 210000.0, 190000.0]",
            "gain_dn_s_per_sr[0] must be from 0.01 to 1e12, got 1e300",
        ),
        (
            "[200000.0, 210000.0, 190000.0]",
            "[200000.0, 1e-300, 190000.0]",
            "gain_dn_s_per_sr[1] must be from 0.01 to 1e12, got 1e-300",
        ),
        (
            "white_level_dn = 4095.0",
            "white_level_dn = 1e300",
            "noise.white_level_dn must be above noise.black_level_dn (64) and at most 1e9, got 1e300",
        ),
        (
            "dark_current_dn_s = 0.5",
            "dark_current_dn_s = 1e300",
            "noise.dark_current_dn_s must be from 0 to 1e9, got 1e300",
        ),
        (
            "white_reflectance = 0.99",
            "white_reflectance = 1e300",
            "white_reflectance must be in (0, 1], got 1e300",
        ),
    ];
    for (from, to, needle) in cases {
        let message = calibration_error(&CALIBRATION.replace(from, to));
        assert!(message.contains(needle), "{needle}: {message}");
    }
}

#[test]
fn a_device_with_an_absurd_axis_range_is_refused_before_planning() {
    let dir = tempfile::tempdir().unwrap();
    for (min, max) in [("-1e300", "1e300"), ("-360000.0", "360000.0")] {
        let text = UTIA_TOML.replacen(
            "min_deg = -180.0\nmax_deg = 180.0",
            &format!("min_deg = {min}\nmax_deg = {max}"),
            1,
        );
        assert_ne!(text, UTIA_TOML);
        let path = write(dir.path(), "wide.toml", &text);
        let message = Device::load(&path).unwrap_err().to_string();
        assert!(
            message.contains("wide.toml")
                && message.contains("turntable")
                && message.contains("[-720, 720]"),
            "{message}"
        );
        assert!(message.len() < 200, "numbers print short: {message}");
    }
    let path = dir.path().join("huge.toml");
    std::fs::File::create(&path)
        .unwrap()
        .set_len(4 << 30)
        .unwrap();
    let message = Device::load(&path).unwrap_err().to_string();
    assert!(message.contains("4294967296 bytes"), "{message}");
}

#[test]
fn a_device_with_absurd_times_speeds_or_park_angles_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            "settle_s = 0.5 ",
            "settle_s = 1e300 ",
            "turntable.settle_s must be from 0 to 600, got 1e300",
        ),
        (
            "speed_deg_s = 20.0 ",
            "speed_deg_s = 1e-300 ",
            "turntable.speed_deg_s must be from 0.01 to 3600, got 1e-300",
        ),
        (
            "accel_deg_s2 = 20.0 ",
            "accel_deg_s2 = 1e300 ",
            "turntable.accel_deg_s2 must be from 0.01 to 36000, got 1e300",
        ),
        (
            "readout_s = 0.32",
            "readout_s = 1e300",
            "capture times must be numbers of seconds from 0 to 3600",
        ),
        (
            "turntable_deg = 0.0",
            "turntable_deg = 1e6",
            "park.turntable_deg must be from -180 to 180, got 1e6",
        ),
        (
            "light_elevation_deg = 45.0",
            "light_elevation_deg = 80.0",
            "park.light_elevation_deg must be from -75 to 75, got 80",
        ),
        (
            "distance_m = 2.0",
            "distance_m = 1e300",
            "camera.distance_m must be above 0 and at most 100, got 1e300",
        ),
        (
            "light_levels = [1.0, 0.1, 0.01]",
            "light_levels = [1e300]",
            "capture.light_levels must be above 0 and at most 1",
        ),
    ];
    for (from, to, needle) in cases {
        let text = UTIA_TOML.replacen(from, to, 1);
        assert_ne!(text, UTIA_TOML, "{from}");
        let path = write(dir.path(), "absurd.toml", &text);
        let message = Device::load(&path).unwrap_err().to_string();
        assert!(
            message.contains("absurd.toml") && message.contains(needle) && !message.contains('\n'),
            "{needle}: {message}"
        );
    }
}
