//! The server side of the driver protocol: any [`Instrument`] served over TCP or over a pair
//! of streams (a program's stdin and stdout).
//!
//! A device does one thing at a time, so one client controls it: the first to authenticate
//! (`hello`, with the token when one is set). Over TCP every connection has a thread of its
//! own, so a client that connects and says nothing never keeps others from being answered:
//! - a newcomer must authenticate within [`ServeLimits::auth`], or it is disconnected (the
//!   deadline is for the whole `hello`, however it is dripped), and its line may be at most
//!   [`MAX_HELLO_BYTES`] long; an authenticated client's request lines at most
//!   [`MAX_REQUEST_BYTES`]: a connection holds at most that much of a line in memory;
//! - a newcomer that authenticates while another client controls the device waits up to
//!   [`ServeLimits::control_wait`] for it to disconnect (a client that gave up on a slow
//!   reply and reconnects finds its old connection closing), then is answered with the
//!   error kind `busy` and disconnected (Specula's client retries later);
//! - the controlling client must complete each request line within [`ServeLimits::idle`] of
//!   the previous reply (a client dripping a byte at a time is cut off too), and every reply
//!   must be written within [`ServeLimits::write`] (a client that never reads is cut off);
//! - at most [`ServeLimits::max_connections`] connections are open at once, and
//!   [`ServeLimits::reserve`] more for newcomers that authenticate within
//!   [`ServeLimits::reserve_auth`] (a client sends its `hello` as soon as it connects): silent
//!   or hostile connections holding every ordinary slot do not keep a real client out;
//! - after a failed authentication is answered, its connection holds the server's
//!   failed-authentication lock for [`ServeLimits::failed_auth_pause`] before closing, so
//!   failures are answered one per pause at most: guessing the token is slow.

use super::faults::{Fault, FaultSchedule};
use super::message::{
    CaptureParams, HelloParams, HelloResult, LightParams, MoveParams, Reply, Request, WireError,
    PROTOCOL_VERSION,
};
use serde::de::DeserializeOwned;
use serde_json::{json, Value};
use specula_acquisition::instrument::{Instrument, InstrumentError};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// The longest line a newcomer may send before it is authenticated, bytes (a `hello` with a
/// long token is well under it).
pub const MAX_HELLO_BYTES: u64 = 16 << 10;

/// The longest request line of an authenticated client, bytes (requests carry a few
/// numbers; replies, which may carry pixels, are bounded by
/// [`MAX_LINE_BYTES`](super::message::MAX_LINE_BYTES)).
pub const MAX_REQUEST_BYTES: u64 = 64 << 10;

/// A shared secret clients send in `hello`: never empty (an empty token would let a `hello`
/// without one through).
#[derive(Clone, PartialEq, Eq)]
pub struct Token(String);

/// Why a token cannot be used.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TokenError {
    /// The token is empty or only whitespace.
    #[error("the token is empty: give a secret of at least one non-blank character")]
    Empty,
}

impl Token {
    /// A token; surrounding whitespace (a newline at the end of a token file) is removed.
    pub fn new(secret: &str) -> Result<Token, TokenError> {
        let secret = secret.trim();
        if secret.is_empty() {
            return Err(TokenError::Empty);
        }
        Ok(Token(secret.to_string()))
    }

    /// The secret itself.
    pub fn secret(&self) -> &str {
        &self.0
    }
}

impl std::fmt::Debug for Token {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Token(..)")
    }
}

/// How long a TCP client may take, and how many may be connected.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServeLimits {
    /// The controlling client's time to complete a request line after the previous reply.
    pub idle: Duration,
    /// A newcomer's time to authenticate.
    pub auth: Duration,
    /// How long an authenticated newcomer waits for the controlling client to disconnect.
    pub control_wait: Duration,
    /// The time to write one reply.
    pub write: Duration,
    /// Connections open at once, beyond the reserve.
    pub max_connections: usize,
    /// Slots beyond `max_connections` for newcomers that authenticate within
    /// `reserve_auth`; when these are taken too, newcomers are answered `busy` and closed.
    pub reserve: usize,
    /// A newcomer's time to authenticate on a reserve slot.
    pub reserve_auth: Duration,
    /// How long a failed authentication holds the server's failed-authentication lock after
    /// its reply (the next failure is answered only after it).
    pub failed_auth_pause: Duration,
}

