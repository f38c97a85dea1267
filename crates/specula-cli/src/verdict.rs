//! A tolerance verdict that failed: the run finished, but a sample lies outside its
//! tolerances, which scripts tell by the exit code.

/// The exit code when a sample fails its tolerances (`appearance`, `report`).
pub(crate) const FAILED_EXIT: u8 = 3;

/// Some samples failed their tolerances: `main` prints it as one line and exits with
/// [`FAILED_EXIT`].
#[derive(Debug)]
pub(crate) struct Failed {
    /// Samples outside their tolerances.
    pub(crate) failed: usize,
    /// Samples judged.
    pub(crate) judged: usize,
}

impl std::fmt::Display for Failed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} of {} samples outside their tolerances",
            self.failed, self.judged
        )
    }
}

impl std::error::Error for Failed {}

/// `Err(Failed)` when any verdict fails, else `Ok`.
pub(crate) fn check(verdicts: &[specula_appearance::Verdict]) -> anyhow::Result<()> {
    let failed = verdicts.iter().filter(|v| !v.passes()).count();
    if failed > 0 {
        return Err(Failed {
            failed,
            judged: verdicts.len(),
        }
        .into());
    }
    Ok(())
}
