//! The probe before the instrument's blur: its column deblurred by the lobe fitted through
//! the instrument's response (`specula_reconstruct::deblur`), so that k is fitted to the
//! material and not to the light's disk (paper 5.2, beyond it).

use crate::probe::ProbeSettings;
use specula_core::capture::CaptureResponse;
use specula_core::{HalfDiff, Rgb};
use specula_reconstruct::deblur::deblur_samples;
use specula_reconstruct::Sample;

/// A probe's `(theta_h_deg, f)` (its column at `column`'s theta_d, phi_d and phi_h) before
/// the instrument's blur ([`deblur_samples`]); the probe as measured where no lobe fits.
pub fn deblur_probe(
    probe: &[(f64, Rgb)],
    column: &ProbeSettings,
    response: &dyn CaptureResponse,
) -> Vec<(f64, Rgb)> {
    let samples: Vec<Sample> = probe
        .iter()
        .map(|&(h, v)| {
            let hd =
                HalfDiff::from_degrees(h, column.phi_h_deg, column.theta_d_deg, column.phi_d_deg);
            Sample::new(hd, v)
        })
        .collect();
    match deblur_samples(&samples, response) {
        Some((sharp, _)) => sharp
            .iter()
            .map(|s| (s.hd.theta_h.to_degrees(), s.value))
            .collect(),
        None => probe.to_vec(),
    }
}