impl Default for ServeLimits {
    fn default() -> Self {
        Self {
            idle: Duration::from_secs(600),
            auth: Duration::from_secs(3),
            control_wait: Duration::from_secs(10),
            write: Duration::from_secs(30),
            max_connections: 8,
            reserve: 4,
            reserve_auth: Duration::from_secs(1),
            failed_auth_pause: Duration::from_secs(1),
        }
    }
}

/// The device and its fault schedule, used by one connection at a time.
struct Device {
    instrument: Box<dyn Instrument>,
    faults: FaultSchedule,
    /// Requests received over the server's life.
    requests: u64,
}

/// What every connection shares.
struct Shared {
    device: Mutex<Device>,
    name: String,
    token: Option<Token>,
    limits: ServeLimits,
    /// Who controls the device now (a peer's address), if anyone.
    controller: Mutex<Option<String>>,
    /// Held while a failed authentication waits.
    failed_auth: Mutex<()>,
}

/// Serves one instrument.
pub struct Server {
    shared: Arc<Shared>,
}

/// How a connection ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ConnectionEnd {
    /// The client closed it.
    ClientClosed,
    /// An injected [`Fault::Drop`].
    Dropped,
    /// The client failed `hello` (wrong token or protocol version), or another client
    /// controls the device.
    Refused(String),
    /// Reading or writing failed, or the client took too long (a timeout of [`ServeLimits`]).
    Broken(String),
}

impl std::fmt::Display for ConnectionEnd {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::ClientClosed => write!(f, "the client closed the connection"),
            Self::Dropped => write!(f, "connection dropped (an injected fault)"),
            Self::Refused(why) => write!(f, "client refused: {why}"),
            Self::Broken(why) => write!(f, "connection broken: {why}"),
        }
    }
}

/// What to do after a request.
enum Next {
    Continue,
    Close(ConnectionEnd),
}

/// Locks a mutex even if a thread panicked while holding it (the device state stays usable:
/// every request is complete or not started).
fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

impl Server {
    /// A server named `name` (reported by `hello`).
    pub fn new(instrument: Box<dyn Instrument>, name: impl Into<String>) -> Self {
        Self {
            shared: Arc::new(Shared {
                device: Mutex::new(Device {
                    instrument,
                    faults: FaultSchedule::new(),
                    requests: 0,
                }),
                name: name.into(),
                token: None,
                limits: ServeLimits::default(),
                controller: Mutex::new(None),
                failed_auth: Mutex::new(()),
            }),
        }
    }

    fn shared_mut(&mut self) -> &mut Shared {
        Arc::get_mut(&mut self.shared).expect("configured before serving")
    }

    /// Requires `hello` with this shared token on every connection.
    pub fn with_token(mut self, token: Option<Token>) -> Self {
        self.shared_mut().token = token;
        self
    }

    /// Injects faults (see [`FaultSchedule`]).
    pub fn with_faults(mut self, faults: FaultSchedule) -> Self {
        lock(&self.shared_mut().device).faults = faults;
        self
    }

    /// Sets the TCP limits (see [`ServeLimits`]; `idle` is [`Server::serve_tcp`]'s).
    pub fn with_limits(mut self, limits: ServeLimits) -> Self {
        self.shared_mut().limits = limits;
        self
    }

    /// Requests received so far.
    pub fn requests(&self) -> u64 {
        lock(&self.shared.device).requests
    }

    /// Serves one connection on a pair of streams (stdin and stdout) until the client closes
    /// it, a fault drops it or it breaks. No timeouts: a pipe's other end is our parent.
    pub fn serve_connection<R: Read, W: Write>(&mut self, reader: R, writer: W) -> ConnectionEnd {
        let auth = self.shared.limits.auth;
        let mut connection = Connection::new(&self.shared, "stdio".into(), auth);
        connection.serve(BufReader::new(Untimed(reader)), writer)
    }

