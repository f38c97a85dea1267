//! What a stop of `specula measure` promises about time and processes: an `exec:` adapter and
//! every process it started (also one that left with `setsid`) end with `measure`, however
//! `measure` ends (complete, an error, one or two Ctrl-C, SIGTERM, `kill -9`); a stop while
//! the device hangs ends the run within seconds, resumably, with exit code 130 (143 after SIGTERM); the session
//! lock holds across a hard link; a directory or a journal of a newer specula is refused in
//! one line. Each adapter carries a unique marker in its command line, looked for in `/proc`.
//! Every wait is bounded.

#![cfg(target_os = "linux")]

mod small_plan;

use small_plan::SMALL_PLAN;
use specula_session::Stage;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

const SPECULA: &str = env!("CARGO_BIN_EXE_specula");
const CALIBRATION: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../tools/example_adapter_calibration.toml"
);

/// A marker no other process has: a `sleep` duration with this process's id and a counter
/// as its decimals (`sleep 900.PID0N` sleeps 15 minutes and is found by its command line).
fn new_marker() -> String {
    static NEXT: AtomicU32 = AtomicU32::new(1);
    format!(
        "900.{}0{}",
        std::process::id(),
        NEXT.fetch_add(1, Ordering::SeqCst)
    )
}

/// The processes whose command line contains `marker`.
fn processes_with(marker: &str) -> Vec<u32> {
    let Ok(entries) = std::fs::read_dir("/proc") else {
        return Vec::new();
    };
    entries
        .filter_map(|e| e.ok()?.file_name().to_str()?.parse::<u32>().ok())
        .filter(|pid| {
            std::fs::read(format!("/proc/{pid}/cmdline"))
                .is_ok_and(|c| String::from_utf8_lossy(&c).contains(marker))
        })
        .collect()
}

