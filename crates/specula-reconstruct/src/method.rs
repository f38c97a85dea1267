//! Reconstruction methods: the value domain and the interpolation kernel used between the
//! lattice nodes (angles in degrees on every axis), and whether the model the residual is
//! taken to blends in the data-driven prior.

use crate::domain::Domain;
use crate::kernel::Kernel;

/// How samples become a full table (see [`crate::reconstruct`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Method {
    /// The value domain the lattice is interpolated in.
    pub domain: Domain,
    /// The interpolation kernel along each axis.
    pub kernel: Kernel,
    /// Whether the model of the `LobeResidual` domain is the lobe blended with the MERL-100
    /// prior by a trust the samples choose ([`crate::prior_reconstruct`]), not the lobe
    /// alone.
    pub prior: bool,
}

impl Method {
    /// The paper's baseline (5.3): f linear in theta_h, theta_d and phi_d, with nearest-node
    /// extrapolation.
    pub const LINEAR: Method = Method {
        domain: Domain::Linear,
        kernel: Kernel::Linear,
        prior: false,
    };
    /// ln f, monotone cubic.
    pub const LOG: Method = Method {
        domain: Domain::Log,
        kernel: Kernel::MonotoneCubic,
        prior: false,
    };
    /// The log ratio to a fitted microfacet lobe, monotone cubic.
    pub const LOBE: Method = Method {
        domain: Domain::LobeResidual,
        kernel: Kernel::MonotoneCubic,
        prior: false,
    };
    /// The log ratio to the lobe blended with the MERL-100 prior, monotone cubic
    /// ([`crate::prior_reconstruct`]).
    pub const PRIOR: Method = Method {
        domain: Domain::LobeResidual,
        kernel: Kernel::MonotoneCubic,
        prior: true,
    };

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

    /// The method's name, as accepted by [`Method::from_str`].
    pub fn name(&self) -> &'static str {
        match *self {
            Method::LINEAR => "linear",
            Method::LOG => "log",
            Method::PRIOR => "prior",
            _ => "lobe",
        }
    }
}

impl std::str::FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "linear" => Ok(Method::LINEAR),
            "log" => Ok(Method::LOG),
            "lobe" => Ok(Method::LOBE),
            "prior" => Ok(Method::PRIOR),
            other => Err(format!(
                "unknown reconstruction method '{other}' (expected {})",
                Method::NAMES.map(|(n, _)| n).join(", ")
            )),
        }
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
}
