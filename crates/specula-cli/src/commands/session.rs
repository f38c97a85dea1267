//! `specula session`: what a measurement session's journal holds.

use anyhow::Result;
use specula_session::journal::{SessionRecord, SessionStatus};
use std::path::PathBuf;

/// Inspect measurement sessions (the SQLite journals of `specula measure`).
#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    pub command: SessionCommand,
}

#[derive(clap::Subcommand)]
pub enum SessionCommand {
    /// Progress of a session: samples measured and left per stage, captures, the device time
    /// spent and the time model's estimate of what is left, faults and resumptions. Safe to
    /// run while the measurement goes on.
    Status {
        /// The session journal (.sqlite).
        session: PathBuf,
    },
}

pub fn run(args: Args) -> Result<()> {
    match args.command {
        SessionCommand::Status { session } => status(&session),
    }
}

fn hours(seconds: f64) -> String {
    format!("{:.2} h", seconds / 3600.0)
}

fn status(path: &std::path::Path) -> Result<()> {
    let record = SessionRecord::read(path)?;
    let status: &SessionStatus = &record.status;
    println!(
        "session: {} (schema {})",
        path.display(),
        status.schema_version
    );
    if let Some(source) = &record.source {
        println!("measures: {source}");
    }
    if let Some(settings) = &record.settings {
        println!(
            "settings: seed {}, {} probe samples, {} theta_h ({}), theta_d step {} deg, phi_d step {} deg, order {:?}, hdr {:?}{}",
            settings.seed,
            settings.probe_samples,
            settings.theta_h_samples,
            settings.family,
            settings.theta_d_step_deg,
            settings.phi_d_step_deg,
            settings.order,
            settings.hdr,
            if settings.ideal { ", ideal" } else { "" }
        );
    }
    if let Some(checks) = &record.checks {
        println!("alignment: {}", checks.alignment);
        println!("orientation: {}", checks.orientation);
    }
    if let Some(fit) = &record.fit {
        println!(
            "k-hat: {:.4} ({}), fit error {:.4e}",
            fit.function.k, fit.function.family, fit.error
        );
    }
    if let Some(plan) = &record.plan {
        println!(
            "plan: {} samples, {} measurable, {} beyond the axes' limits, {} occluded",
            plan.total, plan.measurable, plan.limit, plan.occluded
        );
    }
    let mut complete = !status.stages.is_empty();
    for stage in &status.stages {
        let percent = 100.0 * stage.done as f64 / stage.planned.max(1) as f64;
        println!(
            "{}: {} of {} samples ({percent:.1} %), {} captures; device time {} spent, about {} left (time model); wall time {}",
            stage.stage,
            stage.done,
            stage.planned,
            stage.captures,
            hours(stage.device_s_done),
            hours(stage.predicted_s_left),
            hours(stage.wall_s_done)
        );
        complete &= stage.done == stage.planned;
    }
    if !status.events.is_empty() {
        let counts: Vec<String> = status
            .events
            .iter()
            .map(|(k, n)| format!("{k} {n}"))
            .collect();
        println!("events: {}", counts.join(", "));
        for (_, kind, message) in &status.recent_events {
            println!("  {kind}: {message}");
        }
    }
    let finished = status.events.contains_key("complete");
    println!(
        "state: {}",
        match (finished, complete) {
            (true, _) => "complete",
            (false, true) => "all samples measured; reconstruction not written yet",
            (false, false) => "in progress or interrupted: run the same measure command to resume",
        }
    );
    Ok(())
}
