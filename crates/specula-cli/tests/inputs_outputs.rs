//! What `specula` promises of its inputs and outputs, as a user meets them: every read is
//! bounded (a token file or a CSV file that never ends is a one-line error, not gigabytes of
//! memory), no output can panic (a closed pipe ends quietly, a full disk is one line, a
//! name of any length prints), and output files are checked before work starts and never
//! left half-written by a file-size limit. Every run is bounded in time.

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

const SPECULA: &str = env!("CARGO_BIN_EXE_specula");

/// Runs `command` to its end, killing it (and failing) after `limit`.
fn run_within(command: &mut Command, limit: Duration) -> Output {
    let mut child = command
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{command:?}: still running after {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// Runs specula with `args` (at most a minute, at most 1 GiB of address space) and expects
/// exit `code` and one line on standard error holding every needle.
fn expect_error(args: &[&str], code: i32, needles: &[&str]) {
    let script = "ulimit -v 1048576; exec \"$0\" \"$@\"";
    let output = run_within(
        Command::new("bash")
            .args(["-c", script, SPECULA])
            .args(args),
        Duration::from_secs(60),
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(code), "{args:?}: {stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{args:?}: {stderr}");
    assert!(stderr.len() < 400, "{args:?}: a long error: {stderr}");
    for needle in needles {
        assert!(
            stderr.contains(needle),
            "{args:?}: no '{needle}' in {stderr}"
        );
    }
}

#[test]
fn endless_inputs_are_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.binary");
    let out = out.to_str().unwrap();
    let line = "line 1 is longer than 65536 bytes";
    expect_error(&["fit-k", "/dev/zero"], 1, &["/dev/zero", line]);
    expect_error(
        &["eval", "silver-925", "--dirs", "/dev/zero"],
        1,
        &["/dev/zero", line],
    );
    expect_error(
        &["reconstruct", "--samples-csv", "/dev/zero", "--out", out],
        1,
        &["/dev/zero", line],
    );
    let header = dir.path().join("header.csv");
    std::fs::write(&header, "theta_h,".repeat(1_000_000)).unwrap();
    expect_error(
        &["fit-k", header.to_str().unwrap()],
        1,
        &["header.csv", line],
    );
    expect_error(
        &[
            "device",
            "serve",
            "--truth",
            "silver-925",
            "--listen",
            "127.0.0.1:0",
            "--token-file",
            "/dev/zero",
        ],
        1,
        &["/dev/zero: cannot read the token file", "4096"],
    );
}

/// A material file whose name is `name`.
fn material(dir: &Path, name: &str) -> String {
    let path = dir.join("mat.toml");
    std::fs::write(
        &path,
        format!("name = \"{name}\"\n[base]\nkind = \"conductor\"\ndistribution = \"ggx\"\nalpha = 0.1\neta = [0.15, 0.14, 0.13]\nk = [3.9, 3.2, 2.4]\n"),
    )
    .unwrap();
    path.to_str().unwrap().to_string()
}

#[test]
fn printing_never_panics() {
    let dir = tempfile::tempdir().unwrap();
    let long = material(dir.path(), &"n".repeat(65_536));
    let output = run_within(
        Command::new(SPECULA).args(["appearance", &long]),
        Duration::from_secs(120),
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        stdout.lines().all(|l| l.len() < 200),
        "the name is shortened"
    );
    assert!(stdout.contains("gloss 60 deg"), "{stdout}");
    // A reader that has gone away: quiet, exit 0 (as the reader asked for no more).
    let output = run_within(
        Command::new("bash").args([
            "-c",
            "set -o pipefail; \"$0\" appearance silver-925 | true",
            SPECULA,
        ]),
        Duration::from_secs(120),
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    assert!(stderr.is_empty(), "{stderr}");
    for flags in ["", "--csv"] {
        let output = run_within(
            Command::new("bash").args([
                "-c",
                "\"$0\" appearance silver-925 $1 > /dev/full",
                SPECULA,
                flags,
            ]),
            Duration::from_secs(120),
        );
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{flags}: {stderr}");
        assert_eq!(
            stderr.trim_end(),
            "error: cannot write to standard output: No space left on device (os error 28)"
        );
    }
}

#[test]
fn output_paths_are_checked_before_work_and_never_left_half_written() {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().to_str().unwrap();
    let start = Instant::now();
    expect_error(
        &["tabulate", "silver-925", "--out", folder],
        2,
        &["--out", "is a directory, not a file"],
    );
    let missing = dir.path().join("missing").join("x.binary");
    expect_error(
        &[
            "measure",
            "--truth",
            "silver-925",
            "--out",
            missing.to_str().unwrap(),
        ],
        2,
        &["--out", "does not exist"],
    );
    expect_error(
        &["convert", "silver-925", folder],
        2,
        &["is a directory, not a file"],
    );
    assert!(start.elapsed() < Duration::from_secs(10), "before any work");
    // A file-size limit of 1 MB: a one-line error, and no temporary left behind.
    let out = dir.path().join("big.binary");
    let output = run_within(
        Command::new("bash").args([
            "-c",
            "ulimit -f 1000; \"$0\" tabulate silver-925 --out \"$1\"",
            SPECULA,
            out.to_str().unwrap(),
        ]),
        Duration::from_secs(300),
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("big.binary") && stderr.contains("File too large"),
        "{stderr}"
    );
    let left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert!(left.is_empty(), "left behind: {left:?}");
}
