//! A line link to a device: TCP (`tcp://HOST:PORT`) or a child process's stdin and stdout
//! (`exec:COMMAND`), with a reply timeout.
//!
//! A reader thread turns the incoming bytes into lines on a channel, so that waiting for a
//! reply has a timeout whatever the transport (a pipe has none of its own). Dropping the link
//! closes it: the socket is shut down; an adapter (`sh -c COMMAND`) and every process it
//! started end with it, so a restarted adapter never runs beside the old one. On Linux the
//! adapter runs under a guardian ([`super::guardian`]) that ends them all also when Specula
//! itself dies (a second Ctrl-C, `kill -9`), `setsid` children included; elsewhere the
//! adapter's process group is killed when the link is dropped.

use super::message::MAX_LINE_BYTES;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{Shutdown, TcpStream, ToSocketAddrs};
use std::os::unix::process::CommandExt;
use std::process::{Child, Command, Stdio};
use std::str::FromStr;
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::thread;
use std::time::Duration;

/// Where a device is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Endpoint {
    /// A server speaking the protocol over TCP, `HOST:PORT`.
    Tcp(String),
    /// A program speaking the protocol on its stdin and stdout, run by `sh -c`; it and
    /// everything it starts end with the link.
    Exec(String),
}

impl FromStr for Endpoint {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        if let Some(address) = s.strip_prefix("tcp://") {
            if address
                .rsplit_once(':')
                .is_none_or(|(host, port)| host.is_empty() || port.parse::<u16>().is_err())
            {
                return Err(format!("'{s}': expected tcp://HOST:PORT"));
            }
            Ok(Endpoint::Tcp(address.to_string()))
        } else if let Some(command) = s.strip_prefix("exec:") {
            if command.trim().is_empty() {
                return Err(format!("'{s}': expected exec:COMMAND"));
            }
            Ok(Endpoint::Exec(command.to_string()))
        } else {
            Err(format!(
                "'{s}': a device is tcp://HOST:PORT or exec:COMMAND"
            ))
        }
    }
}

impl std::fmt::Display for Endpoint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Endpoint::Tcp(address) => write!(f, "tcp://{address}"),
            Endpoint::Exec(command) => write!(f, "exec:{command}"),
        }
    }
}

/// Why a line did not arrive.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LinkError {
    /// Nothing within the timeout.
    Timeout,
    /// The other side closed the link, or it broke.
    Closed(String),
}

/// What keeps the far end alive, and how to close it.
enum Peer {
    Socket(TcpStream),
    Process(Adapter),
}

/// An adapter's processes: on Linux its guardian and the lifeline that keeps it going;
/// elsewhere the `sh -c` child, leader of the adapter's process group.
struct Adapter {
    child: Child,
    #[cfg(target_os = "linux")]
    lifeline: Option<std::os::fd::OwnedFd>,
}

impl Adapter {
    /// Starts `sh -c COMMAND` with its stdin and stdout piped, in a process group of its own
    /// (a Ctrl-C at the terminal reaches Specula only, which decides when the adapter ends).
    fn spawn(command: &str) -> std::io::Result<Adapter> {
        let mut shell = Command::new("sh");
        shell
            .arg("-c")
            .arg(command)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .process_group(0);
        #[cfg(target_os = "linux")]
        {
            let (child, lifeline) = super::guardian::spawn(&mut shell)?;
            Ok(Adapter {
                child,
                lifeline: Some(lifeline),
            })
        }
        #[cfg(not(target_os = "linux"))]
        Ok(Adapter {
            child: shell.spawn()?,
        })
    }

    /// Ends the adapter and everything it started, and reaps what this process spawned.
    fn end(&mut self) {
        #[cfg(target_os = "linux")]
        {
            // The guardian kills every descendant once its lifeline closes, then exits.
            self.lifeline = None;
        }
        #[cfg(not(target_os = "linux"))]
        if let Ok(pid) = i32::try_from(self.child.id()) {
            use nix::sys::signal::{killpg, Signal};
            let _ = killpg(nix::unistd::Pid::from_raw(pid), Signal::SIGKILL);
        }
        let _ = self.child.wait();
    }
}

/// An open line link.
pub struct Link {
    writer: Box<dyn Write + Send>,
    lines: Receiver<Result<String, String>>,
    peer: Peer,
}

impl Link {
    /// Connects to the endpoint (for TCP within `connect_timeout`).
    pub fn open(endpoint: &Endpoint, connect_timeout: Duration) -> std::io::Result<Link> {
        match endpoint {
            Endpoint::Tcp(address) => Self::tcp(address, connect_timeout),
            Endpoint::Exec(command) => Self::exec(command),
        }
    }

    fn tcp(address: &str, connect_timeout: Duration) -> std::io::Result<Link> {
        let mut last = std::io::Error::new(std::io::ErrorKind::NotFound, "no address");
        for addr in address.to_socket_addrs()? {
            match TcpStream::connect_timeout(&addr, connect_timeout) {
                Ok(stream) => {
                    stream.set_nodelay(true)?;
                    let reader = stream.try_clone()?;
                    let writer = stream.try_clone()?;
                    return Ok(Link {
                        writer: Box::new(writer),
                        lines: spawn_reader(reader),
                        peer: Peer::Socket(stream),
                    });
                }
                Err(e) => last = e,
            }
        }
        Err(last)
    }

