//! A command line people can trust (issue 15), one test per class of fault a user met: a
//! closed pipe, an output cut short by a kill or a full disk, a failed connection that
//! left a session behind, a device fault in the checks, and the small lies (a MERL table
//! under a .csv name, a header printed before an error, a table mostly made up without a
//! warning, a finished run's lock and WAL files left behind).
//!
//! The ranges of the numeric options and the consistency of flag names across commands are
//! checked on the whole command tree in `src/main.rs`.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

const SPECULA: &str = env!("CARGO_BIN_EXE_specula");

/// Size of a MERL .binary file: the header and three planes of 90 x 90 x 180 doubles.
const MERL_BYTES: u64 = 12 + 3 * 90 * 90 * 180 * 8;

/// A small plan on the paper's grid shape: 30 probe samples, 8 theta_h x 6 theta_d x 3 phi_d
/// (0 to 90 deg).
const SMALL: [&str; 10] = [
    "--grid-preset",
    "paper",
    "--probe-samples",
    "30",
    "--theta-h-samples",
    "8",
    "--theta-d-step",
    "15",
    "--phi-d-step",
    "45",
];

fn specula(args: &[&str]) -> Output {
    Command::new(SPECULA)
        .args(args)
        .output()
        .expect("specula runs")
}

fn ok(args: &[&str]) -> Output {
    let output = specula(args);
    assert!(
        output.status.success(),
        "specula {args:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

fn text(path: &Path) -> String {
    path.display().to_string()
}

/// A small simulated measurement of silver-925 (no checks), complete.
fn measured_session(dir: &Path) -> (PathBuf, PathBuf) {
    let out = dir.join("silver.binary");
    let mut args = vec![
        "measure",
        "--truth",
        "silver-925",
        "--skip-checks",
        "--seed",
        "3",
    ];
    args.extend(SMALL);
    let out_arg = text(&out);
    args.extend(["--out", &out_arg]);
    ok(&args);
    (out.with_extension("session.sqlite"), out)
}

#[test]
fn a_closed_pipe_ends_every_command_quietly() {
    let dir = tempfile::tempdir().unwrap();
    let d = |name: &str| text(&dir.path().join(name));
    let (session, table) = measured_session(dir.path());
    ok(&[
        "probe",
        "chrome",
        "--probe-samples",
        "40",
        "--out",
        &d("probe.csv"),
    ]);
    std::fs::write(
        dir.path().join("dirs.csv"),
        "theta_i,phi_i,theta_o,phi_o\n10,0,10,180\n20,0,20,180\n30,0,30,180\n",
    )
    .unwrap();
    let commands: Vec<Vec<String>> = [
        vec!["info", &text(&table)],
        vec!["info", "chrome"],
        vec!["materials"],
        vec!["fit-k", &d("probe.csv")],
        vec!["eval", "chrome", "--dirs", &d("dirs.csv")],
        vec!["session", "status", &text(&session)],
        vec![
            "check",
            "orientation",
            "--truth",
            "silver-925",
            "--phi-h-step",
            "45",
        ],
        vec!["plan", "--print-device"],
        vec!["plan", "--k", "4.78", "--out", &d("plan.csv")],
        vec!["probe", "steel", "--out", &d("probe2.csv")],
        vec!["tabulate", "steel", "--out", &d("steel.binary")],
        vec!["compare", &text(&table), "silver-925"],
    ]
    .iter()
    .map(|c| c.iter().map(|s| s.to_string()).collect())
    .collect();
    for args in commands {
        let mut child = Command::new(SPECULA)
            .args(&args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // The reader goes away before the first line, as `| head -0` would.
        drop(child.stdout.take());
        let mut stderr = String::new();
        child
            .stderr
            .take()
            .unwrap()
            .read_to_string(&mut stderr)
            .unwrap();
        let status = child.wait().unwrap();
        assert!(
            !stderr.contains("panicked") && !stderr.contains("Broken pipe"),
            "{args:?}: {stderr}"
        );
        #[cfg(unix)]
        let by_sigpipe = std::os::unix::process::ExitStatusExt::signal(&status) == Some(13);
        #[cfg(not(unix))]
        let by_sigpipe = false;
        assert!(
            status.success() || by_sigpipe,
            "{args:?}: {status}: {stderr}"
        );
    }
}

/// Runs `args` with a file size limit (a full disk, as far as the writer can tell, and then
/// SIGXFSZ kills it) and checks that `target` is still what it was: absent, or `old`.
fn cut_short(args: &[&str], target: &Path, old: Option<&[u8]>) {
    if let Some(old) = old {
        std::fs::write(target, old).unwrap();
    }
    let command = args
        .iter()
        .map(|a| format!("'{a}'"))
        .collect::<Vec<_>>()
        .join(" ");
    let status = Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -f 256 && exec '{SPECULA}' {command}"))
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .unwrap();
    assert!(!status.success(), "{args:?} should have run out of room");
    match old {
        Some(old) => assert_eq!(
            std::fs::read(target).unwrap(),
            old,
            "{args:?}: {}",
            text(target)
        ),
        None => assert!(!target.exists(), "{args:?} left a partial {}", text(target)),
    }
}

#[test]
fn an_output_cut_short_leaves_no_partial_file_under_its_name() {
    let dir = tempfile::tempdir().unwrap();
    let d = |name: &str| dir.path().join(name);
    let tabulated = d("t.binary");
    cut_short(
        &["tabulate", "chrome", "--out", &text(&tabulated)],
        &tabulated,
        None,
    );
    cut_short(
        &["tabulate", "chrome", "--out", &text(&tabulated)],
        &tabulated,
        Some(b"the previous table"),
    );
    let converted = d("c.bin");
    cut_short(&["convert", "steel", &text(&converted)], &converted, None);
    let csv = d("c.csv");
    cut_short(&["convert", "steel", &text(&csv)], &csv, None);
    let picture = d("r.exr");
    cut_short(
        &[
            "render",
            "chrome",
            "--size",
            "256",
            "--spp",
            "1",
            "--out",
            &text(&picture),
        ],
        &picture,
        None,
    );

    // reconstruct: from the samples of a noise-free measurement.
    let samples = d("samples.csv");
    ok(&[
        "evaluate",
        "--truth",
        "silver-925",
        "--theta-h-samples",
        "8",
        "--samples-out",
        &text(&samples),
    ]);
    let rebuilt = d("rebuilt.binary");
    cut_short(
        &[
            "reconstruct",
            "--samples-csv",
            &text(&samples),
            "--out",
            &text(&rebuilt),
        ],
        &rebuilt,
        None,
    );
    // And in full, the file is complete.
    ok(&[
        "reconstruct",
        "--samples-csv",
        &text(&samples),
        "--out",
        &text(&rebuilt),
    ]);
    assert_eq!(std::fs::metadata(&rebuilt).unwrap().len(), MERL_BYTES);
}

#[test]
fn a_kill_during_the_write_leaves_no_partial_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("t.binary");
    for _ in 0..3 {
        let mut child = Command::new(SPECULA)
            .args(["tabulate", "chrome", "--out", &text(&out)])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        // Kill as soon as anything appears in the folder: a temporary file, or (written in
        // place) the target itself.
        loop {
            let appeared = std::fs::read_dir(dir.path()).unwrap().next().is_some();
            if appeared || child.try_wait().unwrap().is_some() {
                break;
            }
            std::thread::sleep(std::time::Duration::from_micros(200));
        }
        let _ = child.kill();
        child.wait().unwrap();
        if let Ok(meta) = std::fs::metadata(&out) {
            assert_eq!(meta.len(), MERL_BYTES, "a partial table under its name");
        }
        for entry in std::fs::read_dir(dir.path()).unwrap() {
            std::fs::remove_file(entry.unwrap().path()).unwrap();
        }
    }
}

#[test]
fn a_failed_connection_creates_no_session() {
    let dir = tempfile::tempdir().unwrap();
    let calibration = dir.path().join("cal.toml");
    ok(&[
        "calibrate",
        "--truth",
        "silver-925",
        "--out",
        &text(&calibration),
    ]);
    let out = dir.path().join("m1.binary");
    let output = specula(&[
        "measure",
        "--connect",
        "tcp://127.0.0.1:9",
        "--calibration",
        &text(&calibration),
        "--reply-timeout",
        "1",
        "--max-failures",
        "1",
        "--out",
        &text(&out),
    ]);
    assert_eq!(output.status.code(), Some(1));
    let left: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.starts_with("m1"))
        .collect();
    assert!(left.is_empty(), "left behind: {left:?}");
}

/// `measure` through a child process serving the simulated device, with `faults` injected.
fn measure_with_faults(dir: &Path, name: &str, faults: &str) -> Output {
    let calibration = dir.join("cal.toml");
    if !calibration.exists() {
        ok(&[
            "calibrate",
            "--truth",
            "silver-925",
            "--seed",
            "3",
            "--out",
            &text(&calibration),
        ]);
    }
    let connect = format!(
        "exec:'{SPECULA}' device serve --truth silver-925 --seed 3 --stdio --inject-faults {faults}"
    );
    let out = dir.join(format!("{name}.binary"));
    let (calibration, out) = (text(&calibration), text(&out));
    let mut args = vec![
        "measure",
        "--connect",
        &connect,
        "--calibration",
        &calibration,
    ];
    args.extend(SMALL);
    args.extend(["--out", &out]);
    specula(&args)
}

#[test]
fn a_fault_in_the_checks_is_retried_and_a_check_that_cannot_run_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    // Request 10 falls in the alignment check (after hello, two infos and the homing).
    let output = measure_with_faults(dir.path(), "one", "motor@10");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(stdout.contains("events_fault=1"), "{stdout}");
    assert!(!stdout.contains("alignment=not done"), "{stdout}");

    let every: Vec<String> = (10..200).map(|n| format!("motor@{n}")).collect();
    let output = measure_with_faults(dir.path(), "every", &every.join(","));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("alignment check"), "{stderr}");
}

