//! `specula session`: what a measurement session's journal holds.

use anyhow::Result;
use specula_session::journal::SessionRecord;
use std::path::PathBuf;

/// Inspect measurement sessions (the SQLite journals of `specula measure`).
#[derive(clap::Args)]
pub(crate) struct Args {
    #[command(subcommand)]
    pub command: SessionCommand,
}

#[derive(clap::Subcommand)]
pub(crate) enum SessionCommand {
    /// Progress of a session: samples measured and left per stage, captures, the device time spent
    /// and the estimate of what is left (the progress bar's: the time model scaled by how the
    /// finished samples compared with it), faults and resumptions.
    Status {
        /// The session journal (.sqlite).
        session: PathBuf,
    },
}

pub(crate) fn run(args: Args) -> Result<()> {
    match args.command {
        SessionCommand::Status { session } => status(&session),
    }
}

fn status(path: &std::path::Path) -> Result<()> {
    for line in SessionRecord::read(path)?.status_lines(path) {
        outln!("{line}");
    }
    Ok(())
}
