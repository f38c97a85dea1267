//! The client side of the driver protocol: a device behind TCP or a child process, seen as
//! an [`Instrument`].
//!
//! Every method is safe to repeat (moves are absolute, a capture is another frame), so a
//! request that gets no usable reply is sent again on a fresh link: the link is closed and
//! reopened (a new connection, or the adapter program started again), after a pause that
//! doubles with each failure ([`ClientSettings::backoff_initial`] up to
//! [`ClientSettings::backoff_max`]). After [`ClientSettings::max_failures`] failures in a row
//! the call fails with an error that says what was tried. Errors the device itself reports
//! (motor fault, limit, ...) are returned at once: what to do about them is the engine's
//! decision. A reply outside the protocol's ranges ([`super::validate`]) counts as a failure
//! too: it is asked again, and if the device keeps answering so the call fails as a device
//! fault (camera fault for a capture, motor fault for a move) naming the field.
//!
//! With a stop flag ([`RemoteInstrument::with_stop`]) every wait (for a reply, between tries)
//! looks at the flag every [`STOP_POLL`]: once it is raised the call fails at once, as
//! disconnected "stopped by the user", and the link is not reopened.

use super::link::{Endpoint, Link, LinkError};
use super::message::{
    CaptureParams, HelloParams, HelloResult, LightParams, MoveParams, Reply, Request, WireError,
    PROTOCOL_VERSION,
};
use super::validate::{ReplyProblem, ReplyRanges};
use crate::pace::STOP_POLL;
use serde::de::DeserializeOwned;
use serde_json::{json, Value};
use specula_acquisition::instrument::{Capture, Instrument, InstrumentError, InstrumentInfo};
use specula_acquisition::kinematics::AxisPositions;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::RecvTimeoutError;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Retries, timeouts and the token.
#[derive(Debug, Clone, PartialEq)]
pub struct ClientSettings {
    /// How long to wait for a reply (a real move can take a minute).
    pub reply_timeout: Duration,
    /// How long to wait for a TCP connection.
    pub connect_timeout: Duration,
    /// Failures in a row on one call before giving up.
    pub max_failures: u32,
    /// Pause after the first failure; doubled after each further one.
    pub backoff_initial: Duration,
    /// The longest pause.
    pub backoff_max: Duration,
    /// The shared secret `hello` sends, if the server asks for one.
    pub token: Option<String>,
    /// The device model's ranges replies are checked against (the white level comes from
    /// the device's `info`).
    pub ranges: ReplyRanges,
}

impl Default for ClientSettings {
    fn default() -> Self {
        Self {
            reply_timeout: Duration::from_secs(120),
            connect_timeout: Duration::from_secs(10),
            max_failures: 5,
            backoff_initial: Duration::from_millis(250),
            backoff_max: Duration::from_secs(15),
            token: None,
            ranges: ReplyRanges::default(),
        }
    }
}

impl ClientSettings {
    /// The pause after the `failures`-th failure in a row.
    pub fn backoff(&self, failures: u32) -> Duration {
        let factor = 2u32.saturating_pow(failures.saturating_sub(1).min(30));
        self.backoff_initial
            .saturating_mul(factor)
            .min(self.backoff_max)
    }
}

/// What happened on the link that did not fail the call: `(kind, message)` with kind
/// `retry` or `reconnect`. The engine copies them into the journal's events.
pub type LinkNotes = Arc<Mutex<Vec<(String, String)>>>;

/// Why one attempt failed.
enum AttemptError {
    /// Worth another try on a fresh link.
    Transport { timeout: bool, why: String },
    /// The device answered with an error.
    Device(InstrumentError),
    /// The server refused us (token, protocol version) or does not understand us: another
    /// try would fail the same way.
    Refused(String),
    /// The stop flag was raised while waiting.
    Stopped,
}

/// A device reached through the driver protocol.
pub struct RemoteInstrument {
    endpoint: Endpoint,
    settings: ClientSettings,
    link: Option<Link>,
    next_id: u64,
    clock_s: Option<f64>,
    notes: LinkNotes,
    server: Option<String>,
    stop: Option<Arc<AtomicBool>>,
}

impl RemoteInstrument {
    /// A client for `endpoint`; nothing is opened until the first call.
    pub fn new(endpoint: Endpoint, settings: ClientSettings) -> Self {
        Self {
            endpoint,
            settings,
            link: None,
            next_id: 1,
            clock_s: None,
            notes: LinkNotes::default(),
            server: None,
            stop: None,
        }
    }

    /// Cuts every wait short once `stop` is raised (see the module documentation).
    pub fn with_stop(mut self, stop: Arc<AtomicBool>) -> Self {
        self.stop = Some(stop);
        self
    }

