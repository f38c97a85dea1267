//! What `specula` promises on real hardware (issue 16), as a user meets it: an empty token
//! refused and a token from a file or the environment, a paced run stopped by one SIGTERM,
//! absurd inputs refused by one line before anything is allocated, and a resume with an
//! edited material refused. Servers listen on 127.0.0.1 only; every wait is bounded.

mod serve;
mod small_plan;

use serve::serve;
use small_plan::measure_args;
use specula_session::Stage;
use std::io::{BufRead, BufReader, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

const SPECULA: &str = env!("CARGO_BIN_EXE_specula");

/// Waits at most `limit` for the child; kills it (and fails) if it is still running.
fn finish_within(mut child: Child, limit: Duration, what: &str) -> Output {
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{what}: still running after {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// Runs specula to its end (at most a minute) and expects a one-line error containing
/// every needle, exit code 1.
fn one_line_error(args: &[&str], needles: &[&str]) {
    let child = Command::new(SPECULA)
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let output = finish_within(child, Duration::from_secs(60), &format!("{args:?}"));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{args:?}: {stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    for needle in needles {
        assert!(stderr.contains(needle), "{needle}: {stderr}");
    }
}

/// The reply to a `hello` with `token` (10 s at most).
fn hello(port: u16, token: Option<&str>) -> serde_json::Value {
    let mut stream = TcpStream::connect(("127.0.0.1", port)).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_secs(10)))
        .unwrap();
    let mut params = serde_json::json!({"protocol": 1});
    if let Some(t) = token {
        params["token"] = t.into();
    }
    writeln!(
        stream,
        "{}",
        serde_json::json!({"id": 1, "method": "hello", "params": params})
    )
    .unwrap();
    let mut line = String::new();
    BufReader::new(stream).read_line(&mut line).unwrap();
    serde_json::from_str(&line).unwrap()
}

#[test]
fn an_empty_token_is_refused_and_a_token_comes_from_a_file_or_the_environment() {
    let dir = tempfile::tempdir().unwrap();
    one_line_error(
        &[
            "device",
            "serve",
            "--truth",
            "silver-925",
            "--listen",
            "0.0.0.0:0",
            "--token",
            "",
        ],
        &["--token", "empty"],
    );
    let empty = dir.path().join("empty-token");
    std::fs::write(&empty, "\n").unwrap();
    let empty = empty.display().to_string();
    one_line_error(
        &[
            "device",
            "serve",
            "--truth",
            "silver-925",
            "--token-file",
            &empty,
        ],
        &["empty-token", "empty"],
    );

    let file = dir.path().join("token");
    std::fs::write(&file, "lab-secret\n").unwrap();
    let (mut server, port) = serve(&["--token-file", &file.display().to_string()], &[]);
    assert_eq!(hello(port, None)["error"]["kind"], "unauthorized");
    // The server names its sample by a hash only: nothing of the truth crosses the wire.
    let name = hello(port, Some("lab-secret"))["result"]["server"].clone();
    let name = name.as_str().unwrap();
    assert!(name.starts_with("specula device serve (sample "), "{name}");
    assert!(!name.contains("silver"), "{name}");
    server.kill().unwrap();
    server.wait().unwrap();

    let (mut server, port) = serve(&[], &[("SPECULA_TOKEN", "from-env")]);
    assert_eq!(
        hello(port, Some("lab-secret"))["error"]["kind"],
        "unauthorized"
    );
    assert!(hello(port, Some("from-env"))["result"].is_object());
    server.kill().unwrap();
    server.wait().unwrap();
}

#[test]
fn one_sigterm_stops_a_slowly_paced_run_promptly_and_resumably() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("slow.binary");
    let session = out.with_extension("session.sqlite");
    // A thousandth of real time: one probe sample would take hours.
    let mut child = Command::new(SPECULA)
        .args(measure_args(
            &out,
            &["--truth", "silver-925", "--speedup", "0.001"],
        ))
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    loop {
        let planned = specula_session::journal::Journal::open_read_only(&session)
            .ok()
            .and_then(|j| j.plan(Stage::Probe).ok())
            .is_some_and(|p| !p.is_empty());
        if planned {
            break;
        }
        assert!(child.try_wait().unwrap().is_none(), "the run ended early");
        assert!(start.elapsed() < Duration::from_secs(60), "no probe plan");
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(300));
    let term = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(term.success());
    let stopped_at = Instant::now();
    let output = finish_within(child, Duration::from_secs(10), "after SIGTERM");
    assert!(
        stopped_at.elapsed() < Duration::from_secs(5),
        "{:?}",
        stopped_at.elapsed()
    );
    // SIGTERM's own exit code (128 + 15), not Ctrl-C's, and how to resume.
    assert_eq!(output.status.code(), Some(143), "{:?}", output.status);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("stopped: probe"), "{stdout}");
    assert!(
        stdout.contains("run the same command to resume"),
        "{stdout}"
    );

    // The same command, unpaced, resumes and completes.
    let resumed = Command::new(SPECULA)
        .args(measure_args(&out, &["--truth", "silver-925"]))
        .output()
        .unwrap();
    assert_eq!(
        resumed.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&resumed.stderr)
    );
    assert!(out.exists());
}