#[test]
fn small_lies_are_gone() {
    let dir = tempfile::tempdir().unwrap();
    let d = |name: &str| dir.path().join(name);

    // The format follows the extension: a MERL table is not written under a .csv name.
    let output = specula(&["tabulate", "chrome", "--out", &text(&d("r.csv"))]);
    assert_eq!(output.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&output.stderr).contains(".binary"));
    assert!(!d("r.csv").exists());

    // eval checks every row before printing anything.
    std::fs::write(
        d("dirs.csv"),
        "theta_i,phi_i,theta_o,phi_o\n10,0,10,180\n-30,0,1,1\n",
    )
    .unwrap();
    let output = specula(&["eval", "chrome", "--dirs", &text(&d("dirs.csv"))]);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        output.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&output.stdout)
    );
    assert!(String::from_utf8_lossy(&output.stderr).contains("row 3: theta_i -30"));

    // A table rebuilt from one sample is mostly made up, and says so.
    std::fs::write(
        d("one.csv"),
        "theta_h,phi_h,theta_d,phi_d,r,g,b\n1,45,30,90,2,2,2\n",
    )
    .unwrap();
    let output = ok(&[
        "reconstruct",
        "--samples-csv",
        &text(&d("one.csv")),
        "--out",
        &text(&d("one.binary")),
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("warning:") && stderr.contains("extrapolated"),
        "{stderr}"
    );

    // fit-k on a probe of zeros has nothing to fit; on a MERL file it says what it wants.
    std::fs::write(d("zero.csv"), "theta_h,r,g,b\n0,0,0,0\n1,0,0,0\n5,0,0,0\n").unwrap();
    let output = specula(&["fit-k", &text(&d("zero.csv"))]);
    assert_eq!(output.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&output.stderr).contains("every value of the probe is 0"));
    ok(&["tabulate", "steel", "--out", &text(&d("steel.binary"))]);
    let output = specula(&["fit-k", &text(&d("steel.binary"))]);
    assert!(String::from_utf8_lossy(&output.stderr).contains("wants a probe CSV"));

    // A near name is suggested.
    let output = specula(&["info", "paint-red"]);
    assert!(String::from_utf8_lossy(&output.stderr).contains("paint-red-gloss"));
    assert!(output.stdout.is_empty(), "nothing printed before the error");

    // info reads any source, here an RGL-like continuous fit and a samples file.
    let info = ok(&["info", "sgd:chrome-steel"]);
    assert!(String::from_utf8_lossy(&info.stdout).contains("peak within 75 deg:"));
    let info = ok(&["info", &text(&d("one.csv"))]);
    assert!(String::from_utf8_lossy(&info.stdout).contains("format: samples .csv"));
}