    /// Whether the stop flag is raised.
    fn stopped(&self) -> bool {
        self.stop.as_ref().is_some_and(|s| s.load(Ordering::SeqCst))
    }

    /// Sleeps `pause`, in slices of [`STOP_POLL`]; false when the stop flag cut it short.
    fn pause(&self, pause: Duration) -> bool {
        let end = Instant::now() + pause;
        loop {
            if self.stopped() {
                return false;
            }
            let left = end.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return true;
            }
            std::thread::sleep(left.min(STOP_POLL));
        }
    }

    /// The error of a call the stop flag ended.
    fn stopped_error(&self, method: &str) -> InstrumentError {
        InstrumentError::Disconnected(format!("{}: {method}: stopped by the user", self.endpoint))
    }

    /// Opens the link now and checks the server (protocol version, token).
    pub fn connect(endpoint: Endpoint, settings: ClientSettings) -> Result<Self, InstrumentError> {
        let mut client = Self::new(endpoint, settings);
        client.info()?;
        Ok(client)
    }

    /// The notes of retries and reconnections (shared; drain it now and then).
    pub fn notes(&self) -> LinkNotes {
        self.notes.clone()
    }

    /// The server's name from `hello`, once connected.
    pub fn server_name(&self) -> Option<&str> {
        self.server.as_deref()
    }

    /// Where the device is reached.
    pub fn endpoint(&self) -> &Endpoint {
        &self.endpoint
    }

    fn note(&self, kind: &str, message: String) {
        if let Ok(mut notes) = self.notes.lock() {
            notes.push((kind.to_string(), message));
        }
    }

    /// Calls a method, retrying on a fresh link as the settings say; `check` says what is
    /// wrong with a reply outside the protocol's ranges.
    fn call<T: DeserializeOwned>(
        &mut self,
        method: &str,
        params: Value,
        check: &dyn Fn(&ReplyRanges, &T) -> Result<(), ReplyProblem>,
    ) -> Result<T, InstrumentError> {
        let mut failures = 0u32;
        loop {
            let why = match self.attempt(method, &params) {
                Ok(value) => {
                    let reply: T = serde_json::from_value(value).map_err(|e| {
                        InstrumentError::Disconnected(format!(
                            "{}: the reply to {method} is not what the protocol says: {e}",
                            self.endpoint
                        ))
                    })?;
                    match check(&self.settings.ranges, &reply) {
                        Ok(()) => return Ok(reply),
                        Err(problem) => {
                            failures += 1;
                            let message = format!("{}: {method} reply: {problem}", self.endpoint);
                            if failures >= self.settings.max_failures.max(1) {
                                return Err(bad_reply_error(
                                    method,
                                    format!("{message} ({failures} replies in a row)"),
                                ));
                            }
                            self.link = None;
                            let pause = self.settings.backoff(failures);
                            self.note("retry", format!("{message}; asking again"));
                            if !self.pause(pause) {
                                return Err(self.stopped_error(method));
                            }
                            continue;
                        }
                    }
                }
                Err(AttemptError::Device(error)) => return Err(error),
                Err(AttemptError::Stopped) => {
                    self.link = None;
                    return Err(self.stopped_error(method));
                }
                Err(AttemptError::Refused(why)) => {
                    self.link = None;
                    return Err(InstrumentError::Disconnected(format!(
                        "{}: {why}",
                        self.endpoint
                    )));
                }
                Err(AttemptError::Transport { timeout, why }) => (timeout, why),
            };
            self.link = None;
            failures += 1;
            if failures >= self.settings.max_failures.max(1) {
                let message = format!(
                    "{}: {method} failed {failures} times in a row, giving up (last: {})",
                    self.endpoint, why.1
                );
                return Err(if why.0 {
                    InstrumentError::Timeout(message)
                } else {
                    InstrumentError::Disconnected(message)
                });
            }
            let pause = self.settings.backoff(failures);
            self.note(
                "retry",
                format!(
                    "{method}: {} (failure {failures}); reconnecting in {:.2} s",
                    why.1,
                    pause.as_secs_f64()
                ),
            );
            if !self.pause(pause) {
                return Err(self.stopped_error(method));
            }
        }
    }

    /// One try: open the link if needed, send, wait for the reply with our id.
    fn attempt(&mut self, method: &str, params: &Value) -> Result<Value, AttemptError> {
        if self.stopped() {
            return Err(AttemptError::Stopped);
        }
        if self.link.is_none() {
            self.open()?;
        }
        let id = self.next_id;
        self.next_id += 1;
        let request = Request {
            id,
            method: method.to_string(),
            params: params.clone(),
        };
        let reply = self.exchange(&request)?;
        match reply.error {
            None => Ok(reply.result.unwrap_or(Value::Null)),
            Some(error) => Err(match (error.to_instrument(), error.kind.as_str()) {
                (Some(device), _) => AttemptError::Device(device),
                // The device could not read what we sent: the line was damaged on the way.
                (None, "bad_request") => AttemptError::Transport {
                    timeout: false,
                    why: format!("the device could not read our request: {}", error.message),
                },
                // Another client controls the device: wait for it, as for a lost link.
                (None, "busy") => AttemptError::Transport {
                    timeout: false,
                    why: format!("the device is busy: {}", error.message),
                },
                (None, kind) => {
                    AttemptError::Refused(format!("{method}: {kind}: {}", error.message))
                }
            }),
        }
    }

    /// Opens a link and says hello.
    fn open(&mut self) -> Result<(), AttemptError> {
        self.link = Some(self.connect_link()?);
        let params = HelloParams {
            protocol: PROTOCOL_VERSION,
            token: self.settings.token.clone(),
        };
        let request = Request {
            id: self.next_id,
            method: "hello".into(),
            params: serde_json::to_value(params).expect("serialises"),
        };
        self.next_id += 1;
        let reply = self.exchange(&request)?;
        if let Some(error) = reply.error {
            if error.kind == "busy" {
                return Err(AttemptError::Transport {
                    timeout: false,
                    why: format!("the device is busy: {}", error.message),
                });
            }
            return Err(AttemptError::Refused(format!(
                "refused: {}: {}",
                error.kind, error.message
            )));
        }
        let hello: HelloResult = serde_json::from_value(reply.result.unwrap_or(Value::Null))
            .map_err(|e| AttemptError::Refused(format!("hello: unexpected reply: {e}")))?;
        if let Some(before) = self.server.as_deref().filter(|&b| b != hello.server) {
            return Err(AttemptError::Refused(format!(
                "reconnected to another device: it was '{before}', it is now '{}'; the measurement stops rather than mix two devices' samples",
                hello.server
            )));
        }
        if self.server.is_some() {
            self.note(
                "reconnect",
                format!("reconnected to {} ({})", self.endpoint, hello.server),
            );
        }
        self.server = Some(hello.server);
        Ok(())
    }

    /// Opens a link to the endpoint. With a stop flag the connection is made in a thread of
    /// its own while this one looks at the flag every [`STOP_POLL`] (a TCP connection may
    /// take [`ClientSettings::connect_timeout`]); a connection abandoned on a stop is closed
    /// by that thread once it is made.
    fn connect_link(&self) -> Result<Link, AttemptError> {
        let cannot = |e: std::io::Error| AttemptError::Transport {
            timeout: false,
            why: format!("cannot connect: {e}"),
        };
        let timeout = self.settings.connect_timeout;
        let Some(stop) = self.stop.clone() else {
            return Link::open(&self.endpoint, timeout).map_err(cannot);
        };
        let endpoint = self.endpoint.clone();
        let (sender, receiver) = std::sync::mpsc::channel();
        std::thread::spawn(move || sender.send(Link::open(&endpoint, timeout)));
        loop {
            match receiver.recv_timeout(STOP_POLL) {
                Ok(opened) => return opened.map_err(cannot),
                Err(RecvTimeoutError::Timeout) if stop.load(Ordering::SeqCst) => {
                    return Err(AttemptError::Stopped)
                }
                Err(RecvTimeoutError::Timeout) => {}
                Err(RecvTimeoutError::Disconnected) => {
                    return Err(cannot(std::io::Error::other("the connecting thread ended")))
                }
            }
        }
    }

    /// Sends a request and waits for its reply, skipping stale replies to earlier requests;
    /// the wait looks at the stop flag every [`STOP_POLL`].
    fn exchange(&mut self, request: &Request) -> Result<Reply, AttemptError> {
        let stop = self.stop.clone();
        let link = self.link.as_mut().expect("the link is open");
        let line = serde_json::to_string(request).expect("requests serialise");
        let transport = |timeout: bool, why: String| AttemptError::Transport { timeout, why };
        link.send(&line).map_err(|e| match e {
            LinkError::Timeout => transport(true, "send timed out".into()),
            LinkError::Closed(why) => transport(false, format!("send failed: {why}")),
        })?;
        let deadline = Instant::now() + self.settings.reply_timeout;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            let slice = if stop.is_some() {
                left.min(STOP_POLL)
            } else {
                left
            };
            let line = match link.receive(slice) {
                Err(LinkError::Timeout) if slice < left => {
                    if stop.as_ref().is_some_and(|s| s.load(Ordering::SeqCst)) {
                        return Err(AttemptError::Stopped);
                    }
                    continue;
                }
                received => received,
            };
            let line = line.map_err(|e| match e {
                LinkError::Timeout => transport(
                    true,
                    format!(
                        "no reply within {:.1} s",
                        self.settings.reply_timeout.as_secs_f64()
                    ),
                ),
                LinkError::Closed(why) => transport(false, why),
            })?;
            let reply: Reply = serde_json::from_str(&line)
                .map_err(|e| transport(false, format!("corrupt reply line ({e})")))?;
            match reply.id {
                Some(id) if id == request.id => {
                    if reply.clock_s.is_some() {
                        self.clock_s = reply.clock_s;
                    }
                    return Ok(reply);
                }
                Some(id) if id < request.id => continue,
                _ => {
                    let why = reply
                        .error
                        .map_or("reply to an unknown request".into(), |e: WireError| {
                            e.message
                        });
                    return Err(transport(
                        false,
                        format!("the device could not read our request: {why}"),
                    ));
                }
            }
        }
    }
}

