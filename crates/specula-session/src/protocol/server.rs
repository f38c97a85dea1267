//! The server side of the driver protocol: any [`Instrument`] served over TCP or over a pair
//! of streams (a program's stdin and stdout), one connection at a time, as a device can only
//! do one thing at a time.

use super::faults::{Fault, FaultSchedule};
use super::message::{
    CaptureParams, HelloParams, HelloResult, LightParams, MoveParams, Reply, Request, WireError,
    MAX_LINE_BYTES, PROTOCOL_VERSION,
};
use serde::de::DeserializeOwned;
use serde_json::{json, Value};
use specula_acquisition::instrument::{Instrument, InstrumentError};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpListener;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// Serves one instrument.
pub struct Server {
    instrument: Box<dyn Instrument>,
    name: String,
    token: Option<String>,
    faults: FaultSchedule,
    /// Requests received over the server's life.
    requests: u64,
}

/// How a connection ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ConnectionEnd {
    /// The client closed it.
    ClientClosed,
    /// An injected [`Fault::Drop`].
    Dropped,
    /// The client failed `hello` (wrong token or protocol version).
    Refused(String),
    /// Reading or writing failed (including the idle timeout).
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

impl Server {
    /// A server named `name` (reported by `hello`).
    pub fn new(instrument: Box<dyn Instrument>, name: impl Into<String>) -> Self {
        Self {
            instrument,
            name: name.into(),
            token: None,
            faults: FaultSchedule::new(),
            requests: 0,
        }
    }

    /// Requires `hello` with this shared token on every connection.
    pub fn with_token(mut self, token: Option<String>) -> Self {
        self.token = token;
        self
    }

    /// Injects faults (see [`FaultSchedule`]).
    pub fn with_faults(mut self, faults: FaultSchedule) -> Self {
        self.faults = faults;
        self
    }

    /// Requests received so far.
    pub fn requests(&self) -> u64 {
        self.requests
    }

    /// Serves one connection until the client closes it, a fault drops it or it breaks.
    pub fn serve_connection<R: Read, W: Write>(
        &mut self,
        reader: R,
        mut writer: W,
    ) -> ConnectionEnd {
        let mut reader = BufReader::new(reader);
        let mut authorised = self.token.is_none();
        loop {
            let mut line = Vec::new();
            match (&mut reader)
                .take(MAX_LINE_BYTES + 1)
                .read_until(b'\n', &mut line)
            {
                Ok(0) => return ConnectionEnd::ClientClosed,
                Ok(_) if line.len() as u64 > MAX_LINE_BYTES => {
                    return ConnectionEnd::Broken("request line too long".into())
                }
                Ok(_) => {}
                Err(e) => return ConnectionEnd::Broken(e.to_string()),
            }
            let text = String::from_utf8_lossy(&line);
            if text.trim().is_empty() {
                continue;
            }
            self.requests += 1;
            let fault = self.faults.fault_at(self.requests);
            match fault {
                Some(Fault::Drop) => return ConnectionEnd::Dropped,
                Some(Fault::Slow(delay)) => std::thread::sleep(delay),
                _ => {}
            }
            let (reply, next) = self.answer(text.trim(), &mut authorised, fault);
            let mut out = match fault {
                Some(Fault::Corrupt) => b"{\"id\": 1, \"resu\x01 garbled".to_vec(),
                _ => serde_json::to_vec(&reply).expect("replies always serialise"),
            };
            out.push(b'\n');
            if let Err(e) = writer.write_all(&out).and_then(|()| writer.flush()) {
                return ConnectionEnd::Broken(e.to_string());
            }
            if let Next::Close(end) = next {
                return end;
            }
        }
    }

