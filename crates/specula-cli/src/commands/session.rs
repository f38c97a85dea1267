//! `specula session`: what a measurement session's journal holds.

use anyhow::Result;
use specula_core::shown::duration_text;
use specula_session::journal::{SessionRecord, SessionState, SessionStatus};
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
    let record = SessionRecord::read(path)?;
    let status: &SessionStatus = &record.status;
    outln!(
        "session: {} (schema {})",
        path.display(),
        status.schema_version
    );
    if let Some(source) = &record.source {
        outln!("measures: {source}");
    }
    if let Some(settings) = &record.settings {
        outln!(
            "settings: seed {}, {} probe samples, {} function, order {}, hdr {}{}",
            settings.seed,
            settings.probe_samples,
            settings.family,
            settings.order,
            settings.hdr,
            if settings.ideal { ", ideal" } else { "" }
        );
        outln!("grid: {}", settings.grid);
    }
    if let Some(checks) = &record.checks {
        outln!("alignment: {}", checks.alignment);
        outln!("orientation: {}", checks.orientation);
    }
    if let Some(fit) = &record.fit {
        outln!(
            "k-hat: {} ({}), fit error {} 1/sr",
            crate::output::plain(fit.function.k),
            fit.function.family,
            crate::output::plain(fit.error)
        );
        if let Some(grid) = fit.grid {
            outln!("planned on: {grid}");
        }
    }
    if let Some(plan) = &record.plan {
        outln!(
            "plan: {} samples, {} measurable, {} beyond the axes' limits, {} occluded",
            plan.total,
            plan.measurable,
            plan.limit,
            plan.occluded
        );
    }
    for stage in &status.stages {
        let percent = 100.0 * stage.done as f64 / stage.planned.max(1) as f64;
        outln!(
            "{}: {} of {} samples ({percent:.1} %), {} captures; device time {} spent, about {} left; wall time {}",
            stage.stage,
            stage.done,
            stage.planned,
            stage.captures,
            duration_text(stage.device_s_done),
            duration_text(stage.eta_device_s()),
            duration_text(stage.wall_s_done)
        );
    }
    if !status.events.is_empty() {
        let counts: Vec<String> = status
            .events
            .iter()
            .map(|(k, n)| format!("{k} {n}"))
            .collect();
        outln!("events: {}", counts.join(", "));
        for (_, kind, message) in &status.recent_events {
            outln!("  {kind}: {message}");
        }
    }
    outln!(
        "state: {}",
        match status.state() {
            SessionState::Complete => "complete",
            SessionState::Measured => "all samples measured; reconstruction not written yet",
            SessionState::InProgress =>
                "in progress or interrupted: run the same measure command to resume",
        }
    );
    Ok(())
}