/// Waits up to `limit` for `done`; whether it came.
fn wait_for(limit: Duration, mut done: impl FnMut() -> bool) -> bool {
    let start = Instant::now();
    while start.elapsed() < limit {
        if done() {
            return true;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    done()
}

/// `measure` of the device behind `connect`, writing `out` (stdout and stderr piped).
fn start_measure(connect: &str, out: &Path, extra: &[&str]) -> Child {
    Command::new(SPECULA)
        .arg("measure")
        .args(SMALL_PLAN)
        .args(["--connect", connect, "--calibration", CALIBRATION])
        .args(extra)
        .arg("--out")
        .arg(out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Waits at most `limit` for the child to end; kills it (and fails) if it does not.
fn end_within(mut child: Child, limit: Duration, what: &str) -> Output {
    let ended = wait_for(limit, || child.try_wait().unwrap().is_some());
    if !ended {
        let _ = child.kill();
        let _ = child.wait();
        panic!("{what}: still running after {limit:?}");
    }
    child.wait_with_output().unwrap()
}

fn signal(child: &Child, name: &str) {
    let sent = Command::new("kill")
        .args([name, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success(), "kill {name}");
}

/// An adapter that never answers: a `sleep` in the foreground, one in the background and one
/// that leaves the process group with `setsid`, all marked.
fn hanging_adapter(marker: &str) -> String {
    format!("exec:setsid sleep {marker} & sleep {marker} & sleep {marker}")
}

/// How a test stops `measure`.
#[derive(Debug, Clone, Copy)]
enum Stop {
    CtrlC,
    CtrlCTwice,
    Term,
    Kill,
}

/// Starts `measure` on a hanging adapter, stops it `how`, and checks that it ends within
/// 5 s with the right exit and that no adapter process is left 5 s after.
fn stop_a_hanging_adapter(how: Stop) {
    let dir = tempfile::tempdir().unwrap();
    let marker = new_marker();
    let child = start_measure(&hanging_adapter(&marker), &dir.path().join("x.binary"), &[]);
    // measure, the guardian, the shell and three sleeps.
    assert!(
        wait_for(Duration::from_secs(20), || processes_with(&marker).len()
            >= 5),
        "{how:?}: the adapter did not start: {:?}",
        processes_with(&marker)
    );
    match how {
        Stop::CtrlC => signal(&child, "-INT"),
        Stop::CtrlCTwice => {
            signal(&child, "-INT");
            std::thread::sleep(Duration::from_millis(20));
            signal(&child, "-INT");
        }
        Stop::Term => signal(&child, "-TERM"),
        Stop::Kill => signal(&child, "-KILL"),
    }
    let stopped = Instant::now();
    let output = end_within(child, Duration::from_secs(30), &format!("{how:?}"));
    let took = stopped.elapsed();
    assert!(
        took < Duration::from_secs(5),
        "{how:?}: ended after {took:?}"
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    match how {
        Stop::Kill => assert_eq!(output.status.code(), None, "{how:?}"),
        Stop::Term => assert_eq!(output.status.code(), Some(143), "{how:?}: {stderr}"),
        _ => assert_eq!(output.status.code(), Some(130), "{how:?}: {stderr}"),
    }
    let left = || processes_with(&marker);
    assert!(
        wait_for(Duration::from_secs(5), || left().is_empty()),
        "{how:?}: adapter processes left: {:?}",
        left()
    );
}

#[test]
fn one_ctrl_c_ends_a_run_on_a_hanging_adapter_at_once_with_nothing_left() {
    stop_a_hanging_adapter(Stop::CtrlC);
}

#[test]
fn two_ctrl_c_end_a_run_at_once_with_nothing_left() {
    stop_a_hanging_adapter(Stop::CtrlCTwice);
}

#[test]
fn sigterm_ends_a_run_at_once_with_nothing_left() {
    stop_a_hanging_adapter(Stop::Term);
}

#[test]
fn kill_9_of_measure_leaves_no_adapter_process() {
    stop_a_hanging_adapter(Stop::Kill);
}

#[test]
fn an_adapter_ends_with_a_run_that_fails_or_completes() {
    let dir = tempfile::tempdir().unwrap();

    // An error: the adapter answers garbage, once is enough.
    let marker = new_marker();
    let garbage = format!("exec:setsid sleep {marker} & echo not-json; sleep {marker}");
    let child = start_measure(
        &garbage,
        &dir.path().join("e.binary"),
        &["--max-failures", "1"],
    );
    let output = end_within(child, Duration::from_secs(60), "garbage adapter");
    assert_eq!(output.status.code(), Some(1));
    assert!(
        wait_for(Duration::from_secs(5), || processes_with(&marker)
            .is_empty()),
        "after an error: {:?}",
        processes_with(&marker)
    );

    // A complete run: the simulated device behind the protocol, with a marked process
    // that left the group beside it.
    let marker = new_marker();
    let calibration = dir.path().join("calibration.toml");
    let calibrated = Command::new(SPECULA)
        .args(["calibrate", "--truth", "silver-925", "--seed", "3", "--out"])
        .arg(&calibration)
        .output()
        .unwrap();
    assert!(calibrated.status.success());
    let served = format!(
        "exec:setsid sleep {marker} & exec '{SPECULA}' device serve --truth silver-925 --seed 3 --stdio"
    );
    let output = Command::new(SPECULA)
        .arg("measure")
        .args(SMALL_PLAN)
        .args(["--connect", &served, "--calibration"])
        .arg(&calibration)
        .arg("--out")
        .arg(dir.path().join("c.binary"))
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(
        wait_for(Duration::from_secs(5), || processes_with(&marker)
            .is_empty()),
        "after a complete run: {:?}",
        processes_with(&marker)
    );
}

/// The simulated device served on stdin and stdout, hanging (a 1000 s reply) at its
/// `request`-th request.
fn hanging_device(request: u32) -> String {
    format!("exec:'{SPECULA}' device serve --truth silver-925 --seed 3 --stdio --inject-faults slow@{request}=1000")
}

/// Waits (up to a minute) until the session's probe plan is journaled.
fn wait_for_probe_plan(session: &Path, child: &mut Child) {
    assert!(
        wait_for(Duration::from_secs(60), || {
            assert!(child.try_wait().unwrap().is_none(), "the run ended early");
            specula_session::journal::Journal::open_read_only(session)
                .ok()
                .and_then(|j| j.plan(Stage::Probe).ok())
                .is_some_and(|p| !p.is_empty())
        }),
        "no probe plan"
    );
}

#[test]
fn a_first_ctrl_c_while_the_device_hangs_stops_within_seconds_resumably() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("h.binary");
    let session = out.with_extension("session.sqlite");
    // A 60 s reply timeout and 5 tries: 5 minutes of waiting before the stop was seen.
    let mut child = start_measure(&hanging_device(8), &out, &["--reply-timeout", "60"]);
    wait_for_probe_plan(&session, &mut child);
    std::thread::sleep(Duration::from_millis(500));
    signal(&child, "-INT");
    let stopped = Instant::now();
    let output = end_within(child, Duration::from_secs(30), "Ctrl-C on a hanging device");
    let took = stopped.elapsed();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(took < Duration::from_secs(5), "ended after {took:?}");
    assert_eq!(output.status.code(), Some(130), "{stderr}");
    let last = stderr.trim_end().lines().last().unwrap_or_default();
    assert!(
        last.starts_with("interrupted: ") && last.contains("run the same command to resume"),
        "{stderr}"
    );
    let journal = specula_session::journal::Journal::open_read_only(&session).unwrap();
    let status = journal.status().unwrap();
    assert_eq!(
        status.events.get("interrupted"),
        Some(&1),
        "{:?}",
        status.events
    );
    assert_eq!(
        status.events.get("retry"),
        None,
        "no retry after the stop: {:?}",
        status.events
    );
}

/// A slowly paced simulated run (a thousandth of real time) into `out`'s default session.
fn slow_run(out: &Path) -> Child {
    Command::new(SPECULA)
        .arg("measure")
        .args(SMALL_PLAN)
        .args(["--truth", "silver-925", "--speedup", "0.001", "--out"])
        .arg(out)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap()
}

/// `specula ARGS`' output, at most a minute.
fn run(args: &[&str], session: &Path, out: &Path) -> Output {
    let child = Command::new(SPECULA)
        .args(args)
        .arg("--session")
        .arg(session)
        .arg("--out")
        .arg(out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    end_within(child, Duration::from_secs(60), &format!("{args:?}"))
}

fn one_line_error(output: &Output, needles: &[&str]) {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    for needle in needles {
        assert!(stderr.contains(needle), "{needle}: {stderr}");
    }
}

#[test]
fn a_hard_link_does_not_get_round_the_session_lock() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.binary");
    let session = out.with_extension("session.sqlite");
    let mut first = slow_run(&out);
    wait_for_probe_plan(&session, &mut first);
    let link: PathBuf = dir.path().join("h.sqlite");
    std::fs::hard_link(&session, &link).unwrap();
    let mut args = vec!["measure", "--truth", "silver-925"];
    args.extend(SMALL_PLAN);
    let second = run(&args, &link, &dir.path().join("h.binary"));
    let _ = first.kill();
    let _ = first.wait();
    one_line_error(
        &second,
        &[&link.display().to_string(), "another specula process"],
    );
    assert!(
        !dir.path().join("h.sqlite-wal").exists(),
        "the refused run left a -wal file"
    );
}

#[test]
fn a_directory_or_a_newer_journal_is_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.binary");
    let mut args = vec!["measure", "--truth", "silver-925"];
    args.extend(SMALL_PLAN);
    let output = run(&args, dir.path(), &out);
    one_line_error(
        &output,
        &[&dir.path().display().to_string(), "is a directory"],
    );

    let session = dir.path().join("newer.sqlite");
    {
        let journal = specula_session::journal::Journal::open(&session).unwrap();
        journal
            .put_record(&specula_session::journal::NewestVersionRecord(
                "99.1.0".into(),
            ))
            .unwrap();
    }
    let output = run(&args, &session, &out);
    one_line_error(
        &output,
        &[
            &session.display().to_string(),
            "specula 99.1.0",
            &format!("specula {}", env!("CARGO_PKG_VERSION")),
        ],
    );
}
