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
            "gain_dn_s_per_sr[0] must be positive",
        ),
        (
            "[200000.0, 210000.0, 190000.0]",
            "[200000.0, 0.0, 190000.0]",
            "gain_dn_s_per_sr[1] must be positive",
        ),
        (
            "[200000.0, 210000.0, 190000.0]",
            "[200000.0, 210000.0, nan]",
            "gain_dn_s_per_sr[2] must be positive and finite, got NaN",
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
            "noise.white_level_dn must be finite and above noise.black_level_dn (5000)",
        ),
        (
            "gain_dn_per_e = 0.25",
            "gain_dn_per_e = -1.0",
            "noise.gain_dn_per_e",
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