/// The device fault a reply outside the protocol's ranges stands for.
fn bad_reply_error(method: &str, message: String) -> InstrumentError {
    match method {
        "capture" => InstrumentError::CameraFault(message),
        "home" | "move_to" => InstrumentError::MotorFault(message),
        _ => InstrumentError::Disconnected(message),
    }
}

impl Instrument for RemoteInstrument {
    fn home(&mut self) -> Result<AxisPositions, InstrumentError> {
        self.call("home", Value::Null, &ReplyRanges::check_positions)
    }

    fn move_to(&mut self, target: &AxisPositions) -> Result<AxisPositions, InstrumentError> {
        let params = MoveParams { target: *target };
        self.call(
            "move_to",
            serde_json::to_value(params).expect("serialises"),
            &ReplyRanges::check_positions,
        )
    }

    fn set_light(&mut self, level: f64) -> Result<(), InstrumentError> {
        let params = LightParams { level };
        self.call::<Value>(
            "set_light",
            serde_json::to_value(params).expect("serialises"),
            &|_, _| Ok(()),
        )
        .map(|_| ())
    }

    fn capture(&mut self, exposure_s: f64, with_pixels: bool) -> Result<Capture, InstrumentError> {
        let params = CaptureParams {
            exposure_s,
            with_pixels,
        };
        self.call("capture", json!(params), &|ranges, c| {
            ranges.check_capture(c, exposure_s)
        })
    }

