//! `specula measure`, `specula session status` and `specula device serve` as a user runs
//! them: interrupted by kill -9 and by Ctrl-C and resumed to the same bytes, and through the
//! driver protocol over TCP (loopback) and a child process to the same bytes as the
//! simulator in process. Small plans keep these quick; the paper-size run is in the README.

mod serve;

use serve::serve;
use specula_session::journal::Journal;
use specula_session::workflow::{STAGE_MAIN, STAGE_PROBE};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

const SPECULA: &str = env!("CARGO_BIN_EXE_specula");

/// A small plan: 30 probe samples, 8 theta_h x 6 theta_d x 4 phi_d.
const SMALL: [&str; 8] = [
    "--probe-samples",
    "30",
    "--theta-h-samples",
    "8",
    "--theta-d-step",
    "15",
    "--phi-d-step",
    "30",
];

/// `measure` with the small plan, seed 3 unless `extra` gives one, and `extra`.
fn measure_args(out: &Path, extra: &[&str]) -> Vec<String> {
    let mut args: Vec<String> = ["measure", "--skip-checks"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    args.extend(SMALL.iter().map(|s| s.to_string()));
    if !extra.contains(&"--seed") {
        args.extend(["--seed".to_string(), "3".to_string()]);
    }
    args.extend(extra.iter().map(|s| s.to_string()));
    args.push("--out".into());
    args.push(out.display().to_string());
    args
}

fn run(args: &[String]) -> Output {
    let output = Command::new(SPECULA)
        .args(args)
        .output()
        .expect("run specula");
    assert!(
        output.status.success(),
        "specula {args:?} failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

fn session_of(out: &Path) -> PathBuf {
    out.with_extension("session.sqlite")
}

/// Samples of a stage in the journal, read while another process may write it.
fn done(session: &Path, stage: &str) -> usize {
    Journal::open_read_only(session)
        .ok()
        .and_then(|j| j.samples(stage).ok())
        .map_or(0, |s| s.len())
}

/// Waits (at most a minute) until the stage has at least `count` samples.
fn wait_for(child: &mut Child, session: &Path, stage: &str, count: usize) {
    let start = Instant::now();
    while done(session, stage) < count {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before {count} {stage} samples"
        );
        assert!(start.elapsed() < Duration::from_secs(60), "no progress");
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// The uninterrupted run's table.
fn reference(dir: &Path) -> Vec<u8> {
    let out = dir.join("reference.binary");
    run(&measure_args(&out, &["--truth", "silver-925"]));
    std::fs::read(&out).unwrap()
}

#[test]
fn kill_9_in_the_probe_and_in_the_main_stage_then_resume_to_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let expected = reference(dir.path());
    let out = dir.path().join("killed.binary");
    let session = session_of(&out);
    // Paced at 100x real time so that there is a run to interrupt.
    let paced = measure_args(&out, &["--truth", "silver-925", "--speedup", "100"]);
    for stage in [STAGE_PROBE, STAGE_MAIN] {
        let mut child = Command::new(SPECULA)
            .args(&paced)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let before = done(&session, stage);
        wait_for(&mut child, &session, stage, before + 3);
        child.kill().unwrap(); // SIGKILL
        child.wait().unwrap();
        let after = done(&session, stage);
        assert!(after >= before + 3, "{stage}: {before} -> {after}");
        assert!(!out.exists(), "no table from an interrupted run");
    }
    let journal = Journal::open_read_only(&session).unwrap();
    let planned = journal.plan(STAGE_MAIN).unwrap().len();
    let partial = journal.samples(STAGE_MAIN).unwrap().len();
    assert!(partial > 0 && partial < planned, "{partial} of {planned}");
    drop(journal);

    let output = run(&measure_args(&out, &["--truth", "silver-925"]));
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        stdout.contains(&format!("measured_samples={planned}")),
        "{stdout}"
    );
    assert_eq!(
        std::fs::read(&out).unwrap(),
        expected,
        "resumed table = uninterrupted table"
    );

    // Every planned sample exactly once; the resumption is on record.
    let journal = Journal::open_read_only(&session).unwrap();
    let status = journal.status().unwrap();
    for stage in &status.stages {
        assert_eq!(stage.done, stage.planned, "{stage:?}");
    }
    assert!(
        status.events.get("resumed").copied().unwrap_or(0) >= 1,
        "{:?}",
        status.events
    );

    let status = Command::new(SPECULA)
        .args(["session", "status"])
        .arg(&session)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&status.stdout);
    assert!(
        text.contains(&format!("main: {planned} of {planned} samples")),
        "{text}"
    );
    assert!(text.contains("state: complete"), "{text}");
}

#[test]
fn ctrl_c_finishes_the_sample_then_stops_resumably() {
    let dir = tempfile::tempdir().unwrap();
    let expected = reference(dir.path());
    let out = dir.path().join("interrupted.binary");
    let session = session_of(&out);
    let mut child = Command::new(SPECULA)
        .args(measure_args(
            &out,
            &["--truth", "silver-925", "--speedup", "100"],
        ))
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    wait_for(&mut child, &session, STAGE_MAIN, 2);
    let interrupt = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(interrupt.success());
    let output = child.wait_with_output().unwrap();
    assert!(
        output.status.success(),
        "a clean stop exits 0: {:?}",
        output.status
    );
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        stdout.contains("stopped: main") && stdout.contains("run the same command to resume"),
        "{stdout}"
    );
    let events = Journal::open_read_only(&session)
        .unwrap()
        .status()
        .unwrap()
        .events;
    assert_eq!(events.get("interrupted"), Some(&1), "{events:?}");

    run(&measure_args(&out, &["--truth", "silver-925"]));
    assert_eq!(std::fs::read(&out).unwrap(), expected);
}

