//! Faults a server injects on purpose, to rehearse what a flaky link or device does to a
//! measurement (`specula device serve --inject-faults drop@40,slow@80=3,corrupt@120,motor@160`)
//! and to test the client's retries.

use std::collections::BTreeMap;
use std::str::FromStr;
use std::time::Duration;

/// What happens to one request.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Fault {
    /// The connection closes without a reply.
    Drop,
    /// The reply comes after this delay.
    Slow(Duration),
    /// The request is carried out but the reply line is garbage.
    Corrupt,
    /// The device answers with a motor fault instead of carrying the request out.
    MotorFault,
}

/// Faults by request number: the n-th request the server receives over its life (all
/// connections, `hello` included, from 1).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FaultSchedule {
    at: BTreeMap<u64, Fault>,
}

impl FaultSchedule {
    /// A schedule without faults.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a fault at request `n` (replacing one there).
    pub fn with(mut self, n: u64, fault: Fault) -> Self {
        self.at.insert(n, fault);
        self
    }

    /// The fault of request `n`, if any.
    pub fn fault_at(&self, n: u64) -> Option<Fault> {
        self.at.get(&n).copied()
    }

    /// True when no request has a fault.
    pub fn is_empty(&self) -> bool {
        self.at.is_empty()
    }
}

impl FromStr for FaultSchedule {
    type Err = String;

    /// A comma-separated list of `KIND@N`: `drop@N`, `slow@N=SECONDS`, `corrupt@N`,
    /// `motor@N`.
    fn from_str(s: &str) -> Result<Self, String> {
        let mut schedule = FaultSchedule::new();
        for item in s.split(',').map(str::trim).filter(|i| !i.is_empty()) {
            let bad =
                || format!("fault '{item}': expected drop@N, slow@N=SECONDS, corrupt@N or motor@N");
            let (kind, rest) = item.split_once('@').ok_or_else(bad)?;
            let (n, seconds) = match rest.split_once('=') {
                Some((n, s)) => (n, Some(s)),
                None => (rest, None),
            };
            let n: u64 = n.parse().map_err(|_| bad())?;
            if n == 0 {
                return Err(format!("fault '{item}': requests count from 1"));
            }
            let fault = match (kind, seconds) {
                ("drop", None) => Fault::Drop,
                ("corrupt", None) => Fault::Corrupt,
                ("motor", None) => Fault::MotorFault,
                ("slow", Some(s)) => {
                    let s: f64 = s.parse().map_err(|_| bad())?;
                    if !(s.is_finite() && s >= 0.0) {
                        return Err(bad());
                    }
                    Fault::Slow(Duration::from_secs_f64(s))
                }
                _ => return Err(bad()),
            };
            schedule.at.insert(n, fault);
        }
        Ok(schedule)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schedules_parse() {
        let s: FaultSchedule = "drop@4, slow@9=0.25,corrupt@12,motor@20".parse().unwrap();
        assert_eq!(s.fault_at(4), Some(Fault::Drop));
        assert_eq!(s.fault_at(9), Some(Fault::Slow(Duration::from_millis(250))));
        assert_eq!(s.fault_at(12), Some(Fault::Corrupt));
        assert_eq!(s.fault_at(20), Some(Fault::MotorFault));
        assert_eq!(s.fault_at(5), None);
        for bad in [
            "drop",
            "drop@x",
            "slow@3",
            "slow@3=-1",
            "melt@3",
            "drop@0",
            "drop@3=1",
        ] {
            assert!(bad.parse::<FaultSchedule>().is_err(), "{bad}");
        }
        assert!("".parse::<FaultSchedule>().unwrap().is_empty());
    }
}