    /// Accepts connections on `listener` until `stop` is set (checked every 20 ms), each in
    /// a thread of its own, with the limits of [`ServeLimits`] and `idle` for the
    /// controlling client; on stop, the open connections are shut down too. `log` hears how
    /// each connection ended.
    pub fn serve_tcp(
        &mut self,
        listener: &TcpListener,
        stop: &AtomicBool,
        idle: Duration,
        log: &mut dyn FnMut(String),
    ) -> std::io::Result<()> {
        self.shared_mut().limits.idle = idle;
        listener.set_nonblocking(true)?;
        let open = Arc::new(OpenConnections::default());
        let (log_sender, log_lines) = mpsc::channel::<String>();
        while !stop.load(Ordering::SeqCst) {
            while let Ok(line) = log_lines.try_recv() {
                log(line);
            }
            let (stream, peer) = match listener.accept() {
                Ok(accepted) => accepted,
                Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                    std::thread::sleep(Duration::from_millis(20));
                    continue;
                }
                Err(e) => {
                    log(format!("accept failed: {e}"));
                    std::thread::sleep(Duration::from_millis(20));
                    continue;
                }
            };
            let peer = peer.to_string();
            if let Err(e) = self.start_connection(stream, peer.clone(), &open, &log_sender) {
                log(format!("{peer}: cannot serve: {e}"));
            }
        }
        for stream in lock(&open.streams).values() {
            let _ = stream.shutdown(std::net::Shutdown::Both);
        }
        while let Ok(line) = log_lines.try_recv() {
            log(line);
        }
        Ok(())
    }

    /// Serves an accepted connection in its own thread, or refuses it when too many are open.
    fn start_connection(
        &self,
        stream: TcpStream,
        peer: String,
        open: &Arc<OpenConnections>,
        log: &mpsc::Sender<String>,
    ) -> std::io::Result<()> {
        let limits = self.shared.limits;
        stream.set_nonblocking(false)?;
        stream.set_nodelay(true)?;
        stream.set_write_timeout(Some(limits.write))?;
        let open_now = lock(&open.streams).len();
        if open_now >= limits.max_connections + limits.reserve {
            let error = WireError::new(
                "busy",
                format!("{open_now} connections are open; try again later"),
            );
            write_reply(&mut &stream, &Reply::failed(None, error))?;
            let _ = log.send(format!("{peer}: refused, too many connections"));
            return Ok(());
        }
        let auth = if open_now >= limits.max_connections {
            limits.reserve_auth
        } else {
            limits.auth
        };
        let key = open.next.fetch_add(1, Ordering::SeqCst);
        lock(&open.streams).insert(key, stream.try_clone()?);
        let shared = self.shared.clone();
        let open = open.clone();
        let log = log.clone();
        let writer = stream.try_clone()?;
        std::thread::spawn(move || {
            let _ = log.send(format!("{peer}: connected"));
            let mut connection = Connection::new(&shared, peer.clone(), auth);
            let reader = BufReader::new(Timed {
                stream,
                until: None,
            });
            let end = connection.serve(reader, writer);
            drop(connection);
            lock(&open.streams).remove(&key);
            let _ = log.send(format!("{peer}: {end}"));
        });
        Ok(())
    }
}

/// The TCP connections being served, to count them and to shut them down on stop.
#[derive(Default)]
struct OpenConnections {
    streams: Mutex<std::collections::BTreeMap<u64, TcpStream>>,
    next: AtomicU64,
}

/// A byte source whose reads can be given a deadline.
trait DeadlineRead: Read {
    /// Reads after `until` fail with [`std::io::ErrorKind::TimedOut`]; `None`: no deadline.
    fn set_deadline(&mut self, until: Option<Instant>);
}

/// A stream without timeouts (a pipe, a test's buffer).
struct Untimed<R>(R);

impl<R: Read> Read for Untimed<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        self.0.read(buf)
    }
}

impl<R: Read> DeadlineRead for Untimed<R> {
    fn set_deadline(&mut self, _: Option<Instant>) {}
}

/// A TCP stream whose every read is bounded by the time left to a deadline.
struct Timed {
    stream: TcpStream,
    until: Option<Instant>,
}

