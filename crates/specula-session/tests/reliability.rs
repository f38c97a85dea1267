//! The reliability promises of the driver protocol and the journal (issue 16), each tested
//! on the fault that broke it: orphaned adapters, a client locking others out, replies and
//! inputs trusted, a damaged journal. Network tests use 127.0.0.1 only; every loop is
//! bounded and every test stops by itself within seconds.

use specula_acquisition::instrument::Instrument;
use specula_session::protocol::{ClientSettings, Endpoint, RemoteInstrument};
use std::time::Duration;

/// Processes whose command line is exactly `words`, found in /proc.
fn processes_running(words: &[&str]) -> usize {
    let wanted: Vec<u8> = words
        .iter()
        .flat_map(|w| [w.as_bytes(), b"\0"].concat())
        .collect();
    std::fs::read_dir("/proc")
        .unwrap()
        .filter_map(|entry| std::fs::read(entry.ok()?.path().join("cmdline")).ok())
        .filter(|cmdline| *cmdline == wanted)
        .count()
}

#[test]
fn no_adapter_outlives_its_link_after_timeouts_and_restarts() {
    // An adapter that never answers, started by `sh -c` as a child of the shell (the shell
    // has another command after it, so it cannot exec it in its place).
    let seconds = format!("300.{}", std::process::id());
    let command = format!("sleep {seconds}; true");
    let settings = ClientSettings {
        reply_timeout: Duration::from_millis(300),
        max_failures: 3,
        backoff_initial: Duration::from_millis(1),
        ..ClientSettings::default()
    };
    let mut client = RemoteInstrument::new(Endpoint::Exec(command), settings);
    let err = client.home().unwrap_err().to_string();
    assert!(err.contains("failed 3 times"), "{err}");
    drop(client);
    // Killed processes vanish from /proc once reaped by init; give it a moment.
    let mut left = usize::MAX;
    for _ in 0..50 {
        left = processes_running(&["sleep", &seconds]);
        if left == 0 {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    assert_eq!(
        left, 0,
        "adapter processes left running after three restarts"
    );
}
