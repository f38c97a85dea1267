//! `device serve` cannot be locked before anyone authenticates: with 8 hostile connections
//! open (silent ones, and ones sending 60 MB without a newline, each reopened as soon as the
//! server drops it), a client that sends a good `hello` is answered within 2 s and the
//! server's memory stays bounded. Loopback only; 8 hostile connections for about 6 s.

use specula_acquisition::instrument::{Capture, Instrument, InstrumentError, InstrumentInfo};
use specula_acquisition::kinematics::AxisPositions;
use specula_session::protocol::Server;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A device that answers nothing but `hello` in this test.
struct Idle;

impl Instrument for Idle {
    fn home(&mut self) -> Result<AxisPositions, InstrumentError> {
        Ok(AxisPositions::new(0.0, 0.0, 0.0, 0.0))
    }
    fn move_to(&mut self, target: &AxisPositions) -> Result<AxisPositions, InstrumentError> {
        Ok(*target)
    }
    fn set_light(&mut self, _: f64) -> Result<(), InstrumentError> {
        Ok(())
    }
    fn capture(&mut self, _: f64, _: bool) -> Result<Capture, InstrumentError> {
        Err(InstrumentError::CameraFault("no camera".into()))
    }
    fn info(&mut self) -> Result<InstrumentInfo, InstrumentError> {
        Err(InstrumentError::CameraFault("no camera".into()))
    }
}

/// One hostile connection after another until `until`: silent ones wait for the server to
/// drop them; the others send 60 MB without a newline (or until the server drops them).
fn hostile(port: u16, silent: bool, until: Instant) {
    let chunk = vec![b'x'; 64 << 10];
    while Instant::now() < until {
        let Ok(mut stream) = TcpStream::connect(("127.0.0.1", port)) else {
            std::thread::sleep(Duration::from_millis(20));
            continue;
        };
        let _ = stream.set_read_timeout(Some(Duration::from_millis(200)));
        let _ = stream.set_write_timeout(Some(Duration::from_millis(200)));
        if silent {
            let mut byte = [0u8; 1];
            while Instant::now() < until {
                match stream.read(&mut byte) {
                    Ok(0) => break,
                    Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => continue,
                    Err(e) if e.kind() == std::io::ErrorKind::TimedOut => continue,
                    _ => break,
                }
            }
        } else {
            let mut sent = 0usize;
            while sent < 60 << 20 && Instant::now() < until {
                match stream.write(&chunk) {
                    Ok(n) => sent += n,
                    Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => continue,
                    Err(e) if e.kind() == std::io::ErrorKind::TimedOut => continue,
                    Err(_) => break,
                }
            }
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// How long a good `hello` takes to be answered, if it is answered with a result.
fn good_hello(port: u16) -> Result<Duration, String> {
    let start = Instant::now();
    let mut stream = TcpStream::connect(("127.0.0.1", port)).map_err(|e| e.to_string())?;
    stream
        .set_read_timeout(Some(Duration::from_secs(5)))
        .unwrap();
    stream
        .write_all(b"{\"id\":1,\"method\":\"hello\",\"params\":{\"protocol\":1}}\n")
        .map_err(|e| e.to_string())?;
    let mut line = String::new();
    BufReader::new(stream)
        .read_line(&mut line)
        .map_err(|e| e.to_string())?;
    if line.contains("\"result\"") {
        Ok(start.elapsed())
    } else {
        Err(format!("not answered: {line:?}"))
    }
}

/// The most memory this process has held, MiB (`VmHWM`).
fn peak_rss_mib() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
        .map_or(0.0, |kib| kib / 1024.0)
}

#[test]
fn a_good_client_gets_in_while_eight_hostile_connections_are_open() {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    let stop = Arc::new(AtomicBool::new(false));
    let server_stop = stop.clone();
    let server = std::thread::spawn(move || {
        let mut server = Server::new(Box::new(Idle), "idle");
        server
            .serve_tcp(
                &listener,
                &server_stop,
                Duration::from_secs(600),
                &mut |_| {},
            )
            .unwrap();
    });
    let until = Instant::now() + Duration::from_secs(6);
    let attackers: Vec<_> = (0..8)
        .map(|i| std::thread::spawn(move || hostile(port, i % 2 == 0, until)))
        .collect();
    std::thread::sleep(Duration::from_millis(500));
    let mut answered = Vec::new();
    while Instant::now() + Duration::from_secs(1) < until {
        let took = good_hello(port);
        answered.push(took.clone());
        std::thread::sleep(Duration::from_millis(300));
    }
    for attacker in attackers {
        attacker.join().unwrap();
    }
    stop.store(true, Ordering::SeqCst);
    server.join().unwrap();
    assert!(answered.len() >= 10, "{answered:?}");
    for took in &answered {
        match took {
            Ok(took) => assert!(*took < Duration::from_secs(2), "{answered:?}"),
            Err(why) => panic!("a good hello was refused: {why} ({answered:?})"),
        }
    }
    let peak = peak_rss_mib();
    assert!(peak < 200.0, "peak memory {peak:.0} MiB");
}
