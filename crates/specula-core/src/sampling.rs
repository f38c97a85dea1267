//! The non-linear theta_h sampling functions of the paper's equations 1 to 4 (section 5.1).
//!
//! Each maps `t`, spread evenly over `[0, m]` with `m = 90` degrees, to a sample position
//! `theta_h = g(t)` that crowds samples near the specular peak at `theta_h = 0`:
//!
//! - square root (eq. 1): `g(t) = t^2 / m`, MERL's mapping, the power family with `k = 2`;
//! - power (eq. 2): `g(t) = m (t/m)^k`, `k > 0`;
//! - exponential (eq. 3): `g(t) = m (exp(k t/m) - 1) / (exp(k) - 1)`, `k > 0`;
//! - base-k (eq. 4): `g(t) = m (k^(t/m) - 1) / (k - 1)`, `k > 1`.
//!
//! Positions are in degrees, as in the paper; callers convert at use.

use serde::{Deserialize, Serialize};

/// The largest theta_h, `m` in the paper's equations, in degrees.
pub const THETA_H_MAX_DEG: f64 = 90.0;

/// One of the paper's families of theta_h sampling functions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Family {
    /// Equation 2, `m (t/m)^k`.
    Power,
    /// Equation 3, `m (exp(k t/m) - 1) / (exp(k) - 1)`.
    Exponential,
    /// Equation 4, `m (k^(t/m) - 1) / (k - 1)`.
    Base,
}

impl Family {
    /// The three families of the paper (equations 2 to 4), in its order.
    pub const ALL: [Family; 3] = [Family::Power, Family::Exponential, Family::Base];

    /// The lowercase name used on the command line and in files.
    pub fn name(self) -> &'static str {
        match self {
            Family::Power => "power",
            Family::Exponential => "exponential",
            Family::Base => "base",
        }
    }

    /// The smallest k the family accepts (exclusive).
    pub fn k_lower_bound(self) -> f64 {
        match self {
            Family::Power | Family::Exponential => 0.0,
            Family::Base => 1.0,
        }
    }
}

impl std::str::FromStr for Family {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "power" => Ok(Family::Power),
            "exponential" | "exp" => Ok(Family::Exponential),
            "base" | "base-k" => Ok(Family::Base),
            other => Err(format!(
                "unknown sampling family '{other}' (expected power, exponential or base)"
            )),
        }
    }
}

impl std::fmt::Display for Family {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A sampling function: a family with its parameter k.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SamplingFunction {
    /// The family (paper equations 2 to 4).
    pub family: Family,
    /// The family's parameter (k-hat once fitted to a probe, paper section 5.2).
    pub k: f64,
}

/// A k outside its family's range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("k = {k} is out of range for the {family} sampling function (needs k > {bound})")]
pub struct InvalidK {
    /// The family asked for.
    pub family: Family,
    /// The k given.
    pub k: f64,
    /// The family's lower bound of k (exclusive).
    pub bound: f64,
}

impl SamplingFunction {
    /// Checks `k > 0` (power, exponential) or `k > 1` (base-k), finite.
    pub fn new(family: Family, k: f64) -> Result<Self, InvalidK> {
        let bound = family.k_lower_bound();
        if k.is_finite() && k > bound {
            Ok(Self { family, k })
        } else {
            Err(InvalidK { family, k, bound })
        }
    }

    /// MERL's square-root mapping, equation 1 (power with k = 2).
    pub fn square_root() -> Self {
        Self {
            family: Family::Power,
            k: 2.0,
        }
    }

    /// `g(t)`: the theta_h position in degrees of the uniform coordinate `t_deg` in `[0, m]`.
    pub fn theta_h_deg(&self, t_deg: f64) -> f64 {
        let m = THETA_H_MAX_DEG;
        let u = (t_deg / m).clamp(0.0, 1.0);
        let k = self.k;
        match self.family {
            Family::Power => m * u.powf(k),
            // exp_m1 keeps precision for small k * u.
            Family::Exponential => m * (k * u).exp_m1() / k.exp_m1(),
            Family::Base => m * (u * k.ln()).exp_m1() / (k - 1.0),
        }
    }

    /// `g^-1(theta_h)`: the uniform coordinate in degrees of a theta_h position in degrees.
    pub fn t_deg(&self, theta_h_deg: f64) -> f64 {
        let m = THETA_H_MAX_DEG;
        let y = (theta_h_deg / m).clamp(0.0, 1.0);
        let k = self.k;
        let u = match self.family {
            Family::Power => y.powf(1.0 / k),
            Family::Exponential => (y * k.exp_m1()).ln_1p() / k,
            Family::Base => (y * (k - 1.0)).ln_1p() / k.ln(),
        };
        m * u
    }

    /// `n` positions in degrees: `g(t)` at `t` evenly spaced over `[0, m]`, both ends included.
    pub fn positions_deg(&self, n: usize) -> Vec<f64> {
        match n {
            0 => Vec::new(),
            1 => vec![0.0],
            _ => (0..n)
                .map(|i| self.theta_h_deg(THETA_H_MAX_DEG * i as f64 / (n - 1) as f64))
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn any_function() -> impl Strategy<Value = SamplingFunction> {
        prop_oneof![
            (0.05..12.0f64).prop_map(|k| SamplingFunction::new(Family::Power, k).unwrap()),
            (0.01..30.0f64).prop_map(|k| SamplingFunction::new(Family::Exponential, k).unwrap()),
            (1.01..5000.0f64).prop_map(|k| SamplingFunction::new(Family::Base, k).unwrap()),
        ]
    }

    proptest! {
        #[test]
        fn endpoints_are_zero_and_m(f in any_function()) {
            prop_assert!(f.theta_h_deg(0.0).abs() < 1e-12);
            prop_assert!((f.theta_h_deg(90.0) - 90.0).abs() < 1e-9);
        }

        #[test]
        fn monotone(f in any_function(), a in 0.0..90.0f64, b in 0.0..90.0f64) {
            let (lo, hi) = if a < b { (a, b) } else { (b, a) };
            prop_assert!(f.theta_h_deg(lo) <= f.theta_h_deg(hi));
        }

        #[test]
        fn inverse_round_trips(f in any_function(), t in 0.0..90.0f64) {
            let back = f.t_deg(f.theta_h_deg(t));
            // The round trip loses precision where g is flat (g' tiny near t = 0).
            prop_assert!((back - t).abs() < 1e-6, "{f:?}: {t} -> {back}");
        }
    }

    #[test]
    fn power_two_is_the_square_root_mapping() {
        let f = SamplingFunction::square_root();
        for i in 0..=90 {
            let t = i as f64;
            assert!((f.theta_h_deg(t) - t * t / 90.0).abs() < 1e-12);
        }
    }

    #[test]
    fn k_is_checked() {
        assert!(SamplingFunction::new(Family::Power, 0.0).is_err());
        assert!(SamplingFunction::new(Family::Exponential, -1.0).is_err());
        assert!(SamplingFunction::new(Family::Base, 1.0).is_err());
        assert!(SamplingFunction::new(Family::Base, f64::NAN).is_err());
        assert!(SamplingFunction::new(Family::Base, 1.5).is_ok());
    }

    #[test]
    fn positions_span_the_range() {
        let p = SamplingFunction::new(Family::Exponential, 4.78)
            .unwrap()
            .positions_deg(30);
        assert_eq!(p.len(), 30);
        assert_eq!(p[0], 0.0);
        assert!((p[29] - 90.0).abs() < 1e-9);
        assert!(p.windows(2).all(|w| w[0] < w[1]));
    }
}
