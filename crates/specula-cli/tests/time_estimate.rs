//! The time a run takes, as `plan` predicts it and `measure` records it beside the simulated
//! clock: the prediction holds within 10 % for the default grid (predicted exposures) and the
//! paper's (nested order, fixed bracket), and `plan --k K` prints the same prediction.

use assert_cmd::Command;

fn specula() -> Command {
    Command::cargo_bin("specula").expect("the specula binary is built")
}

/// `key=value` of the command's standard output, as a number.
fn value(stdout: &str, key: &str) -> f64 {
    let prefix = format!("{key}=");
    let line = stdout
        .lines()
        .find_map(|l| l.strip_prefix(&prefix))
        .unwrap_or_else(|| panic!("no {key}= in\n{stdout}"));
    line.trim().parse().expect("a number")
}

/// Measures silver-925 on the simulated device with `grid` options, then plans the same grid
/// with the measured k-hat: (predicted_main_hours, simulated_main_hours, plan's predicted_hours).
fn measured_and_planned(grid: &[&str], plan_only: &[&str]) -> (f64, f64, f64) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("silver.binary");
    let output = specula()
        .args(["measure", "--truth", "silver-925", "--skip-checks"])
        .args(grid)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(output.status.success(), "{stdout}");
    let k_hat = value(&stdout, "k_hat");
    let plan = specula()
        .args(["plan", "--k", &k_hat.to_string()])
        .args(grid.iter().filter(|a| !["--method", "linear"].contains(a)))
        .args(plan_only)
        .arg("--out")
        .arg(dir.path().join("plan.csv"))
        .output()
        .unwrap();
    let planned = String::from_utf8_lossy(&plan.stdout).into_owned();
    assert!(plan.status.success(), "{planned}");
    (
        value(&stdout, "predicted_main_hours"),
        value(&stdout, "simulated_main_hours"),
        value(&planned, "predicted_hours"),
    )
}

fn assert_holds(predicted: f64, simulated: f64, planned: f64) {
    assert!(
        (predicted / simulated - 1.0).abs() < 0.10,
        "predicted {predicted} h, simulated {simulated} h"
    );
    assert_eq!(
        planned, predicted,
        "plan's predicted_hours vs the summary's"
    );
}

#[test]
fn the_default_grid_with_predicted_exposures_takes_the_predicted_time() {
    // The recommended grid's shape (graded theta_d, phi_d over the half turn), small, measured
    // whole (a preset fixes the grid before the first capture).
    let grid = [
        "--grid-preset",
        "recommended",
        "--theta-h-samples",
        "8",
        "--theta-d-step",
        "9:3@60",
        "--phi-d-step",
        "45",
    ];
    let (predicted, simulated, planned) = measured_and_planned(&grid, &["--truth", "silver-925"]);
    assert_holds(predicted, simulated, planned);
}

#[test]
fn the_papers_grid_with_the_bracket_takes_the_predicted_time() {
    let grid = [
        "--grid-preset",
        "paper",
        "--method",
        "linear",
        "--order",
        "nested",
        "--hdr",
        "bracket",
        "--theta-h-samples",
        "8",
        "--theta-d-step",
        "15",
        "--phi-d-step",
        "30",
    ];
    let (predicted, simulated, planned) = measured_and_planned(&grid, &[]);
    assert_holds(predicted, simulated, planned);
}
