//! The shared secret of the driver protocol (`hello`'s token), shared by `device serve` and
//! `measure`: on the command line, in a file, or in the `SPECULA_TOKEN` environment variable
//! (a token on the command line shows in the process list; a file or the environment does
//! not).

use anyhow::{Context, Result};
use specula_session::protocol::Token;
use std::path::PathBuf;

/// The environment variable a token is read from when no flag gives one.
pub(crate) const TOKEN_VAR: &str = "SPECULA_TOKEN";

/// The largest token file read, bytes.
const MAX_TOKEN_FILE_BYTES: u64 = 4096;

#[derive(clap::Args, Clone, Debug)]
pub(crate) struct TokenArgs {
    /// The shared secret of `hello` (never empty). Visible in the process list: prefer
    /// --token-file or the SPECULA_TOKEN environment variable.
    #[arg(long, conflicts_with = "token_file")]
    pub token: Option<String>,
    /// A file holding the shared secret (surrounding whitespace ignored; at most 4096
    /// bytes). Without --token or --token-file, SPECULA_TOKEN is used when set.
    #[arg(long)]
    pub token_file: Option<PathBuf>,
}

impl TokenArgs {
    /// The token from the flag, the file or the environment, in that order; `None` when
    /// none gives one. An empty token is an error wherever it comes from.
    pub(crate) fn resolve(&self) -> Result<Option<Token>> {
        let (secret, origin) = if let Some(token) = &self.token {
            (token.clone(), "--token".to_string())
        } else if let Some(path) = &self.token_file {
            // Bounded: /dev/zero or a growing file claims a size of 0 and never ends.
            let bytes = specula_core::bounded_read::read_bounded(path, MAX_TOKEN_FILE_BYTES)
                .map_err(|e| {
                    anyhow::anyhow!(
                        "{}: cannot read the token file: {}",
                        path.display(),
                        specula_core::shown::io_cause(&e)
                    )
                })?;
            let text = String::from_utf8(bytes).map_err(|_| {
                anyhow::anyhow!("{}: the token file is not UTF-8 text", path.display())
            })?;
            (text, path.display().to_string())
        } else if let Some(value) = std::env::var_os(TOKEN_VAR) {
            let text = value
                .into_string()
                .map_err(|_| anyhow::anyhow!("{TOKEN_VAR} is not UTF-8"))?;
            (text, TOKEN_VAR.to_string())
        } else {
            return Ok(None);
        };
        Token::new(&secret)
            .map(Some)
            .with_context(|| format!("{origin}: not a usable token"))
    }
}
