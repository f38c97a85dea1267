//! The value domain in which the lattice is extrapolated and interpolated.
//!
//! - `Linear`: f itself (the paper's baseline, 5.3).
//! - `Log`: `ln(f + eps)`. A specular peak falls by orders of magnitude between theta_h
//!   nodes; in the log domain a Gaussian-like peak is a parabola, which interpolation follows
//!   far better than the exponential-like fall of f.
//! - `LobeResidual`: `ln((f + eps) / (m + eps))`, the log ratio of the measurement to a
//!   microfacet lobe `m` fitted to the samples ([`crate::lobe`]). Between and beyond the
//!   nodes the lobe supplies the shape, the lattice only the slowly varying correction.
//!
//! `eps` = [`LOG_OFFSET`] keeps zero values finite; back-transformed values are clamped at 0.

/// The offset `eps` in 1/sr of the log domains, far below any diffuse reflectance.
pub const LOG_OFFSET: f64 = 1e-4;

/// See the module documentation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Domain {
    /// f itself (the paper's baseline, 5.3).
    Linear,
    /// `ln(f + eps)`.
    Log,
    /// `ln((f + eps) / (m + eps))`, the log ratio to a fitted microfacet lobe `m`.
    LobeResidual,
}

impl Domain {
    /// The domain value of `f` where the lobe is `model` (ignored outside `LobeResidual`).
    pub fn forward(self, f: f64, model: f64) -> f64 {
        match self {
            Domain::Linear => f,
            Domain::Log => (f + LOG_OFFSET).ln(),
            Domain::LobeResidual => ((f + LOG_OFFSET) / (model + LOG_OFFSET)).ln(),
        }
    }

    /// f of a domain value where the lobe is `model`, clamped at zero.
    pub fn inverse(self, v: f64, model: f64) -> f64 {
        let f = match self {
            Domain::Linear => v,
            Domain::Log => v.exp() - LOG_OFFSET,
            Domain::LobeResidual => (model + LOG_OFFSET) * v.exp() - LOG_OFFSET,
        };
        f.max(0.0)
    }

    /// Whether the domain needs a fitted lobe (only `LobeResidual`).
    pub(crate) fn uses_lobe(self) -> bool {
        self == Domain::LobeResidual
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_undoes_forward() {
        for d in [Domain::Linear, Domain::Log, Domain::LobeResidual] {
            for (f, m) in [(0.0, 1.0), (1e-3, 0.0), (250.0, 300.0), (0.2, 0.25)] {
                let back = d.inverse(d.forward(f, m), m);
                assert!((back - f).abs() < 1e-9 * (1.0 + f), "{d:?} {f} {m}: {back}");
            }
        }
        assert_eq!(Domain::Linear.inverse(-0.5, 0.0), 0.0);
    }
}