impl Read for Timed {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let timeout = match self.until {
            None => None,
            Some(until) => {
                let left = until.saturating_duration_since(Instant::now());
                if left.is_zero() {
                    return Err(std::io::Error::new(
                        std::io::ErrorKind::TimedOut,
                        "deadline passed",
                    ));
                }
                Some(left)
            }
        };
        self.stream.set_read_timeout(timeout)?;
        self.stream.read(buf)
    }
}

impl DeadlineRead for Timed {
    fn set_deadline(&mut self, until: Option<Instant>) {
        self.until = until;
    }
}

fn write_reply(writer: &mut impl Write, reply: &Reply) -> std::io::Result<()> {
    let mut out = serde_json::to_vec(reply).expect("replies always serialise");
    out.push(b'\n');
    writer.write_all(&out).and_then(|()| writer.flush())
}

/// One client's connection.
struct Connection<'a> {
    shared: &'a Shared,
    peer: String,
    /// Authenticated (and, for requests other than `hello`, in control).
    authorised: bool,
    /// This connection controls the device.
    controls: bool,
    /// Held after a failed authentication, until the pause after its reply is over.
    penalty: Option<MutexGuard<'a, ()>>,
    /// The time this connection has to authenticate.
    auth: Duration,
}

impl Drop for Connection<'_> {
    fn drop(&mut self) {
        if self.controls {
            *lock(&self.shared.controller) = None;
        }
    }
}

impl<'a> Connection<'a> {
    fn new(shared: &'a Shared, peer: String, auth: Duration) -> Self {
        Self {
            shared,
            peer,
            authorised: false,
            controls: false,
            penalty: None,
            auth,
        }
    }

    /// The deadline for the next request line: a newcomer's to authenticate, the controlling
    /// client's idle time.
    fn deadline(&self) -> Instant {
        Instant::now()
            + if self.authorised {
                self.shared.limits.idle
            } else {
                self.auth
            }
    }

    /// The longest line the client may send now.
    fn max_line_bytes(&self) -> u64 {
        if self.authorised {
            MAX_REQUEST_BYTES
        } else {
            MAX_HELLO_BYTES
        }
    }

    fn serve<R: DeadlineRead, W: Write>(
        &mut self,
        mut reader: BufReader<R>,
        mut writer: W,
    ) -> ConnectionEnd {
        let mut auth_deadline = Some(self.deadline());
        loop {
            let until = auth_deadline.unwrap_or_else(|| self.deadline());
            reader.get_mut().set_deadline(Some(until));
            let mut line = Vec::new();
            let max_line_bytes = self.max_line_bytes();
            match (&mut reader)
                .take(max_line_bytes + 1)
                .read_until(b'\n', &mut line)
            {
                Ok(0) => return ConnectionEnd::ClientClosed,
                Ok(_) if line.len() as u64 > max_line_bytes => {
                    let message = format!("a request line is longer than {max_line_bytes} bytes");
                    let reply = Reply::failed(None, WireError::new("bad_request", &message));
                    let _ = write_reply(&mut writer, &reply);
                    return ConnectionEnd::Broken(message);
                }
                Ok(_) => {}
                Err(e)
                    if matches!(
                        e.kind(),
                        std::io::ErrorKind::TimedOut | std::io::ErrorKind::WouldBlock
                    ) =>
                {
                    let what = if self.authorised {
                        "no complete request within the idle timeout"
                    } else {
                        "no hello within the authentication deadline"
                    };
                    return ConnectionEnd::Broken(what.into());
                }
                Err(e) => return ConnectionEnd::Broken(e.to_string()),
            }
            let text = String::from_utf8_lossy(&line);
            if text.trim().is_empty() {
                continue;
            }
            let (requests, fault) = {
                let mut device = lock(&self.shared.device);
                device.requests += 1;
                (device.requests, device.faults.fault_at(device.requests))
            };
            match fault {
                Some(Fault::Drop) => return ConnectionEnd::Dropped,
                Some(Fault::Slow(delay)) => std::thread::sleep(delay),
                _ => {}
            }
            let (reply, next) = self.answer(text.trim(), fault, requests);
            if self.authorised {
                auth_deadline = None;
            }
            let written = match fault {
                Some(Fault::Corrupt) => writer
                    .write_all(b"{\"id\": 1, \"resu\x01 garbled\n")
                    .and_then(|()| writer.flush()),
                _ => write_reply(&mut writer, &reply),
            };
            if let Some(penalty) = self.penalty.take() {
                std::thread::sleep(self.shared.limits.failed_auth_pause);
                drop(penalty);
            }
            if let Err(e) = written {
                return ConnectionEnd::Broken(format!("cannot write a reply: {e}"));
            }
            if let Next::Close(end) = next {
                return end;
            }
        }
    }