fn material(dir: &Path, alpha: f64) -> PathBuf {
    let path = dir.join("mat.toml");
    let text = format!(
        "name = \"mat\"\n[base]\nkind = \"conductor\"\ndistribution = \"ggx\"\nalpha = {alpha}\n\
         eta = [0.15, 0.14, 0.13]\nk = [3.9, 3.2, 2.4]\n"
    );
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_resume_with_an_edited_material_is_refused_naming_the_truth() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("mat.binary");
    let path = material(dir.path(), 0.04).display().to_string();
    let output = Command::new(SPECULA)
        .args(measure_args(&out, &["--truth", &path]))
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    material(dir.path(), 0.3);
    let args = measure_args(&out, &["--truth", &path]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    one_line_error(&args, &["other inputs", "truth (content sha256)"]);
}

#[test]
fn absurd_inputs_are_refused_in_one_line_before_allocating() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.binary").display().to_string();
    // A 4 GiB sparse file as a truth and as a table to evaluate.
    let huge = dir.path().join("huge.binary");
    std::fs::File::create(&huge)
        .unwrap()
        .set_len(4 << 30)
        .unwrap();
    let huge = huge.display().to_string();
    let started = Instant::now();
    let args = measure_args(Path::new(&out), &["--truth", &huge]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    one_line_error(&args, &["huge.binary"]);
    assert!(
        started.elapsed() < Duration::from_secs(20),
        "{:?}",
        started.elapsed()
    );
    let huge_csv = dir.path().join("huge.csv");
    std::fs::File::create(&huge_csv)
        .unwrap()
        .set_len(4 << 30)
        .unwrap();
    let huge_csv = huge_csv.display().to_string();
    one_line_error(
        &["convert", &huge_csv, &out],
        &["huge.csv", "4294967296 bytes"],
    );

    // A device model with a turntable range of +-1e300 deg.
    let wide = dir.path().join("wide.toml");
    let utia = specula_acquisition::device::UTIA_TOML.replacen(
        "min_deg = -180.0\nmax_deg = 180.0",
        "min_deg = -1e300\nmax_deg = 1e300",
        1,
    );
    std::fs::write(&wide, utia).unwrap();
    let wide = wide.display().to_string();
    one_line_error(
        &[
            "plan",
            "--device",
            &wide,
            "--k",
            "4.78",
            "--out",
            &format!("{out}.plan.csv"),
        ],
        &["wide.toml", "turntable", "[-720, 720]"],
    );

    // A calibration with a negative gain.
    let calibration = dir.path().join("cam.toml");
    std::fs::write(
        &calibration,
        std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../../tools/example_adapter_calibration.toml"),
        )
        .unwrap()
        .replace(
            "[200000.0, 200000.0, 200000.0]",
            "[-200000.0, 200000.0, 200000.0]",
        ),
    )
    .unwrap();
    let calibration = calibration.display().to_string();
    let args = measure_args(
        Path::new(&out),
        &[
            "--connect",
            "tcp://127.0.0.1:9",
            "--calibration",
            &calibration,
        ],
    );
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    one_line_error(
        &args,
        &["cam.toml", "gain_dn_s_per_sr[0] must be from 0.01 to 1e12"],
    );
}

#[test]
fn without_a_terminal_progress_comes_as_lines_at_each_interval() {
    // stderr is a pipe, not a terminal: the bars draw nothing, so lines carry the stage,
    // the samples done of those planned and the time left, at each interval of wall time
    // (half a second here instead of the default minute), also within one slow stage.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("logged.binary");
    let output = Command::new(SPECULA)
        .args(measure_args(
            &out,
            &["--truth", "silver-925", "--speedup", "300"],
        ))
        .env("SPECULA_PROGRESS_INTERVAL_S", "0.5")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    let lines: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("progress: "))
        .collect();
    // A line when the main stage starts (a few seconds at this pace), then one per interval.
    let main_lines = lines
        .iter()
        .filter(|l| l.starts_with("progress: main "))
        .count();
    assert!(main_lines >= 3, "{main_lines} lines: {stderr}");
    let main = lines
        .iter()
        .rev()
        .find(|l| l.starts_with("progress: main "))
        .unwrap_or_else(|| panic!("no line of the main stage: {stderr}"));
    assert!(
        main.contains(" samples, ") && main.contains("left (device time)"),
        "{main}"
    );
    assert!(
        lines
            .iter()
            .any(|l| l.starts_with("progress: probe 0/") && l.contains("not yet known")),
        "{stderr}"
    );
}

#[test]
fn a_resume_with_another_grid_names_the_setting_and_both_values_in_words() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("grid.binary");
    // Started on the recommended grid (its rule for an unresolved peak included)...
    let recommended: Vec<String> = measure_args(&out, &["--truth", "silver-925"])
        .into_iter()
        .filter(|a| a != "--grid-preset" && a != "paper")
        .collect();
    let first = Command::new(SPECULA).args(&recommended).output().unwrap();
    assert!(first.status.success());
    // ...resumed asking for the paper's grid.
    let output = Command::new(SPECULA)
        .args(measure_args(&out, &["--truth", "silver-925"]))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    let error = stderr
        .lines()
        .find(|l| l.starts_with("error: "))
        .unwrap_or_else(|| panic!("{stderr}"));
    assert!(
        error.contains("--phi-d-span: half-turn in the session, quarter asked"),
        "{error}"
    );
    assert!(
        !error.contains('{') && !error.contains("null") && !error.contains(" vs "),
        "no internal JSON: {error}"
    );
}

#[test]
fn a_session_that_does_not_exist_is_named_in_one_line_by_every_reader() {
    // reconstruct, report and session status read a journal; given a path where none is,
    // each says so by name (not SQLite's "unable to open database file") and creates nothing.
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("never-measured.session.sqlite");
    let missing_arg = missing.display().to_string();
    let out = dir.path().join("t.binary").display().to_string();
    let report = dir.path().join("r.html").display().to_string();
    for args in [
        vec!["reconstruct", "--session", &missing_arg, "--out", &out],
        vec!["report", &missing_arg, "--out", &report],
        vec!["session", "status", &missing_arg],
    ] {
        one_line_error(
            &args,
            &["never-measured.session.sqlite", "no such session journal"],
        );
        assert!(!missing.exists(), "{args:?} created the journal");
    }
}