    fn exec(command: &str) -> std::io::Result<Link> {
        let mut adapter = Adapter::spawn(command)?;
        let stdin = adapter.child.stdin.take().expect("stdin is piped");
        let stdout = adapter.child.stdout.take().expect("stdout is piped");
        Ok(Link {
            writer: Box::new(stdin),
            lines: spawn_reader(stdout),
            peer: Peer::Process(adapter),
        })
    }

    /// Sends one line (a newline is added).
    pub fn send(&mut self, line: &str) -> Result<(), LinkError> {
        let mut bytes = Vec::with_capacity(line.len() + 1);
        bytes.extend_from_slice(line.as_bytes());
        bytes.push(b'\n');
        self.writer
            .write_all(&bytes)
            .and_then(|()| self.writer.flush())
            .map_err(|e| LinkError::Closed(e.to_string()))
    }

    /// The next line, without its newline.
    pub fn receive(&mut self, timeout: Duration) -> Result<String, LinkError> {
        match self.lines.recv_timeout(timeout) {
            Ok(Ok(line)) => Ok(line),
            Ok(Err(why)) => Err(LinkError::Closed(why)),
            Err(RecvTimeoutError::Timeout) => Err(LinkError::Timeout),
            Err(RecvTimeoutError::Disconnected) => Err(LinkError::Closed("link closed".into())),
        }
    }
}

impl Drop for Link {
    fn drop(&mut self) {
        match &mut self.peer {
            Peer::Socket(stream) => {
                let _ = stream.shutdown(Shutdown::Both);
            }
            Peer::Process(adapter) => adapter.end(),
        }
    }
}

/// Reads lines until the end of the stream, an error or an over-long line; the last message
/// on the channel says why it stopped.
fn spawn_reader<R: Read + Send + 'static>(source: R) -> Receiver<Result<String, String>> {
    let (sender, receiver) = mpsc::channel();
    thread::spawn(move || {
        let mut reader = BufReader::new(source);
        loop {
            let mut line = Vec::new();
            let read = (&mut reader)
                .take(MAX_LINE_BYTES + 1)
                .read_until(b'\n', &mut line);
            let message = match read {
                Ok(0) => Err("the device closed the link".to_string()),
                Ok(_) if line.last() != Some(&b'\n') && line.len() as u64 > MAX_LINE_BYTES => {
                    Err(format!("a line longer than {MAX_LINE_BYTES} bytes"))
                }
                Ok(_) => {
                    while matches!(line.last(), Some(b'\n' | b'\r')) {
                        line.pop();
                    }
                    Ok(String::from_utf8_lossy(&line).into_owned())
                }
                Err(e) => Err(e.to_string()),
            };
            let stop = message.is_err();
            if sender.send(message).is_err() || stop {
                return;
            }
        }
    });
    receiver
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn endpoints_parse_and_print() {
        let tcp: Endpoint = "tcp://127.0.0.1:7878".parse().unwrap();
        assert_eq!(tcp, Endpoint::Tcp("127.0.0.1:7878".into()));
        assert_eq!(tcp.to_string(), "tcp://127.0.0.1:7878");
        let exec: Endpoint = "exec:python3 adapter.py --port /dev/ttyUSB0"
            .parse()
            .unwrap();
        assert_eq!(
            exec,
            Endpoint::Exec("python3 adapter.py --port /dev/ttyUSB0".into())
        );
        for bad in [
            "127.0.0.1:7878",
            "tcp://host",
            "tcp://:80",
            "tcp://h:99999",
            "exec:  ",
        ] {
            assert!(bad.parse::<Endpoint>().is_err(), "{bad}");
        }
    }

    /// The processes whose command line contains `marker`.
    #[cfg(target_os = "linux")]
    fn processes_with(marker: &str) -> Vec<String> {
        std::fs::read_dir("/proc")
            .unwrap()
            .filter_map(|e| {
                let cmdline = std::fs::read(e.ok()?.path().join("cmdline")).ok()?;
                let cmdline = String::from_utf8_lossy(&cmdline).replace('\0', " ");
                cmdline.contains(marker).then_some(cmdline)
            })
            .collect()
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn a_dropped_exec_link_leaves_no_process_of_its_adapter() {
        // Sleeps with a unique duration: in the background, and in a new session (setsid),
        // out of the adapter's process group.
        let marker = format!("900.{}07", std::process::id());
        let command =
            format!("setsid sh -c 'sleep {marker}' & (sleep {marker} &) ; exec sleep {marker}");
        let link = Link::open(&Endpoint::Exec(command), Duration::from_secs(1)).unwrap();
        let started = std::time::Instant::now();
        while processes_with(&marker).len() < 4 && started.elapsed() < Duration::from_secs(10) {
            std::thread::sleep(Duration::from_millis(20));
        }
        assert!(
            processes_with(&marker).len() >= 4,
            "{:?}",
            processes_with(&marker)
        );
        drop(link);
        assert_eq!(processes_with(&marker), Vec::<String>::new());
    }

    #[test]
    fn exec_link_exchanges_lines_and_times_out() {
        // `cat` echoes every line back.
        let mut link = Link::open(&Endpoint::Exec("cat".into()), Duration::from_secs(1)).unwrap();
        link.send("{\"id\":1}").unwrap();
        assert_eq!(link.receive(Duration::from_secs(5)).unwrap(), "{\"id\":1}");
        assert_eq!(
            link.receive(Duration::from_millis(50)),
            Err(LinkError::Timeout)
        );
        let mut gone = Link::open(&Endpoint::Exec("true".into()), Duration::from_secs(1)).unwrap();
        assert!(matches!(
            gone.receive(Duration::from_secs(5)),
            Err(LinkError::Closed(_))
        ));
    }
}