    /// Takes control of the device, waiting up to [`ServeLimits::control_wait`] for the
    /// controlling client to disconnect; or says who has it.
    fn take_control(&mut self) -> Result<(), String> {
        if self.controls {
            return Ok(());
        }
        let give_up = Instant::now() + self.shared.limits.control_wait;
        loop {
            {
                let mut controller = lock(&self.shared.controller);
                match controller.as_deref() {
                    None => {
                        *controller = Some(self.peer.clone());
                        self.controls = true;
                        return Ok(());
                    }
                    Some(other) if Instant::now() >= give_up => return Err(other.to_string()),
                    Some(_) => {}
                }
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    fn busy(&self, id: Option<u64>, other: &str) -> (Reply, Next) {
        let message =
            format!("another client ({other}) controls the device; try again when it disconnects");
        (
            Reply::failed(id, WireError::new("busy", message)),
            Next::Close(ConnectionEnd::Refused(format!("busy: {other} in control"))),
        )
    }

    /// The reply to one request line, and whether to keep the connection.
    fn answer(&mut self, line: &str, fault: Option<Fault>, requests: u64) -> (Reply, Next) {
        let request: Request = match serde_json::from_str(line) {
            Ok(request) => request,
            Err(e) => {
                let error = WireError::new("bad_request", format!("not a request: {e}"));
                return (Reply::failed(None, error), Next::Continue);
            }
        };
        let id = request.id;
        if request.method == "hello" {
            return self.hello(id, &request.params);
        }
        if !self.authorised && self.shared.token.is_some() {
            let error = WireError::new("unauthorized", "send hello with the token first");
            return (
                Reply::failed(Some(id), error),
                Next::Close(ConnectionEnd::Refused("request before hello".into())),
            );
        }
        if let Err(other) = self.take_control() {
            return self.busy(Some(id), &other);
        }
        self.authorised = true;
        let mut device = lock(&self.shared.device);
        let mut reply = if fault == Some(Fault::MotorFault) {
            let error =
                InstrumentError::MotorFault(format!("injected fault on request {requests}"));
            Reply::failed(Some(id), WireError::from_instrument(&error))
        } else {
            match call(device.instrument.as_mut(), &request.method, request.params) {
                Ok(result) => Reply::ok(id, result),
                Err(error) => Reply::failed(Some(id), error),
            }
        };
        reply.clock_s = device.instrument.simulated_clock_s();
        (reply, Next::Continue)
    }

    fn hello(&mut self, id: u64, params: &Value) -> (Reply, Next) {
        let hello: HelloParams = match parse(params.clone()) {
            Ok(h) => h,
            Err(e) => return (Reply::failed(Some(id), e), Next::Continue),
        };
        if hello.protocol != PROTOCOL_VERSION {
            let message = format!(
                "protocol {} asked, this server speaks {PROTOCOL_VERSION}",
                hello.protocol
            );
            return (
                Reply::failed(Some(id), WireError::new("version", message.clone())),
                Next::Close(ConnectionEnd::Refused(message)),
            );
        }
        if let Some(expected) = &self.shared.token {
            let given = hello.token.as_deref().unwrap_or("");
            if !same_secret(given.as_bytes(), expected.secret().as_bytes()) {
                self.penalty = Some(lock(&self.shared.failed_auth));
                return (
                    Reply::failed(
                        Some(id),
                        WireError::new("unauthorized", "wrong or missing token"),
                    ),
                    Next::Close(ConnectionEnd::Refused("wrong token".into())),
                );
            }
        }
        if let Err(other) = self.take_control() {
            return self.busy(Some(id), &other);
        }
        self.authorised = true;
        let result = HelloResult {
            protocol: PROTOCOL_VERSION,
            server: self.shared.name.clone(),
        };
        let mut reply = Reply::ok(id, serde_json::to_value(result).expect("serialises"));
        reply.clock_s = lock(&self.shared.device).instrument.simulated_clock_s();
        (reply, Next::Continue)
    }
}

/// Carries a method out on the instrument.
fn call(instrument: &mut dyn Instrument, method: &str, params: Value) -> Result<Value, WireError> {
    let device = |e: InstrumentError| WireError::from_instrument(&e);
    let to_value = |v: Result<Value, serde_json::Error>| v.expect("results serialise");
    match method {
        "info" => Ok(to_value(serde_json::to_value(
            instrument.info().map_err(device)?,
        ))),
        "home" => Ok(to_value(serde_json::to_value(
            instrument.home().map_err(device)?,
        ))),
        "move_to" => {
            let p: MoveParams = parse(params)?;
            let read_back = instrument.move_to(&p.target).map_err(device)?;
            Ok(to_value(serde_json::to_value(read_back)))
        }
        "set_light" => {
            let p: LightParams = parse(params)?;
            instrument.set_light(p.level).map_err(device)?;
            Ok(json!({}))
        }
        "capture" => {
            let p: CaptureParams = parse(params)?;
            let capture = instrument
                .capture(p.exposure_s, p.with_pixels)
                .map_err(device)?;
            Ok(to_value(serde_json::to_value(capture)))
        }
        other => Err(WireError::new(
            "unknown_method",
            format!("no method '{other}'"),
        )),
    }
}

fn parse<T: DeserializeOwned>(params: Value) -> Result<T, WireError> {
    serde_json::from_value(params)
        .map_err(|e| WireError::new("bad_request", format!("bad params: {e}")))
}

/// Compares secrets in time independent of where they differ.
fn same_secret(a: &[u8], b: &[u8]) -> bool {
    a.len() == b.len() && a.iter().zip(b).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_acquisition::instrument::{Capture, InstrumentInfo};
    use specula_acquisition::kinematics::AxisPositions;

    /// Answers every call; moves read back the target.
    struct Echo;
    impl Instrument for Echo {
        fn home(&mut self) -> Result<AxisPositions, InstrumentError> {
            Ok(AxisPositions::new(0.0, 0.0, 0.0, 0.0))
        }
        fn move_to(&mut self, target: &AxisPositions) -> Result<AxisPositions, InstrumentError> {
            if target.camera_rad > 1.5 {
                return Err(InstrumentError::Limit("camera".into()));
            }
            Ok(*target)
        }
        fn set_light(&mut self, _level: f64) -> Result<(), InstrumentError> {
            Ok(())
        }
        fn capture(
            &mut self,
            exposure_s: f64,
            _with_pixels: bool,
        ) -> Result<Capture, InstrumentError> {
            Ok(Capture {
                exposure_s,
                light_level: 1.0,
                mean_raw: [1.0, 2.0, 3.0],
                saturated_fraction: [0.0; 3],
                pixel_count: 4,
                pixels: None,
            })
        }
        fn info(&mut self) -> Result<InstrumentInfo, InstrumentError> {
            Err(InstrumentError::CameraFault("no camera".into()))
        }
    }

    fn exchange(server: &mut Server, input: &str) -> (Vec<Value>, ConnectionEnd) {
        let mut out = Vec::new();
        let end = server.serve_connection(input.as_bytes(), &mut out);
        let replies = String::from_utf8(out)
            .unwrap()
            .lines()
            .map(|l| serde_json::from_str(l).unwrap_or(Value::String(l.into())))
            .collect();
        (replies, end)
    }

    #[test]
    fn answers_requests_and_reports_errors() {
        let mut server = Server::new(Box::new(Echo), "echo");
        let input = concat!(
            "{\"id\":1,\"method\":\"hello\",\"params\":{\"protocol\":1}}\n",
            "{\"id\":2,\"method\":\"move_to\",\"params\":{\"target\":{\"turntable_rad\":0.1,",
            "\"camera_rad\":0.2,\"light_azimuth_rad\":0.3,\"light_elevation_rad\":0.4}}}\n",
            "{\"id\":3,\"method\":\"move_to\",\"params\":{\"target\":{\"turntable_rad\":0.1,",
            "\"camera_rad\":2.0,\"light_azimuth_rad\":0.3,\"light_elevation_rad\":0.4}}}\n",
            "{\"id\":4,\"method\":\"info\"}\n",
            "this is not json\n",
            "{\"id\":5,\"method\":\"dance\"}\n",
            "{\"id\":6,\"method\":\"set_light\",\"params\":{\"level\":\"high\"}}\n",
            "{\"id\":7,\"method\":\"capture\",\"params\":{\"exposure_s\":0.5}}\n",
        );
        let (replies, end) = exchange(&mut server, input);
        assert_eq!(end, ConnectionEnd::ClientClosed);
        assert_eq!(replies.len(), 8);
        assert_eq!(replies[0]["result"]["server"], "echo");
        assert_eq!(replies[1]["result"]["camera_rad"], 0.2);
        assert_eq!(replies[2]["error"]["kind"], "limit");
        assert_eq!(replies[3]["error"]["kind"], "camera_fault");
        assert_eq!(replies[4]["id"], Value::Null);
        assert_eq!(replies[4]["error"]["kind"], "bad_request");
        assert_eq!(replies[5]["error"]["kind"], "unknown_method");
        assert_eq!(replies[6]["error"]["kind"], "bad_request");
        assert_eq!(replies[7]["result"]["exposure_s"], 0.5);
        assert_eq!(server.requests(), 8);
    }

    #[test]
    fn a_token_is_required_when_set() {
        let mut server =
            Server::new(Box::new(Echo), "echo").with_token(Some(Token::new("s3cret").unwrap()));
        let (replies, end) = exchange(
            &mut server,
            "{\"id\":1,\"method\":\"home\"}\n{\"id\":2,\"method\":\"home\"}\n",
        );
        assert_eq!(replies.len(), 1);
        assert_eq!(replies[0]["error"]["kind"], "unauthorized");
        assert!(matches!(end, ConnectionEnd::Refused(_)));
        let wrong =
            "{\"id\":1,\"method\":\"hello\",\"params\":{\"protocol\":1,\"token\":\"guess\"}}\n";
        let (replies, _) = exchange(&mut server, wrong);
        assert_eq!(replies[0]["error"]["kind"], "unauthorized");
        let right =
            "{\"id\":1,\"method\":\"hello\",\"params\":{\"protocol\":1,\"token\":\"s3cret\"}}\n\
                     {\"id\":2,\"method\":\"home\"}\n";
        let (replies, end) = exchange(&mut server, right);
        assert_eq!(replies[1]["result"]["camera_rad"], 0.0);
        assert_eq!(end, ConnectionEnd::ClientClosed);
        let old =
            "{\"id\":1,\"method\":\"hello\",\"params\":{\"protocol\":0,\"token\":\"s3cret\"}}\n";
        let (replies, _) = exchange(&mut server, old);
        assert_eq!(replies[0]["error"]["kind"], "version");
    }

    #[test]
    fn injected_faults_happen_at_their_request() {
        let faults: FaultSchedule = "corrupt@2,motor@3,drop@4".parse().unwrap();
        let mut server = Server::new(Box::new(Echo), "echo").with_faults(faults);
        let input = "{\"id\":1,\"method\":\"home\"}\n".repeat(5);
        let (replies, end) = exchange(&mut server, &input);
        assert_eq!(end, ConnectionEnd::Dropped);
        assert_eq!(replies.len(), 3);
        assert_eq!(replies[0]["result"]["camera_rad"], 0.0);
        assert!(replies[1].is_string(), "garbled: {:?}", replies[1]);
        assert_eq!(replies[2]["error"]["kind"], "motor_fault");
    }
}
