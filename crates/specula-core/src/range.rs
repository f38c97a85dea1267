//! The checked range of a number a user gives (an option of the CLI, an argument of the
//! Python package), in words: both front ends refuse a value outside it with the same
//! one-line message, `OPTION VALUE: expected WORDS` (OPTION the CLI's flag or the Python
//! argument), and the CLI ends the option's help
//! with `Range: WORDS`.

/// A value outside its range: `OPTION VALUE: expected WORDS`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{option} {value}: expected {expected}")]
pub struct RangeError {
    /// The option or argument, as the front end names it (`--theta-h-samples`,
    /// `theta_h_samples`).
    pub option: String,
    /// The value as given.
    pub value: String,
    /// The range in words.
    pub expected: String,
}

/// A real number between two finite bounds, in a unit: degrees, seconds, stops, ...
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RealRange {
    /// The lower bound.
    pub min: f64,
    /// The upper bound, included.
    pub max: f64,
    /// The minimum itself is refused (a step, a timeout: above 0).
    pub above_min: bool,
    /// The unit in words: `degrees`, `seconds`, `a number`.
    pub unit: &'static str,
}

impl RealRange {
    /// Values from `min` to `max`, both included, in `unit`.
    pub const fn from_to(min: f64, max: f64, unit: &'static str) -> Self {
        Self {
            min,
            max,
            above_min: false,
            unit,
        }
    }

    /// Values above `min` (excluded) up to `max` (included), in `unit`.
    pub const fn above(min: f64, max: f64, unit: &'static str) -> Self {
        Self {
            min,
            max,
            above_min: true,
            unit,
        }
    }

    /// The range in words, as the CLI's `--help` and the error say it.
    pub fn words(&self) -> String {
        if self.above_min {
            format!("{} above {} and at most {}", self.unit, self.min, self.max)
        } else {
            format!("{} from {} to {}", self.unit, self.min, self.max)
        }
    }

    /// Whether `value` lies in the range (NaN never does).
    pub fn contains(&self, value: f64) -> bool {
        let above = if self.above_min {
            value > self.min
        } else {
            value >= self.min
        };
        above && value <= self.max
    }

    /// `value` when it lies in the range, else the error naming `option`.
    pub fn check(&self, option: &str, value: f64) -> Result<f64, RangeError> {
        if self.contains(value) {
            Ok(value)
        } else {
            Err(self.refuse(option, &value.to_string()))
        }
    }

    /// The error of `value` (as given, e.g. text that is no number) for `option`.
    pub fn refuse(&self, option: &str, value: &str) -> RangeError {
        refuse(option, value, self.words())
    }
}

/// A whole number between two bounds (a count of samples, pixels, tries).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CountRange {
    /// The lower bound, included.
    pub min: usize,
    /// The upper bound, included.
    pub max: usize,
}

impl CountRange {
    /// Counts from `min` to `max`, both included.
    pub const fn from_to(min: usize, max: usize) -> Self {
        Self { min, max }
    }

    /// The range in words, as the CLI's `--help` and the error say it.
    pub fn words(&self) -> String {
        format!("a whole number from {} to {}", self.min, self.max)
    }

    /// Whether `value` lies in the range.
    pub fn contains(&self, value: usize) -> bool {
        (self.min..=self.max).contains(&value)
    }

    /// `value` when it lies in the range, else the error naming `option`.
    pub fn check(&self, option: &str, value: usize) -> Result<usize, RangeError> {
        if self.contains(value) {
            Ok(value)
        } else {
            Err(self.refuse(option, &value.to_string()))
        }
    }

    /// The error of `value` (as given, e.g. text that is no number) for `option`.
    pub fn refuse(&self, option: &str, value: &str) -> RangeError {
        refuse(option, value, self.words())
    }
}

fn refuse(option: &str, value: &str, expected: String) -> RangeError {
    RangeError {
        option: option.to_string(),
        value: value.to_string(),
        expected,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_read_in_words_and_refuse_nan() {
        let elevation = RealRange::above(0.0, 90.0, "degrees");
        let phi_d = RealRange::from_to(0.0, 180.0, "degrees");
        assert_eq!(elevation.words(), "degrees above 0 and at most 90");
        assert_eq!(phi_d.words(), "degrees from 0 to 180");
        assert!(!elevation.contains(0.0) && elevation.contains(90.0));
        assert!(!phi_d.contains(f64::NAN) && !phi_d.contains(400.0));
        assert_eq!(
            phi_d.check("--phi-d", 400.0).unwrap_err().to_string(),
            "--phi-d 400: expected degrees from 0 to 180"
        );
        let count = CountRange::from_to(2, 10_000);
        assert_eq!(count.words(), "a whole number from 2 to 10000");
        assert_eq!(
            count.check("samples", 1).unwrap_err().to_string(),
            "samples 1: expected a whole number from 2 to 10000"
        );
        assert_eq!(count.check("samples", 2), Ok(2));
    }
}