/// The calibration `specula calibrate` measures on the simulated device with seed 3: the
/// one the in-process run measures for itself.
fn calibration(dir: &Path) -> PathBuf {
    let path = dir.join("calibration.toml");
    run(&[
        "calibrate".into(),
        "--truth".into(),
        "silver-925".into(),
        "--seed".into(),
        "3".into(),
        "--out".into(),
        path.display().to_string(),
    ]);
    path
}

#[test]
fn the_driver_protocol_over_tcp_and_exec_gives_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let expected = reference(dir.path());
    let calibration = calibration(dir.path());
    let calibration = calibration.display().to_string();

    // TCP, with a dropped connection and a motor fault on the way.
    let (mut server, port) = serve(&["--seed", "3", "--inject-faults", "drop@30,motor@61"], &[]);
    let out = dir.path().join("tcp.binary");
    let device = format!("tcp://127.0.0.1:{port}");
    let output = run(&measure_args(
        &out,
        &[
            "--connect",
            &device,
            "--calibration",
            &calibration,
            "--reply-timeout",
            "5",
        ],
    ));
    server.kill().unwrap();
    server.wait().unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    for event in [
        "events_retry=1",
        "events_reconnect=1",
        "events_redo=1",
        "events_fault=1",
        "events_recovered=2",
    ] {
        assert!(stdout.contains(event), "{event}: {stdout}");
    }
    assert!(
        stdout.contains("simulated_hours="),
        "the served clock crosses the wire: {stdout}"
    );
    let tcp = std::fs::read(&out).unwrap();

    // A child process speaking the protocol on stdin and stdout.
    let out = dir.path().join("exec.binary");
    let device = format!("exec:{SPECULA} device serve --truth silver-925 --seed 3 --stdio");
    run(&measure_args(
        &out,
        &["--connect", &device, "--calibration", &calibration],
    ));
    let exec = std::fs::read(&out).unwrap();

    // A drop comes before the device acts, and after it (a new link) as after the motor
    // fault the engine homes and measures the sample again from its move: the simulator's
    // noise is keyed by the capture since the last move, so all three tables are the same.
    assert_eq!(tcp, expected, "over TCP = in process");
    assert_eq!(exec, expected, "over exec = in process");
}

#[test]
fn bad_arguments_get_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.binary");
    let fails = |args: &[String], needle: &str| {
        let output = Command::new(SPECULA).args(args).output().unwrap();
        assert_eq!(output.status.code(), Some(1), "{args:?}");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
        assert!(stderr.contains(needle), "{needle}: {stderr}");
    };
    fails(
        &measure_args(&out, &["--connect", "tcp://127.0.0.1:9"]),
        "--calibration",
    );
    fails(
        &measure_args(&out, &["--connect", "serial:/dev/ttyUSB0"]),
        "tcp://HOST:PORT or exec:COMMAND",
    );
    fails(
        &measure_args(&out, &["--truth", "no-such-material"]),
        "no-such-material",
    );
    let magic = Command::new(SPECULA)
        .args(measure_args(
            &out,
            &["--truth", "silver-925", "--method", "magic"],
        ))
        .output()
        .unwrap();
    assert_eq!(magic.status.code(), Some(2), "a usage error");
    assert!(String::from_utf8_lossy(&magic.stderr).contains("magic"));
    let session = dir.path().join("s.sqlite");
    let session_arg = session.display().to_string();
    // A session belongs to one measurement.
    let first = measure_args(&out, &["--truth", "silver-925", "--session", &session_arg]);
    let _ = Command::new(SPECULA).args(&first).output().unwrap();
    fails(
        &measure_args(
            &out,
            &[
                "--truth",
                "silver-925",
                "--session",
                &session_arg,
                "--seed",
                "4",
            ],
        ),
        "other settings",
    );
    let text = dir.path().join("notes.sqlite");
    std::fs::write(&text, "not a database").unwrap();
    let output = Command::new(SPECULA)
        .args(["session", "status"])
        .arg(&text)
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&output.stderr).contains("notes.sqlite"));
    let output = Command::new(SPECULA)
        .args([
            "device",
            "serve",
            "--truth",
            "silver-925",
            "--listen",
            "0.0.0.0:7878",
        ])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&output.stderr).contains("--token"));
}
