//! How to reach a device through the driver protocol, shared by `measure` and `calibrate`:
//! the token and the client's patience.

use super::token_args::TokenArgs;
use crate::range;
use anyhow::Result;
use specula_session::protocol::{ClientSettings, Endpoint, RemoteInstrument};
use std::time::Duration;

#[derive(clap::Args, Clone, Debug)]
pub(crate) struct ConnectArgs {
    /// Shared token for a server that asks for one (`specula device serve --token-file`).
    #[command(flatten)]
    pub token: TokenArgs,
    /// Seconds to wait for a device's reply. Range: seconds above 0 and at most 86400.
    #[arg(hide_short_help = true, long, default_value_t = 120.0, value_parser = range::TIMEOUT_S)]
    pub reply_timeout: f64,
    /// Failures in a row before giving up. Range: a whole number from 1 to 100.
    #[arg(hide_short_help = true, long, default_value_t = 5, value_parser = range::FAILURES)]
    pub max_failures: usize,
}

impl ConnectArgs {
    /// The client's settings these options give.
    pub(crate) fn client_settings(&self) -> Result<ClientSettings> {
        Ok(ClientSettings {
            reply_timeout: Duration::from_secs_f64(self.reply_timeout),
            max_failures: u32::try_from(self.max_failures).unwrap_or(u32::MAX),
            token: self.token.resolve()?.map(|t| t.secret().to_string()),
            ..ClientSettings::default()
        })
    }

    /// A client of `spec` (`tcp://HOST:PORT` or `exec:COMMAND`), not yet connected.
    pub(crate) fn client(&self, spec: &str) -> Result<RemoteInstrument> {
        let endpoint: Endpoint = spec.parse().map_err(anyhow::Error::msg)?;
        Ok(RemoteInstrument::new(endpoint, self.client_settings()?))
    }
}