    /// Accepts connections on `listener` one after another until `stop` is set (checked
    /// after each connection; connect once to wake an idle server). A client silent for
    /// `idle` is disconnected. `log` hears how each connection ended.
    pub fn serve_tcp(
        &mut self,
        listener: &TcpListener,
        stop: &AtomicBool,
        idle: Duration,
        log: &mut dyn FnMut(String),
    ) -> std::io::Result<()> {
        while !stop.load(Ordering::SeqCst) {
            let (stream, peer) = match listener.accept() {
                Ok(accepted) => accepted,
                Err(e) => {
                    log(format!("accept failed: {e}"));
                    continue;
                }
            };
            if stop.load(Ordering::SeqCst) {
                break;
            }
            stream.set_read_timeout(Some(idle))?;
            stream.set_nodelay(true)?;
            let writer = stream.try_clone()?;
            log(format!("{peer}: connected"));
            let end = self.serve_connection(stream, writer);
            log(format!("{peer}: {end}"));
        }
        Ok(())
    }

    /// The reply to one request line, and whether to keep the connection.
    fn answer(&mut self, line: &str, authorised: &mut bool, fault: Option<Fault>) -> (Reply, Next) {
        let request: Request = match serde_json::from_str(line) {
            Ok(request) => request,
            Err(e) => {
                let error = WireError::new("bad_request", format!("not a request: {e}"));
                return (Reply::failed(None, error), Next::Continue);
            }
        };
        let id = request.id;
        if request.method == "hello" {
            return self.hello(id, &request.params, authorised);
        }
        if !*authorised {
            let error = WireError::new("unauthorized", "send hello with the token first");
            return (
                Reply::failed(Some(id), error),
                Next::Close(ConnectionEnd::Refused("request before hello".into())),
            );
        }
        let mut reply = if fault == Some(Fault::MotorFault) {
            let error =
                InstrumentError::MotorFault(format!("injected fault on request {}", self.requests));
            Reply::failed(Some(id), WireError::from_instrument(&error))
        } else {
            match self.call(&request.method, request.params) {
                Ok(result) => Reply::ok(id, result),
                Err(error) => Reply::failed(Some(id), error),
            }
        };
        reply.clock_s = self.instrument.simulated_clock_s();
        (reply, Next::Continue)
    }

    fn hello(&mut self, id: u64, params: &Value, authorised: &mut bool) -> (Reply, Next) {
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
        if let Some(expected) = &self.token {
            let given = hello.token.as_deref().unwrap_or("");
            if !same_secret(given.as_bytes(), expected.as_bytes()) {
                return (
                    Reply::failed(
                        Some(id),
                        WireError::new("unauthorized", "wrong or missing token"),
                    ),
                    Next::Close(ConnectionEnd::Refused("wrong token".into())),
                );
            }
        }
        *authorised = true;
        let result = HelloResult {
            protocol: PROTOCOL_VERSION,
            server: self.name.clone(),
        };
        let mut reply = Reply::ok(id, serde_json::to_value(result).expect("serialises"));
        reply.clock_s = self.instrument.simulated_clock_s();
        (reply, Next::Continue)
    }

    /// Carries a method out on the instrument.
    fn call(&mut self, method: &str, params: Value) -> Result<Value, WireError> {
        let device = |e: InstrumentError| WireError::from_instrument(&e);
        let to_value = |v: Result<Value, serde_json::Error>| v.expect("results serialise");
        match method {
            "info" => Ok(to_value(serde_json::to_value(
                self.instrument.info().map_err(device)?,
            ))),
            "home" => Ok(to_value(serde_json::to_value(
                self.instrument.home().map_err(device)?,
            ))),
            "move_to" => {
                let p: MoveParams = parse(params)?;
                let read_back = self.instrument.move_to(&p.target).map_err(device)?;
                Ok(to_value(serde_json::to_value(read_back)))
            }
            "set_light" => {
                let p: LightParams = parse(params)?;
                self.instrument.set_light(p.level).map_err(device)?;
                Ok(json!({}))
            }
            "capture" => {
                let p: CaptureParams = parse(params)?;
                let capture = self
                    .instrument
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
        let mut server = Server::new(Box::new(Echo), "echo").with_token(Some("s3cret".into()));
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
