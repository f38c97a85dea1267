//! The probe before the instrument's blur: its column deblurred by the lobe fitted through
//! the instrument's response (`specula_reconstruct::deblur`), so that k is fitted to the
//! material and not to the light's disk (paper 5.2, beyond it).

use specula_core::capture::CaptureResponse;
use specula_core::{ProbePoint, ProbeSpec, Sample};
use specula_reconstruct::deblur::deblur_samples;
use specula_reconstruct::lobe::Lobe;

/// A probe's points before the instrument's blur and the lobe fitted through the response
/// that took the blur away.
#[derive(Debug, Clone)]
pub struct DeblurredProbe {
    /// The points as the material would give them without the blur; the probe as measured
    /// where no lobe fits.
    pub points: Vec<ProbePoint>,
    /// The lobe fitted through the response; `None` where none fits.
    pub lobe: Option<Lobe>,
}

impl DeblurredProbe {
    /// True when the lobe's peak is narrower (half width at half maximum in theta_h) than
    /// `resolution_deg`, the instrument's resolution: the blur hides the peak's shape.
    pub fn peak_unresolved(&self, resolution_deg: f64) -> bool {
        self.lobe
            .is_some_and(|lobe| lobe.shape.half_width_deg() < resolution_deg)
    }
}

/// A probe's points (its column at `column`'s theta_d, phi_d and phi_h) before the
/// instrument's blur ([`deblur_samples`]).
pub fn deblur_probe(
    probe: &[ProbePoint],
    column: &ProbeSpec,
    response: &dyn CaptureResponse,
) -> DeblurredProbe {
    let samples: Vec<Sample> = probe
        .iter()
        .map(|p| Sample::new(column.half_diff(p.theta_h_deg), p.value))
        .collect();
    match deblur_samples(&samples, response) {
        Some((sharp, lobe)) => DeblurredProbe {
            points: sharp
                .iter()
                .map(|s| ProbePoint::new(s.theta_h_deg(), s.value))
                .collect(),
            lobe: Some(lobe),
        },
        None => DeblurredProbe {
            points: probe.to_vec(),
            lobe: None,
        },
    }
}
