//! The edges a new user meets first: negative angles, the help of the BRDF commands, what
//! `info`, `compare` and `fit` say, and the ranges the CLI shares with the Python package.

use assert_cmd::Command;
use specula_core::merl::{Bin, MerlBrdf, CELLS};
use specula_core::request;
use specula_core::Rgb;

fn specula() -> Command {
    Command::cargo_bin("specula").expect("the specula binary is built")
}

/// (exit code, stdout, stderr) of `specula ARGS`.
fn run(args: &[&str]) -> (Option<i32>, String, String) {
    let output = specula().args(args).output().unwrap();
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

#[test]
fn a_negative_angle_gets_the_options_range_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("p.csv");
    let (code, _, stderr) = run(&[
        "probe",
        "chrome",
        "--theta-d",
        "-40",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(
        stderr.contains("--theta-d -40: expected degrees from 0 to 89.5"),
        "{stderr}"
    );
    assert!(!stderr.contains("unexpected argument"), "{stderr}");
}

#[test]
fn probe_takes_a_negative_phi_h_as_its_help_says() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let (code, _, stderr) = run(&[
        "probe",
        "chrome",
        "--phi-h",
        "-45",
        "--out",
        &path("minus.csv"),
    ]);
    assert_eq!(code, Some(0), "{stderr}");
    let (code, _, stderr) = run(&[
        "probe",
        "chrome",
        "--phi-h",
        "315",
        "--out",
        &path("turn.csv"),
    ]);
    assert_eq!(code, Some(0), "{stderr}");
    let read = |name: &str| std::fs::read_to_string(path(name)).unwrap();
    // An isotropic material: -45 and 315 deg are the same orientation.
    assert_eq!(read("minus.csv"), read("turn.csv"));
    let (_, help, _) = run(&["probe", "--help"]);
    let help = help.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(help.contains("Range: degrees from -360 to 360"), "{help}");
}

#[test]
fn eval_help_names_the_light_the_camera_and_the_rgl_slot() {
    let (_, help, _) = run(&["eval", "--help"]);
    let help = help.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(
        help.contains("(theta_i, phi_i) is the direction towards the light"),
        "{help}"
    );
    assert!(
        help.contains("(theta_o, phi_o) the direction towards the camera"),
        "{help}"
    );
    assert!(
        help.contains("the camera direction in the file's incident slot"),
        "{help}"
    );
}

#[test]
fn the_brdf_commands_list_rgl_files_among_their_inputs() {
    for argv in [&["--help"][..], &["render", "--help"], &["eval", "--help"]] {
        let (_, help, _) = run(argv);
        assert!(help.contains(".bsdf"), "{argv:?}: {help}");
    }
}

/// A flat table with a bright cell at grazing theta_d and a brighter-than-flat one within
/// 75 deg.
fn grazing_table(path: &std::path::Path) {
    let mut table = MerlBrdf::empty("matte");
    for i in 0..CELLS {
        table.set_cell(i, Some(Rgb::splat(0.2)));
    }
    let bin = |theta_h_i, theta_d_i| {
        Bin {
            theta_h_i,
            theta_d_i,
            phi_d_i: 90,
        }
        .index()
    };
    table.set_cell(bin(10, 89), Some(Rgb::splat(1000.0)));
    table.set_cell(bin(10, 20), Some(Rgb::splat(5.0)));
    table.write(path).unwrap();
}

#[test]
fn info_leads_with_the_peak_within_75_deg_and_names_the_grazing_one() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("matte.binary");
    grazing_table(&path);
    let (code, stdout, stderr) = run(&["info", path.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{stderr}");
    let within = stdout
        .lines()
        .position(|l| l.starts_with("peak within 75 deg: 5 1/sr") && l.contains("theta_d 20.5 deg"))
        .unwrap_or_else(|| panic!("{stdout}"));
    let grazing = stdout
        .lines()
        .position(|l| {
            l.starts_with("peak of the grazing cells: 1000 1/sr")
                && l.contains("theta_d 89.5 deg")
                && l.contains("beyond 75 deg")
        })
        .unwrap_or_else(|| panic!("{stdout}"));
    assert!(within < grazing, "{stdout}");
}

#[test]
fn compare_leads_with_the_row_within_75_deg_and_says_what_grazing_cells_are() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("matte.binary");
    grazing_table(&path);
    let p = path.to_str().unwrap();
    let (code, stdout, stderr) = run(&["compare", p, "green-paint"]);
    assert_eq!(code, Some(0), "{stderr}");
    let rows: Vec<&str> = stdout.lines().collect();
    assert_eq!(rows[0], "set,cells,relative_rmse,log_rmse,slice_mae");
    assert!(
        rows[1].starts_with("within,") && rows[2].starts_with("all,"),
        "{stdout}"
    );
    assert!(stderr.contains("grazing cells"), "{stderr}");
    assert!(stderr.contains("seen edge-on"), "{stderr}");
}

#[test]
fn fit_says_which_model_it_exported() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("fit.toml");
    let (code, stdout, stderr) = run(&[
        "fit",
        "chrome",
        "--model",
        "conductor",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(stdout.contains("exported model: conductor"), "{stdout}");
}

#[test]
fn the_grid_and_probe_ranges_are_the_librarys_words() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.binary");
    let out = out.to_str().unwrap();
    let cases = [
        (
            vec![
                "plan",
                "--k",
                "4.78",
                "--theta-h-samples",
                "1",
                "--out",
                out,
            ],
            format!(
                "--theta-h-samples 1: expected {}",
                request::THETA_H_SAMPLES.words()
            ),
        ),
        (
            vec!["plan", "--k", "4.78", "--phi-h", "-400", "--out", out],
            format!("--phi-h -400: expected {}", request::AZIMUTH_DEG.words()),
        ),
        (
            vec![
                "measure",
                "--truth",
                "chrome",
                "--probe-samples",
                "20000",
                "--out",
                out,
            ],
            format!(
                "--probe-samples 20000: expected {}",
                request::PROBE_SAMPLES.words()
            ),
        ),
        (
            vec!["measure", "--truth", "chrome", "--tilt", "20", "--out", out],
            format!("--tilt 20: expected {}", request::TILT_DEG.words()),
        ),
    ];
    for (argv, words) in cases {
        let (code, _, stderr) = run(&argv);
        assert_eq!(code, Some(2), "{argv:?}: {stderr}");
        assert!(stderr.contains(&words), "{argv:?}: {stderr}");
    }
}

/// A long render stopped by Ctrl-C (SIGINT): it ends at its next tile, exits 130 as every
/// stopped run does, and writes no picture.
#[test]
fn ctrl_c_stops_a_render_at_once_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("long.png");
    // 1024 x 1024 pixels at 4096 rays each: minutes of work.
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_specula"))
        .args([
            "render", "chrome", "--size", "1024", "--spp", "4096", "--out",
        ])
        .arg(&out)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_secs(2));
    let sent = std::time::Instant::now();
    let interrupt = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(interrupt.success());
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(130), "{stderr}");
    assert!(
        stderr.contains("interrupted: stopped: 0 of 1 pictures done"),
        "{stderr}"
    );
    assert!(
        sent.elapsed() < std::time::Duration::from_secs(30),
        "stopped {:?} after the signal",
        sent.elapsed()
    );
    assert!(!out.exists());
}
