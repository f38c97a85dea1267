//! `specula device`: the simulated device behind the driver protocol.

use super::token_args::{TokenArgs, TOKEN_VAR};
use anyhow::{bail, Context, Result};
use specula_session::ideal::simulated_instrument;
use specula_session::inputs::brdf_fingerprint;
use specula_session::protocol::{FaultSchedule, Server};
use std::net::{SocketAddr, TcpListener};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

/// Work with devices through the driver protocol (docs/book/src/driver-protocol.md).
#[derive(clap::Args)]
pub(crate) struct Args {
    #[command(subcommand)]
    pub command: DeviceCommand,
}

#[derive(clap::Subcommand)]
pub(crate) enum DeviceCommand {
    /// Serve the simulated device over the driver protocol, so that `specula measure --connect
    /// tcp://HOST:PORT` (or a client of your own) can drive it.
    Serve(ServeArgs),
}

#[derive(clap::Args)]
pub(crate) struct ServeArgs {
    /// The sample on the simulated turntable: a preset, a material .toml, a MERL .binary or
    /// a model:name fit.
    #[arg(long)]
    pub truth: String,
    /// Where to listen.
    #[arg(long, default_value = "127.0.0.1:7878")]
    pub listen: SocketAddr,
    /// A shared secret every client must send in `hello`.
    #[command(flatten)]
    pub token: TokenArgs,
    /// Serve one client on stdin and stdout instead of TCP (for --connect exec:...).
    #[arg(long, conflicts_with = "listen")]
    pub stdio: bool,
    /// Seed of the simulated device: its positioning errors and its noise.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Noise-free camera and exact positioning.
    #[arg(long)]
    pub ideal: bool,
    /// Device description (TOML; see `specula plan --print-device`); default: the paper's
    /// UTIA gonioreflectometer.
    #[arg(long, alias = "device-model")]
    pub device: Option<PathBuf>,
    /// Misbehave on purpose, to rehearse faults: comma-separated drop@N, slow@N=SECONDS,
    /// corrupt@N, motor@N, N counting requests from 1 over the server's life.
    #[arg(long, default_value = "")]
    pub inject_faults: String,
    /// Disconnect the controlling client when a request line does not arrive whole within this many
    /// seconds of the previous reply. Range: seconds above 0 and at most 86400.
    #[arg(long, default_value_t = 600.0, value_parser = crate::range::TIMEOUT_S)]
    pub idle_timeout: f64,
}

pub(crate) fn run(args: Args) -> Result<()> {
    match args.command {
        DeviceCommand::Serve(serve_args) => serve(serve_args),
    }
}

fn serve(args: ServeArgs) -> Result<()> {
    let token = args.token.resolve()?;
    if !args.stdio && !args.listen.ip().is_loopback() && token.is_none() {
        bail!(
            "--listen {}: serving beyond this machine needs a token (--token-file, {TOKEN_VAR} or --token; and a network you trust: the protocol is not encrypted)",
            args.listen
        );
    }
    let faults: FaultSchedule = args.inject_faults.parse().map_err(anyhow::Error::msg)?;
    let device = specula_acquisition::device::Device::load_or_utia(args.device.as_deref())?;
    let truth = specula_formats::source::load_brdf(&args.truth)?;
    // The truth's content hash goes in the server's name: a client reconnecting to a server
    // restarted with another truth (or an edited file of the same name) sees another device.
    // Nothing else of the truth crosses the wire, not even its name: a client calibrates and
    // measures it as it would a real sample.
    let fingerprint = brdf_fingerprint(truth.as_ref());
    let instrument = simulated_instrument(device, truth, args.seed, args.ideal);
    let name = format!("specula device serve (sample {})", &fingerprint[..16]);
    let mut server = Server::new(instrument, name)
        .with_token(token)
        .with_faults(faults);
    if args.stdio {
        let end = server.serve_connection(std::io::stdin().lock(), std::io::stdout().lock());
        eprintln!("specula device serve: {end}");
        return Ok(());
    }
    let listener = TcpListener::bind(args.listen)
        .with_context(|| format!("cannot listen on {}", args.listen))?;
    eprintln!(
        "serving {} on {} (Ctrl-C to stop)",
        args.truth,
        listener.local_addr()?
    );
    let never = AtomicBool::new(false);
    let idle = Duration::from_secs_f64(args.idle_timeout);
    server.serve_tcp(&listener, &never, idle, &mut |line| eprintln!("{line}"))?;
    Ok(())
}
