//! `specula measure`, `specula session status` and `specula device serve` as a user runs
//! them: interrupted by kill -9 and by Ctrl-C and resumed to the same bytes, and through the
//! driver protocol over TCP (loopback) and a child process to the same bytes as the
//! simulator in process. Small plans keep these quick; the paper-size run is in docs/book/src/plan.md.

mod serve;
mod small_plan;

use serve::serve;
use small_plan::measure_args;
use specula_session::journal::Journal;
use specula_session::Stage;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

const SPECULA: &str = env!("CARGO_BIN_EXE_specula");

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
fn done(session: &Path, stage: Stage) -> usize {
    Journal::open_read_only(session)
        .ok()
        .and_then(|j| j.samples(stage).ok())
        .map_or(0, |s| s.len())
}

/// Waits (at most a minute) until the stage has at least `count` samples.
fn wait_for(child: &mut Child, session: &Path, stage: Stage, count: usize) {
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
    for stage in [Stage::Probe, Stage::Main] {
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
    let planned = journal.plan(Stage::Main).unwrap().len();
    let partial = journal.samples(Stage::Main).unwrap().len();
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
    wait_for(&mut child, &session, Stage::Main, 2);
    let interrupt = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(interrupt.success());
    let output = child.wait_with_output().unwrap();
    assert_eq!(
        output.status.code(),
        Some(130),
        "a stopped run is no finished one: {:?}",
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

#[test]
fn the_default_grid_measures_both_halves_of_phi_d_and_reconstructs_them_apart() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("halves.binary");
    // The recommended grid's shape (graded theta_d, phi_d over the half turn), small.
    let args: Vec<String> = [
        "measure",
        "--truth",
        "green-paint",
        "--skip-checks",
        "--ideal",
        "--probe-samples",
        "30",
        "--theta-h-samples",
        "6",
        "--theta-d-step",
        "15:5@60",
        "--phi-d-step",
        "45",
        "--out",
    ]
    .iter()
    .map(|s| s.to_string())
    .chain([out.display().to_string()])
    .collect();
    let stdout = String::from_utf8_lossy(&run(&args).stdout).into_owned();
    let grid = "6 theta_h, theta_d step 15 deg (5 deg from 60), phi_d step 45 deg over 0-180 \
                (both halves), phi_h 45 deg";
    assert!(stdout.contains(&format!("grid: {grid}\n")), "{stdout}");
    assert!(stdout.contains(&format!("grid={grid}\n")), "{stdout}");
    assert!(stdout.contains("phi_d_halves=true\n"), "{stdout}");
    assert!(
        stdout.contains(&format!("planned_samples={}\n", 6 * 10 * 5)),
        "{stdout}"
    );
    let journal = Journal::open_read_only(&session_of(&out)).unwrap();
    let beyond_90 = journal
        .plan(Stage::Main)
        .unwrap()
        .iter()
        .filter(|row| row.hd.phi_d.to_degrees() > 91.0)
        .count();
    assert!(beyond_90 > 0);
    drop(journal);
    let status = Command::new(SPECULA)
        .args(["session", "status"])
        .arg(session_of(&out))
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&status.stdout);
    assert!(text.contains(&format!("grid: {grid}\n")), "{text}");
}

/// A settings record as a journal written before the graded theta_d and the half turn of
/// phi_d kept it: without their keys.
struct OldSettings(serde_json::Value);

impl serde::Serialize for OldSettings {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.0.serialize(s)
    }
}

impl specula_session::journal::Record for OldSettings {
    const KEY: &'static str = "settings";
}

#[test]
fn an_old_journal_resumes_on_its_own_grid_with_the_same_command() {
    use specula_core::grid::{GridSpec, ThetaDSteps};
    use specula_session::workflow::{measure, MeasureSettings, Quiet, Source};
    use std::sync::atomic::AtomicBool;
    use std::sync::Arc;

    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("old.binary");
    // Started (and stopped at once) as before issue 20: the small plan on the paper's grid,
    // the settings record without the new keys.
    let settings = MeasureSettings {
        seed: 3,
        probe_samples: 30,
        checks: false,
        grid: GridSpec {
            theta_h_samples: 8,
            theta_d: ThetaDSteps::even(15.0),
            phi_d_step_deg: 30.0,
            ..GridSpec::paper()
        },
        ..MeasureSettings::default()
    };
    let truth = specula_formats::source::load_brdf("silver-925").unwrap();
    measure(
        Source::Simulated {
            truth,
            speedup: None,
        },
        &specula_acquisition::device::Device::utia(),
        &settings,
        None,
        &session_of(&out),
        &out,
        Arc::new(AtomicBool::new(true)),
        &mut Quiet,
    )
    .unwrap();
    let mut old = serde_json::to_value(&settings).unwrap();
    let keys = old.as_object_mut().unwrap();
    assert!(keys.remove("theta_d_grazing").is_some() && keys.remove("phi_d_span").is_some());
    Journal::open(&session_of(&out))
        .unwrap()
        .put_record(&OldSettings(old))
        .unwrap();

    // The command of then, without --grid-preset: it resumes on the paper's quarter.
    let then: Vec<String> = measure_args(&out, &["--truth", "silver-925"])
        .into_iter()
        .filter(|a| a != "--grid-preset" && a != "paper")
        .collect();
    let stdout = String::from_utf8_lossy(&run(&then).stdout).into_owned();
    assert!(
        stdout.contains(
            "grid: 8 theta_h, theta_d step 15 deg, phi_d step 30 deg over 0-90, phi_h 45 deg"
        ),
        "{stdout}"
    );
    assert!(
        stdout.contains(&format!("planned_samples={}\n", 8 * 6 * 4)),
        "{stdout}"
    );
    assert!(stdout.contains("phi_d_halves=false\n"), "{stdout}");
}
