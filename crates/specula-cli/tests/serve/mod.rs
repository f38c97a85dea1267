//! Shared by the tests that talk to the simulated device over TCP (measure.rs,
//! reliability.rs): `specula device serve` on a free port of 127.0.0.1.

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};

/// `specula device serve --truth silver-925` on 127.0.0.1 with a free port and the given
/// extra arguments and environment; returns the child and the port. The server's log is
/// drained so that it never blocks on a full pipe.
pub(crate) fn serve(extra: &[&str], env: &[(&str, &str)]) -> (Child, u16) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_specula"))
        .args([
            "device",
            "serve",
            "--truth",
            "silver-925",
            "--listen",
            "127.0.0.1:0",
        ])
        .args(extra)
        .envs(env.iter().copied())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
    let first = lines
        .next()
        .expect("the server says where it listens")
        .unwrap();
    let port = first
        .rsplit_once("127.0.0.1:")
        .and_then(|(_, rest)| rest.split_whitespace().next())
        .and_then(|p| p.parse().ok())
        .unwrap_or_else(|| panic!("no port in '{first}'"));
    std::thread::spawn(move || lines.for_each(drop));
    (child, port)
}
