//! The checks that make a rerun resume the same measurement: the settings, the source, the
//! device model and the inputs' content a session started with, and the version of specula
//! that last wrote it. A session asked with other settings, or written by a newer specula,
//! is refused with the differences in words.

use crate::connection::Source;
use crate::inputs::{brdf_fingerprint, sha256_hex, InputHashes};
use crate::journal::{
    DeviceRecord, Journal, MeasureSettings, NewestVersionRecord, SourceRecord, VersionRecord,
};
use crate::workflow_error::WorkflowError;
use specula_acquisition::device::Device;
use specula_core::grid::UnresolvedPeak;
use specula_core::GridSpec;
use std::path::Path;

/// The grid an existing session journal measures on, `None` when `session` does not exist
/// yet or holds no settings. A front end resumes on it unless told another grid (which
/// [`crate::workflow::measure`] then refuses as a change of settings): a journal written
/// before the graded theta_d and the half turn of phi_d continues on the paper's grid it
/// started with, not on today's default. A session another process is writing is refused
/// ([`Journal::refuse_in_use`]).
pub fn session_grid(session: &Path) -> Result<Option<GridSpec>, WorkflowError> {
    Ok(session_settings(session)?.map(|s| s.grid))
}

/// The settings an existing session journal measures with, `None` when `session` does not
/// exist yet or holds none; a session another process is writing is refused.
pub fn session_settings(session: &Path) -> Result<Option<MeasureSettings>, WorkflowError> {
    if !session.exists() {
        return Ok(None);
    }
    Journal::refuse_in_use(session)?;
    let journal = Journal::open_read_only(session)?;
    Ok(journal.record::<MeasureSettings>()?)
}

/// The content hashes of what a session measures from (see [`crate::inputs`]).
pub(crate) fn input_hashes(source: &Source, device: &Device) -> InputHashes {
    let (truth, calibration) = match source {
        Source::Simulated { truth, .. } => (Some(brdf_fingerprint(truth.as_ref())), None),
        Source::Remote { calibration, .. } => {
            let json = serde_json::to_vec(calibration.as_ref()).unwrap_or_default();
            (None, Some(sha256_hex(&json)))
        }
    };
    InputHashes {
        truth,
        device_model: sha256_hex(device.to_toml_string().as_bytes()),
        calibration,
    }
}

/// Records the settings of a new session, or checks that a resumed one asks the same.
pub(crate) fn start_session(
    journal: &Journal,
    settings: &MeasureSettings,
    source: &SourceRecord,
    device: &Device,
) -> Result<(), WorkflowError> {
    let session = journal.path().display().to_string();
    let stored: MeasureSettings = journal.record_or_insert(|| settings.clone())?;
    if stored != *settings {
        return Err(WorkflowError::Settings {
            session,
            differences: differences(&stored, settings),
        });
    }
    let stored_source = journal.record_or_insert(|| source.clone())?;
    if stored_source != *source {
        return Err(WorkflowError::Source {
            session,
            stored: stored_source,
            asked: source.clone(),
        });
    }
    let stored_device = journal.record_or_insert(|| DeviceRecord(device.to_toml_string()))?;
    if stored_device.0 != device.to_toml_string() {
        return Err(WorkflowError::DeviceModel { session });
    }
    journal.record_or_insert(|| VersionRecord(THIS_VERSION.to_string()))?;
    Ok(())
}

/// This build's version.
const THIS_VERSION: &str = env!("CARGO_PKG_VERSION");

/// Refuses a session written by a newer specula (same schema, but an older build may measure
/// or reconstruct it differently); a session from an older one is resumed, and this build
/// recorded as its newest writer (with an event saying so).
pub(crate) fn check_version(journal: &Journal) -> Result<(), WorkflowError> {
    let newest = match journal.record::<NewestVersionRecord>()? {
        Some(NewestVersionRecord(v)) => Some(v),
        None => journal.record::<VersionRecord>()?.map(|VersionRecord(v)| v),
    };
    match newest.as_deref() {
        Some(v) if v == THIS_VERSION => return Ok(()),
        Some(v) if !is_older_version(v, THIS_VERSION) => {
            return Err(WorkflowError::NewerVersion {
                session: journal.path().display().to_string(),
                journal: v.to_string(),
                this: THIS_VERSION.to_string(),
            })
        }
        Some(v) => journal.log_event(
            "version",
            &format!("resumed by specula {THIS_VERSION}; last written by specula {v}"),
        )?,
        None => {}
    }
    journal.put_record(&NewestVersionRecord(THIS_VERSION.to_string()))?;
    Ok(())
}

/// Whether version `a` comes before `b` (dotted numbers, compared number by number; a
/// pre-release or build suffix after `-` or `+` is ignored). A version that does not read
/// as dotted numbers is not older.
fn is_older_version(a: &str, b: &str) -> bool {
    let numbers = |v: &str| -> Option<Vec<u64>> {
        v.split(['-', '+'])
            .next()?
            .split('.')
            .map(|n| n.parse().ok())
            .collect()
    };
    match (numbers(a), numbers(b)) {
        (Some(a), Some(b)) => a < b,
        _ => false,
    }
}

