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
//! A measured value below zero (camera noise about a dark configuration, after the dark
//! frame is subtracted) means "zero within the noise": the log domains take it as 0, so that
//! no sample's logarithm is undefined.

/// The offset `eps` in 1/sr of the log domains, far below any diffuse reflectance.
pub(crate) const LOG_OFFSET: f64 = 1e-4;

/// `ln(max(f, 0) + eps)`: the logarithm of a measured value, which noise may have taken
/// below zero (see the module documentation).
pub(crate) fn log_of_measured(f: f64) -> f64 {
    (f.max(0.0) + LOG_OFFSET).ln()
}

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
            Domain::Log => log_of_measured(f),
            Domain::LobeResidual => log_of_measured(f) - log_of_measured(model),
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

    #[test]
    fn a_value_noise_took_below_zero_has_a_logarithm() {
        // The dark frame subtracted, a configuration that reflects nothing measures a little
        // below zero now and then; its logarithm is that of zero, in both log domains.
        for d in [Domain::Log, Domain::LobeResidual] {
            let v = d.forward(-3e-4, 0.5);
            assert!(v.is_finite(), "{d:?}");
            assert_eq!(v, d.forward(0.0, 0.5), "{d:?}");
        }
    }
}
