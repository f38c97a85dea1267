//! What `specula session status` prints of a journal: its settings, checks, fit, plan, each
//! stage's progress, a sequential measurement's batches, the events and the state.

use super::{SessionRecord, SessionState, SessionStatus};
use specula_core::shown::{duration_text, plain};
use std::path::Path;

impl SessionRecord {
    /// The session at `path` in lines, as `specula session status` prints them.
    pub fn status_lines(&self, path: &Path) -> Vec<String> {
        let status: &SessionStatus = &self.status;
        let mut lines = vec![format!(
            "session: {} (schema {})",
            path.display(),
            status.schema_version
        )];
        if let Some(source) = &self.source {
            lines.push(format!("measures: {source}"));
        }
        if let Some(settings) = &self.settings {
            lines.push(format!(
                "settings: seed {}, {} probe samples, {} function, order {}, hdr {}{}",
                settings.seed,
                settings.probe_samples,
                settings.family,
                settings.order,
                settings.hdr,
                if settings.ideal { ", ideal" } else { "" }
            ));
            lines.push(format!("grid: {}", settings.grid));
            if let Some(limits) = &settings.sequential {
                lines.push(format!("main stage: {limits}"));
            }
        }
        if let Some(checks) = &self.checks {
            lines.push(format!("alignment: {}", checks.alignment));
            lines.push(format!("orientation: {}", checks.orientation));
        }
        if let Some(fit) = &self.fit {
            lines.push(format!(
                "k-hat: {} ({}), fit error {} 1/sr",
                plain(fit.function.k),
                fit.function.family,
                plain(fit.error)
            ));
            if let Some(grid) = fit.grid {
                lines.push(format!("planned on: {grid}"));
            }
        }
        if let Some(plan) = &self.plan {
            lines.push(format!(
                "plan: {} samples, {} measurable, {} beyond the axes' limits, {} occluded",
                plan.total, plan.measurable, plan.limit, plan.occluded
            ));
        }
        for stage in &status.stages {
            let percent = 100.0 * stage.done as f64 / stage.planned.max(1) as f64;
            lines.push(format!(
                "{}: {} of {} samples ({percent:.1} %), {} captures; device time {} spent, about {} left; wall time {}",
                stage.stage,
                stage.done,
                stage.planned,
                stage.captures,
                duration_text(stage.device_s_done),
                duration_text(stage.eta_device_s()),
                duration_text(stage.wall_s_done)
            ));
        }
        if let Some(sequence) = &self.sequence {
            let sizes: Vec<String> = sequence
                .batches
                .iter()
                .map(|b| b.samples.to_string())
                .collect();
            lines.push(format!(
                "batches: {} ({} samples){}",
                sequence.batches.len(),
                sizes.join(" + "),
                sequence
                    .stopped
                    .as_ref()
                    .map_or(String::new(), |r| format!("; stopped: {r}"))
            ));
        }
        if !status.events.is_empty() {
            let counts: Vec<String> = status
                .events
                .iter()
                .map(|(k, n)| format!("{k} {n}"))
                .collect();
            lines.push(format!("events: {}", counts.join(", ")));
            for (_, kind, message) in &status.recent_events {
                lines.push(format!("  {kind}: {message}"));
            }
        }
        lines.push(format!(
            "state: {}",
            match status.state() {
                SessionState::Complete => "complete",
                SessionState::Measured => "all samples measured; reconstruction not written yet",
                SessionState::InProgress =>
                    "in progress or interrupted: run the same measure command to resume",
            }
        ));
        lines
    }
}
