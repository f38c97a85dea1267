//! The probe before the instrument's blur: its column deblurred by the lobe fitted through
//! the instrument's response (`specula_reconstruct::deblur`), so that k is fitted to the
//! material and not to the light's disk (paper 5.2, beyond it).

use specula_core::capture::CaptureResponse;
use specula_core::{ProbePoint, ProbeSpec, Sample};
use specula_reconstruct::deblur::deblur_samples;

/// A probe's points (its column at `column`'s theta_d, phi_d and phi_h) before the
/// instrument's blur ([`deblur_samples`]); the probe as measured where no lobe fits.
pub fn deblur_probe(
    probe: &[ProbePoint],
    column: &ProbeSpec,
    response: &dyn CaptureResponse,
) -> Vec<ProbePoint> {
    let samples: Vec<Sample> = probe
        .iter()
        .map(|p| Sample::new(column.half_diff(p.theta_h_deg), p.value))
        .collect();
    match deblur_samples(&samples, response) {
        Some((sharp, _)) => sharp
            .iter()
            .map(|s| ProbePoint::new(s.theta_h_deg(), s.value))
            .collect(),
        None => probe.to_vec(),
    }
}
