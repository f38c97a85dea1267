//! The driver protocol: the [`Instrument`](specula_acquisition::instrument::Instrument)
//! interface carried as JSON lines over TCP or over a child process's stdin and stdout, so
//! that a lab can connect its own hardware by writing a small adapter in any language.
//! `docs/driver-protocol.md` is the specification; `tools/example_adapter.py` an adapter.
//!
//! - [`message`]: the request and reply lines;
//! - [`link`]: the transports (`tcp://HOST:PORT`, `exec:COMMAND`) with reply timeouts;
//! - [`client`]: [`RemoteInstrument`], retries with backoff and reconnection;
//! - [`server`]: [`Server`], any instrument served over a connection;
//! - [`validate`]: the ranges every reply must respect;
//! - [`faults`]: faults a server injects on purpose, for rehearsals and tests.

pub mod client;
pub mod faults;
#[cfg(target_os = "linux")]
mod guardian;
pub mod link;
pub mod message;
pub mod server;
pub mod validate;

pub use client::{ClientSettings, RemoteInstrument};
pub use faults::{Fault, FaultSchedule};
pub use link::Endpoint;
pub use server::{ConnectionEnd, ServeLimits, Server, Token, TokenError};