    fn info(&mut self) -> Result<InstrumentInfo, InstrumentError> {
        let info: InstrumentInfo =
            self.call("info", Value::Null, &|_, i| ReplyRanges::check_info(i))?;
        self.settings.ranges.white_level = Some(info.white_level);
        Ok(info)
    }

    fn simulated_clock_s(&self) -> Option<f64> {
        self.clock_s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn backoff_doubles_up_to_the_cap() {
        let settings = ClientSettings {
            backoff_initial: Duration::from_millis(100),
            backoff_max: Duration::from_millis(700),
            ..ClientSettings::default()
        };
        let pauses: Vec<u128> = (1..=6).map(|n| settings.backoff(n).as_millis()).collect();
        assert_eq!(pauses, vec![100, 200, 400, 700, 700, 700]);
        assert_eq!(settings.backoff(u32::MAX), Duration::from_millis(700));
    }

    /// A scripted server on 127.0.0.1 for `kinds.len()` connections, and one more when
    /// `then_ok`: each answers `hello`, then its next request with the given error kind (the
    /// last one, with a home position).
    fn scripted(kinds: Vec<&'static str>, then_ok: bool) -> (String, std::thread::JoinHandle<()>) {
        use std::io::{BufRead, BufReader, Write};
        let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        let address = listener.local_addr().unwrap().to_string();
        let thread = std::thread::spawn(move || {
            let last = then_ok.then_some(None);
            for kind in kinds.into_iter().map(Some).chain(last) {
                let (stream, _) = listener.accept().unwrap();
                let mut reader = BufReader::new(stream.try_clone().unwrap());
                let mut writer = stream;
                for n in 0..2 {
                    let mut line = String::new();
                    if reader.read_line(&mut line).unwrap() == 0 {
                        break;
                    }
                    let id = serde_json::from_str::<Request>(&line).unwrap().id;
                    let reply = match (n, kind) {
                        (0, _) => json!({"id": id, "result": {"protocol": 1, "server": "script"}}),
                        (_, Some(kind)) => {
                            json!({"id": id, "error": {"kind": kind, "message": "scripted"}})
                        }
                        (_, None) => {
                            json!({"id": id, "result": AxisPositions::new(0.0, 0.0, 0.0, 0.0)})
                        }
                    };
                    writeln!(writer, "{reply}").unwrap();
                }
            }
        });
        (address, thread)
    }

    fn quick() -> ClientSettings {
        ClientSettings {
            max_failures: 3,
            backoff_initial: Duration::from_millis(1),
            reply_timeout: Duration::from_secs(5),
            ..ClientSettings::default()
        }
    }

    #[test]
    fn a_damaged_request_is_sent_again_and_a_refusal_is_final() {
        let (address, server) = scripted(vec!["bad_request"], true);
        let mut client = RemoteInstrument::new(Endpoint::Tcp(address), quick());
        assert_eq!(
            client.home().unwrap(),
            AxisPositions::new(0.0, 0.0, 0.0, 0.0)
        );
        server.join().unwrap();
        let notes = client.notes().lock().unwrap().clone();
        assert_eq!(notes.len(), 2, "a retry, then a reconnection: {notes:?}");

        let (address, server) = scripted(vec!["unknown_method"], false);
        let mut client = RemoteInstrument::new(Endpoint::Tcp(address), quick());
        let err = client.home().unwrap_err().to_string();
        server.join().unwrap();
        assert!(err.contains("home: unknown_method: scripted"), "{err}");
        assert!(client.notes().lock().unwrap().is_empty(), "no retry");
    }

    /// A client of `address` with a minute's timeouts and a stop flag raised after 200 ms;
    /// `home`'s error and how long it took.
    fn stopped_home(address: String) -> (InstrumentError, Duration, usize) {
        let settings = ClientSettings {
            reply_timeout: Duration::from_secs(60),
            connect_timeout: Duration::from_secs(60),
            ..ClientSettings::default()
        };
        let stop = Arc::new(AtomicBool::new(false));
        let raise = stop.clone();
        std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(200));
            raise.store(true, Ordering::SeqCst);
        });
        let mut client = RemoteInstrument::new(Endpoint::Tcp(address), settings).with_stop(stop);
        let started = Instant::now();
        let err = client.home().unwrap_err();
        let notes = client.notes().lock().unwrap().len();
        (err, started.elapsed(), notes)
    }

    #[test]
    fn a_stop_ends_the_wait_for_a_reply_at_once_without_a_retry() {
        // Accepts and never answers.
        let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        let address = listener.local_addr().unwrap().to_string();
        let _held = std::thread::spawn(move || listener.accept());
        let (err, took, notes) = stopped_home(address);
        assert!(took < Duration::from_secs(2), "{took:?}");
        assert!(err.to_string().contains("stopped by the user"), "{err}");
        assert_eq!(notes, 0, "no retry after a stop");
    }

    #[test]
    fn a_stop_ends_the_wait_for_a_connection_at_once() {
        // A listener whose accept queue is full: a further connection waits for its timeout.
        let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        let address = listener.local_addr().unwrap();
        let mut queued = Vec::new();
        let full = (0..1024).any(|_| {
            match std::net::TcpStream::connect_timeout(&address, Duration::from_millis(200)) {
                Ok(stream) => {
                    queued.push(stream);
                    false
                }
                Err(_) => true,
            }
        });
        assert!(full, "the accept queue never filled");
        let (err, took, _) = stopped_home(address.to_string());
        assert!(took < Duration::from_secs(2), "{took:?}");
        assert!(err.to_string().contains("stopped by the user"), "{err}");
    }

    #[test]
    fn an_unreachable_device_fails_after_the_configured_tries() {
        // A port nothing listens on: bind one, then close it.
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .unwrap()
            .local_addr()
            .unwrap()
            .port();
        let settings = ClientSettings {
            max_failures: 3,
            backoff_initial: Duration::from_millis(1),
            connect_timeout: Duration::from_millis(200),
            ..ClientSettings::default()
        };
        let mut client =
            RemoteInstrument::new(Endpoint::Tcp(format!("127.0.0.1:{port}")), settings);
        let err = client.home().unwrap_err();
        let text = err.to_string();
        assert!(matches!(err, InstrumentError::Disconnected(_)), "{text}");
        assert!(
            text.contains("home failed 3 times in a row") && text.contains("cannot connect"),
            "{text}"
        );
        assert_eq!(
            client.notes().lock().unwrap().len(),
            2,
            "two retries before giving up"
        );
    }
}
