//! Pass/fail verdicts: the largest allowed difference of each figure to a reference, read
//! from a tolerance file, and the verdict of a sample's differences against them.
//!
//! A tolerance file is TOML with one table, `[tolerances]`, holding one key per figure:
//!
//! ```toml
//! [tolerances]
//! gloss_20 = 5.0   # largest |difference| in gloss units at 20 deg
//! de00_15 = 1.0    # largest CIEDE2000 at 15 deg aspecular
//! ```
//!
//! The keys are the names of [`difference_names`] (the CSV's difference columns without
//! their `d_` prefix); each value is the largest allowed absolute difference, in the
//! figure's unit. A figure without a key is not judged; a judged figure the sample lacks
//! (a colour reading its table has not measured) fails, since nothing vouches for it.

use crate::figures::{difference_names, Differences};
use std::fmt;
use std::path::{Path, PathBuf};

/// Why a tolerance file could not be used.
#[derive(Debug, thiserror::Error)]
pub enum ToleranceError {
    /// The file could not be read.
    #[error("{}: cannot read the tolerance file: {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The file is not a tolerance file (its TOML or its layout).
    #[error("{}: {problem}", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// What is wrong, on one line.
        problem: String,
    },
}

/// The largest allowed absolute difference per figure, in [`difference_names`] order.
#[derive(Debug, Clone, PartialEq)]
pub struct Tolerances {
    limits: Vec<(String, f64)>,
}

impl Tolerances {
    /// Reads a tolerance file (see the module documentation).
    pub fn read(path: &Path) -> Result<Self, ToleranceError> {
        let text = std::fs::read_to_string(path).map_err(|source| ToleranceError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        Self::parse(&text).map_err(|problem| ToleranceError::Invalid {
            path: path.to_path_buf(),
            problem,
        })
    }

    /// Tolerances from the text of a tolerance file; the error is one line saying what is
    /// wrong.
    pub fn parse(text: &str) -> Result<Self, String> {
        let table: toml::Table = text
            .parse()
            .map_err(|e| specula_core::toml_error::one_line(text, &e))?;
        if let Some(key) = table.keys().find(|k| *k != "tolerances") {
            return Err(format!(
                "unknown table or key `{key}` (a tolerance file holds one table, [tolerances])"
            ));
        }
        let Some(entries) = table.get("tolerances") else {
            return Err("no [tolerances] table".into());
        };
        let Some(entries) = entries.as_table() else {
            return Err("`tolerances` must be a table, [tolerances]".into());
        };
        let names = difference_names();
        if let Some(key) = entries.keys().find(|k| !names.contains(k)) {
            return Err(format!(
                "unknown figure `{key}` in [tolerances] (known: {})",
                names.join(", ")
            ));
        }
        let mut limits = Vec::new();
        for name in names {
            let Some(value) = entries.get(&name) else {
                continue;
            };
            let limit = value
                .as_float()
                .or_else(|| value.as_integer().map(|i| i as f64))
                .filter(|v| v.is_finite() && *v >= 0.0)
                .ok_or_else(|| {
                    format!("`{name}` must be a number of at least 0 (the largest allowed |difference|), not {value}")
                })?;
            limits.push((name, limit));
        }
        if limits.is_empty() {
            return Err("[tolerances] names no figure".into());
        }
        Ok(Self { limits })
    }

    /// The figures judged and their largest allowed absolute differences.
    pub fn limits(&self) -> &[(String, f64)] {
        &self.limits
    }

    /// The verdict on a sample's differences to the reference.
    pub fn verdict(&self, differences: &Differences) -> Verdict {
        let values = differences.values();
        let names = difference_names();
        let failing = self
            .limits
            .iter()
            .filter(|(name, limit)| {
                let value = names.iter().position(|n| n == name).and_then(|i| values[i]);
                value.is_none_or(|v| v.abs() > *limit)
            })
            .map(|(name, _)| name.clone())
            .collect();
        Verdict { failing }
    }
}

/// Whether a sample is inside every tolerance; shown as `pass` or `fail: gloss_20, de00_15`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Verdict {
    /// The figures outside their tolerance (or unknown), in [`difference_names`] order.
    pub failing: Vec<String>,
}

impl Verdict {
    /// True when every judged figure is inside its tolerance.
    pub fn passes(&self) -> bool {
        self.failing.is_empty()
    }
}

impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.passes() {
            write!(f, "pass")
        } else {
            write!(f, "fail: {}", self.failing.join(", "))
        }
    }
}
