//! Reconstruction methods: the value domain and the interpolation kernel used between the
//! lattice nodes (angles in degrees on every axis), and whether the model the residual is
//! taken to blends in the data-driven prior.

use crate::domain::Domain;
use crate::kernel::Kernel;

/// How samples become a full table (see [`crate::reconstruct`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// The paper's baseline (5.3): f linear in theta_h, theta_d and phi_d, with nearest-node
    /// extrapolation.
    Linear,
    /// ln f, monotone cubic.
    Log,
    /// The log ratio to a fitted microfacet lobe, monotone cubic.
    Lobe,
    /// The log ratio to the lobe blended with the MERL-100 prior, monotone cubic
    /// ([`crate::prior_reconstruct`]).
    Prior,
}

impl Method {
    /// Every method, in the order of [`Method::NAMES`].
    pub const ALL: [Method; 4] = [Method::Linear, Method::Log, Method::Lobe, Method::Prior];

    /// The names accepted by [`Method::from_str`], with what each does.
    pub const NAMES: [(&'static str, &'static str); 4] = [
        (
            "linear",
            "the paper's baseline: f linear in theta_h, theta_d, phi_d",
        ),
        ("log", "ln f, monotone cubic"),
        (
            "lobe",
            "ln of f over a fitted microfacet lobe, monotone cubic",
        ),
        (
            "prior",
            "as lobe, over the lobe blended with a MERL-100 prior as far as the samples trust it",
        ),
    ];

    /// The value domain the lattice is interpolated in.
    pub fn domain(self) -> Domain {
        match self {
            Method::Linear => Domain::Linear,
            Method::Log => Domain::Log,
            Method::Lobe | Method::Prior => Domain::LobeResidual,
        }
    }

    /// The interpolation kernel along each axis.
    pub fn kernel(self) -> Kernel {
        match self {
            Method::Linear => Kernel::Linear,
            Method::Log | Method::Lobe | Method::Prior => Kernel::MonotoneCubic,
        }
    }

    /// Whether the model of the `LobeResidual` domain is the lobe blended with the MERL-100
    /// prior by a trust the samples choose ([`crate::prior_reconstruct`]), not the lobe
    /// alone.
    pub fn uses_prior(self) -> bool {
        self == Method::Prior
    }

    /// The method's name, as accepted by [`Method::from_str`].
    pub fn name(self) -> &'static str {
        match self {
            Method::Linear => "linear",
            Method::Log => "log",
            Method::Lobe => "lobe",
            Method::Prior => "prior",
        }
    }
}

impl std::str::FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let s = s.to_ascii_lowercase();
        Method::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| {
                format!(
                    "unknown reconstruction method '{s}' (expected {})",
                    Method::NAMES.map(|(n, _)| n).join(", ")
                )
            })
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_and_print() {
        for (name, _) in Method::NAMES {
            let m: Method = name.parse().unwrap();
            assert_eq!(m.to_string(), name);
        }
        assert!("cubic"
            .parse::<Method>()
            .unwrap_err()
            .contains("expected linear, log, lobe, prior"));
    }

    #[test]
    fn each_method_has_its_own_domain_kernel_and_prior() {
        let parts: Vec<_> = Method::ALL
            .iter()
            .map(|m| (m.domain(), m.kernel(), m.uses_prior()))
            .collect();
        for (i, a) in parts.iter().enumerate() {
            assert!(parts[i + 1..].iter().all(|b| b != a), "{a:?}");
        }
        assert_eq!(Method::Lobe.domain(), Domain::LobeResidual);
        assert!(Method::Prior.uses_prior() && !Method::Lobe.uses_prior());
    }
}