/// The settings that differ, in words: `SETTING: SESSION'S in the session, ASKED asked`,
/// joined by `; ` (the grid's parts one by one, each as its option reads).
fn differences(stored: &MeasureSettings, asked: &MeasureSettings) -> String {
    let mut found = Vec::new();
    let mut differ = |name: &str, a: String, b: String| {
        if a != b {
            found.push(format!("{name}: {a} in the session, {b} asked"));
        }
    };
    let yes_no = |v: bool| if v { "on" } else { "off" }.to_string();
    differ("--seed", stored.seed.to_string(), asked.seed.to_string());
    differ("--ideal", yes_no(stored.ideal), yes_no(asked.ideal));
    differ(
        "--point-light",
        yes_no(stored.point_light),
        yes_no(asked.point_light),
    );
    differ(
        "--probe-samples",
        stored.probe_samples.to_string(),
        asked.probe_samples.to_string(),
    );
    differ(
        "--family",
        stored.family.to_string(),
        asked.family.to_string(),
    );
    grid_differences(&stored.grid, &asked.grid, &mut differ);
    differ("--order", stored.order.to_string(), asked.order.to_string());
    differ("--hdr", stored.hdr.to_string(), asked.hdr.to_string());
    differ(
        "--method",
        stored.method.to_string(),
        asked.method.to_string(),
    );
    differ(
        "deblurring (--no-deblur)",
        yes_no(stored.deblur),
        yes_no(asked.deblur),
    );
    differ(
        "the checks (--skip-checks)",
        yes_no(stored.checks),
        yes_no(asked.checks),
    );
    let strategy = |s: &MeasureSettings| match s.sequential {
        Some(l) => format!(
            "sequential to {} h and {} samples{}",
            l.max_hours,
            l.max_samples,
            l.target_uncertainty_rel
                .map_or(String::new(), |t| format!(" or {} %", 100.0 * t))
        ),
        None => "the whole grid".to_string(),
    };
    differ(
        "the main stage (--grid-preset, --max-hours, --max-samples, --target-uncertainty)",
        strategy(stored),
        strategy(asked),
    );
    let deg = |v: f64| format!("{v} deg");
    differ("--tilt", deg(stored.tilt_deg), deg(asked.tilt_deg));
    differ(
        "--tilt-azimuth",
        deg(stored.tilt_azimuth_deg),
        deg(asked.tilt_azimuth_deg),
    );
    found.join("; ")
}

/// The grid's parts that differ, named as the options that set them.
fn grid_differences(
    stored: &GridSpec,
    asked: &GridSpec,
    differ: &mut dyn FnMut(&str, String, String),
) {
    differ(
        "--theta-h-samples",
        stored.theta_h_samples.to_string(),
        asked.theta_h_samples.to_string(),
    );
    differ(
        "--theta-d-step",
        stored.theta_d.to_string(),
        asked.theta_d.to_string(),
    );
    let deg = |v: f64| format!("{v} deg");
    differ(
        "--phi-d-step",
        deg(stored.phi_d_step_deg),
        deg(asked.phi_d_step_deg),
    );
    differ(
        "--phi-d-span",
        stored.phi_d_span.to_string(),
        asked.phi_d_span.to_string(),
    );
    differ("--phi-h", deg(stored.phi_h_deg), deg(asked.phi_h_deg));
    let peak = |rule: &Option<UnresolvedPeak>| match rule {
        Some(rule) => format!(
            "up to {} theta_h with theta_d step {} deg within {} samples",
            rule.theta_h_samples, rule.theta_d, rule.budget_samples
        ),
        None => "none".to_string(),
    };
    differ(
        "the rule for a peak the instrument does not resolve (--grid-preset)",
        peak(&stored.unresolved_peak),
        peak(&asked.unresolved_peak),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn versions_compare_number_by_number() {
        assert!(is_older_version("0.1.0", "0.2.0"));
        assert!(is_older_version("0.9.9", "0.10.0"));
        assert!(is_older_version("1.2", "1.2.1"));
        assert!(!is_older_version("0.2.0", "0.1.0"));
        assert!(!is_older_version("0.1.0", "0.1.0"));
        assert!(!is_older_version("0.1.0-rc1+x", "0.1.0"));
        assert!(
            !is_older_version("garbage", "0.1.0"),
            "unreadable: not older"
        );
    }

    #[test]
    fn settings_differences_name_the_field() {
        let a = MeasureSettings::default();
        let b = MeasureSettings {
            seed: 7,
            ..MeasureSettings::default()
        };
        assert_eq!(differences(&a, &b), "--seed: 1 in the session, 7 asked");
        // The recommended grid's rule for an unresolved peak against the paper's grid: in
        // words, not the record's JSON.
        let paper = MeasureSettings {
            grid: GridSpec::paper(),
            ..MeasureSettings::default()
        };
        let recommended = MeasureSettings {
            grid: GridSpec {
                unresolved_peak: Some(UnresolvedPeak {
                    theta_h_samples: 30,
                    theta_d: specula_core::ThetaDSteps::even(3.0),
                    budget_samples: 4073,
                }),
                ..GridSpec::paper()
            },
            ..MeasureSettings::default()
        };
        let text = differences(&recommended, &paper);
        assert_eq!(
            text,
            "the rule for a peak the instrument does not resolve (--grid-preset): up to 30 \
             theta_h with theta_d step 3 deg within 4073 samples in the session, none asked"
        );
    }
}