#[test]
fn a_finished_run_leaves_only_its_journal() {
    let dir = tempfile::tempdir().unwrap();
    let (session, table) = measured_session(dir.path());
    ok(&["session", "status", &text(&session)]);
    ok(&[
        "reconstruct",
        "--session",
        &text(&session),
        "--out",
        &text(&dir.path().join("again.binary")),
    ]);
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    for name in &names {
        assert!(
            !name.ends_with(".lock") && !name.ends_with("-wal") && !name.ends_with("-shm"),
            "left behind: {names:?}"
        );
    }
    // The peak of a reconstruction is among the cells a sample fell in.
    let info = ok(&["info", &text(&table)]);
    assert!(
        String::from_utf8_lossy(&info.stdout).contains("among the cells a sample fell in"),
        "{}",
        String::from_utf8_lossy(&info.stdout)
    );
    // The status gives the progress bar's estimate, in words, and no internal names.
    let status = ok(&["session", "status", &text(&session)]);
    let status = String::from_utf8_lossy(&status.stdout);
    assert!(
        status.contains("order optimized, hdr predicted"),
        "{status}"
    );
    assert!(status.contains("state: complete"), "{status}");
}

/// Runs `specula demo ARGS` until a line of its progress starts with `until` (then kills it)
/// or it ends; returns the progress read.
fn demo_until(args: &[&str], until: &str) -> String {
    use std::io::BufRead;
    let mut child = Command::new(SPECULA)
        .arg("demo")
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut progress = String::new();
    let mut lines = std::io::BufReader::new(child.stderr.take().unwrap()).lines();
    for line in lines.by_ref() {
        let line = line.unwrap();
        progress.push_str(&line);
        progress.push('\n');
        if line.starts_with(until) {
            let _ = child.kill();
            break;
        }
    }
    child.wait().unwrap();
    progress
}

#[test]
fn another_seed_after_a_first_demo_is_another_measurement() {
    // The first demo's silver-925 session exists (journal with its probe) when the second
    // starts; `demo --seed 2` once refused it with "use another --session", an option demo
    // does not have. Each run is stopped once it has its probe, to keep the test short.
    let dir = tempfile::tempdir().unwrap();
    let out = text(dir.path());
    let first = demo_until(&["--out", &out], "probe:");
    assert!(
        first.contains("probe:"),
        "the first demo did not reach its probe: {first}"
    );
    let journal = |d: &Path| d.join("silver-925").join("silver-925.session.sqlite");
    assert!(journal(dir.path()).exists(), "{first}");
    let second = demo_until(&["--out", &out, "--seed", "2"], "probe:");
    assert!(
        second.contains("probe:") && !second.contains("error"),
        "demo --seed 2 after a first demo: {second}"
    );
    assert!(journal(&dir.path().join("seed-2")).exists(), "{second}");
}
