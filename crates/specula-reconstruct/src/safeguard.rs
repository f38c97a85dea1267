//! A deblurred table is checked against the samples it was made from before anyone trusts
//! it, and where it fails, the data's own un-deblurred values take its place.
//!
//! Deblurring divides out the instrument's response, and a response blurs: a spike narrower
//! than the light's disk changes what the instrument records hardly at all, so a table can
//! match the samples in its fit and still hold a feature the samples never saw. Two checks
//! catch what the fit cannot:
//!
//! 1. **Consistency** ([`crate::consistency`]): the table, blurred by the response, must
//!    reproduce every sample within its uncertainty. The uncertainty of a prediction is
//!    `u = sqrt(u_pos^2 + u_rep^2 + (r S)^2)`: the device's angular positioning through the
//!    local slope ([`crate::consistency::positioning_uncertainty`], of the fitted lobe's
//!    table, which invents nothing), the table's binning of the fitted lobe under the
//!    response (`|P_lobe table - M_lobe|`: what a table of MERL bins loses of a sharp peak
//!    however right it is) and a relative floor `r` = [`RELATIVE_FLOOR`] for the binning of
//!    the material's departure from the lobe. The normalised chi-square is reported; a region
//!    fails when its reproduction error exceeds [`FAIL_FACTOR`] times the one its
//!    uncertainties explain (`sqrt(sum u^2 / sum S^2)`): weighted by the signal, so that a
//!    few samples of tiny uncertainty on a dark flank cannot decide alone.
//! 2. **Energy**: the table's directional albedo ([`MerlBrdf::directional_albedo`]) must stay
//!    at most 1 (plus the quadrature's [`ALBEDO_TOLERANCE`]) at every incidence; an invented
//!    spike breaks it first.
//!
//! Where either fails, the table is reconstructed again without the response (the samples
//! as measured, blur and all) and its cells below the failing region's upper theta_h take
//! the deblurred ones' place when they reproduce the samples of every region there better
//! (lower reproduction error). The summary says so: a bound at the instrument's resolution,
//! not a resolved peak. Where they do not, the deblurred table stays and the summary says
//! which check it failed.

use crate::consistency::{self, Consistency, Instrument};
use crate::lobe::{Lobe, LobeOnGrid};
use crate::response_nodes::FIT_RESPONSE_NODES;
use specula_core::capture::{CaptureNode, CaptureResponse};
use specula_core::merl::{Bin, MerlBrdf};
use specula_core::{Rgb, Sample};

/// A region fails when its reproduction error exceeds this many times the one its
/// uncertainties explain.
pub const FAIL_FACTOR: f64 = 3.0;

/// The relative floor of a prediction's uncertainty (see the module documentation).
pub const RELATIVE_FLOOR: f64 = 0.01;

/// The largest directional albedo accepted as energy conserving: 1 plus the quadrature's
/// error on a table ([`MerlBrdf::directional_albedo`]).
pub const ALBEDO_TOLERANCE: f64 = 1.02;

/// Incidences at which the albedo is checked, degrees.
const ALBEDO_INCIDENCES_DEG: [f64; 9] = [0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0];

/// What the checks found of a deblurred table (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct Safeguard {
    /// The figures of the table returned.
    pub consistency: Consistency,
    /// The deblurred table's figures, when part of it was replaced.
    pub deblurred: Option<Consistency>,
    /// Cells with theta_h below this (degrees) hold the un-deblurred reconstruction.
    pub fallback_below_deg: Option<f64>,
    /// Why the fallback was taken, in words.
    pub reason: Option<String>,
    /// The largest directional albedo of the table returned, over the channels and
    /// [`ALBEDO_INCIDENCES_DEG`].
    pub max_albedo: f64,
}

impl Safeguard {
    /// True when the deblurred table failed a check (whether or not it was replaced).
    pub fn failed(&self) -> bool {
        self.reason.is_some()
    }

    /// The summary's lines: the consistency per region, the albedo and any fallback.
    pub fn lines(&self) -> Vec<String> {
        let mut lines = self.consistency.lines();
        lines.push(format!("max_directional_albedo={:.4}", self.max_albedo));
        lines.push(match (self.fallback_below_deg, &self.reason) {
            (Some(limit), Some(reason)) => format!(
                "deblur_fallback=theta_h below {limit:.2} deg holds the un-deblurred values ({reason})"
            ),
            (None, Some(reason)) => format!("deblur_fallback=none, check failed: {reason}"),
            _ => "deblur_fallback=none, checks passed".into(),
        });
        if let Some(d) = &self.deblurred {
            lines.extend(d.lines().into_iter().map(|l| format!("deblurred_{l}")));
        }
        lines
    }
}

/// Checks the `deblurred` table (made through `response` from `samples`, with its fitted
/// `lobe`) and falls back per region to the table `without_response()` makes where it fails
/// (see the module documentation): the table to keep, what the checks found and, when its
/// cells were replaced, the deblurred table itself.
pub(crate) fn safeguarded<R: CaptureResponse + ?Sized, E>(
    samples: &[Sample],
    deblurred: MerlBrdf,
    lobe: Option<&Lobe>,
    response: &R,
    without_response: impl FnOnce() -> Result<MerlBrdf, E>,
) -> Result<(MerlBrdf, Safeguard, Option<MerlBrdf>), E> {
    let nodes = response.capture_nodes(FIT_RESPONSE_NODES);
    let instrument = Instrument {
        nodes: &nodes,
        resolution_deg: Some(response.resolution_deg()),
    };
    let u = prediction_uncertainty(samples, lobe, &deblurred, &nodes);
    let check = Consistency::check(samples, &u, &deblurred, instrument);
    let albedo = max_albedo(&deblurred);
    let Some((limit_deg, reason)) = failure(&check, albedo) else {
        let passed = Safeguard {
            consistency: check,
            deblurred: None,
            fallback_below_deg: None,
            reason: None,
            max_albedo: albedo,
        };
        return Ok((deblurred, passed, None));
    };
    let plain = without_response()?;
    let merged = replaced_below(&deblurred, &plain, limit_deg);
    let merged_check = Consistency::check(samples, &u, &merged, instrument);
    let merged_albedo = max_albedo(&merged);
    if !fits_better(&merged_check, &check, limit_deg) {
        let kept = Safeguard {
            consistency: check,
            deblurred: None,
            fallback_below_deg: None,
            reason: Some(format!("{reason}; the un-deblurred values reproduce the samples no better, so the deblurred ones stay")),
            max_albedo: albedo,
        };
        return Ok((deblurred, kept, None));
    }
    let replaced = Safeguard {
        consistency: merged_check,
        deblurred: Some(check),
        fallback_below_deg: Some(limit_deg),
        reason: Some(reason),
        max_albedo: merged_albedo,
    };
    Ok((merged, replaced, Some(deblurred)))
}

/// The standard uncertainty of each sample's prediction (see the module documentation):
/// positioning and the lobe table's binning from the fitted `lobe` when there is one, else
/// the positioning through `table` itself; and the relative floor.
fn prediction_uncertainty(
    samples: &[Sample],
    lobe: Option<&Lobe>,
    table: &MerlBrdf,
    nodes: &[CaptureNode],
) -> Vec<Rgb> {
    let floor = |s: &Sample| s.value.abs() * RELATIVE_FLOOR;
    let Some(lobe) = lobe else {
        let positioning = consistency::positioning_uncertainty(samples, table, nodes);
        return samples
            .iter()
            .zip(positioning)
            .map(|(s, p)| quadrature_sum(&[p, floor(s)]))
            .collect();
    };
    let on_grid = LobeOnGrid::new(*lobe);
    let lobe_table = MerlBrdf::from_fn("lobe", |index| Some(on_grid.at(index)));
    let positioning = consistency::positioning_uncertainty(samples, &lobe_table, nodes);
    let representation =
        consistency::LobeCaptures::of(samples, lobe, &lobe_table, nodes).representation_error();
    samples
        .iter()
        .zip(positioning)
        .zip(representation)
        .map(|((s, p), r)| quadrature_sum(&[p, r.abs(), floor(s)]))
        .collect()
}

/// `sqrt(sum of squares)` per channel.
fn quadrature_sum(terms: &[Rgb]) -> Rgb {
    let sum = terms.iter().fold(Rgb::ZERO, |acc, t| acc + *t * *t);
    Rgb::new(sum.x.sqrt(), sum.y.sqrt(), sum.z.sqrt())
}

/// The theta_h below which the table is replaced and why, if any check fails: the peak
/// region's limit when only the peak fails (or the albedo), the flank's when the flank does.
fn failure(check: &Consistency, max_albedo: f64) -> Option<(f64, String)> {
    let failed = |name: &str| {
        check
            .region(name)
            .filter(|r| r.relative_error > FAIL_FACTOR * r.expected_error)
            .map(|r| {
                format!(
                    "{name} reproduction error {:.2} % above {FAIL_FACTOR} x the {:.2} % its uncertainties explain",
                    100.0 * r.relative_error,
                    100.0 * r.expected_error
                )
            })
    };
    let mut reasons: Vec<String> = Vec::new();
    let mut limit = None;
    if let Some(r) = failed("peak") {
        reasons.push(r);
        limit = Some(check.peak_limit_deg);
    }
    if max_albedo > ALBEDO_TOLERANCE {
        reasons.push(format!("directional albedo {max_albedo:.3} above 1"));
        limit = limit.or(Some(check.peak_limit_deg));
    }
    if let Some(r) = failed("flank") {
        reasons.push(r);
        limit = Some(crate::lobe::BLUR_THETA_H_DEG);
    }
    limit.map(|l| (l, reasons.join("; ")))
}

/// True when `merged` reproduces the samples of every region below `limit_deg` better
/// (lower reproduction error) than `deblurred`.
fn fits_better(merged: &Consistency, deblurred: &Consistency, limit_deg: f64) -> bool {
    ["peak", "flank"]
        .iter()
        .filter(|name| **name == "peak" || limit_deg > deblurred.peak_limit_deg)
        .all(|name| match (merged.region(name), deblurred.region(name)) {
            (Some(m), Some(d)) => m.relative_error < d.relative_error,
            _ => true,
        })
}

/// `deblurred` with every cell whose theta_h centre lies below `limit_deg` taken from `plain`.
fn replaced_below(deblurred: &MerlBrdf, plain: &MerlBrdf, limit_deg: f64) -> MerlBrdf {
    MerlBrdf::from_fn(specula_core::Brdf::name(deblurred), |index| {
        let [theta_h_deg, _, _] = Bin::from_index(index).centre_deg();
        if theta_h_deg < limit_deg {
            plain.cell(index)
        } else {
            deblurred.cell(index)
        }
    })
}

/// The largest directional albedo of `table` (see [`Safeguard::max_albedo`]).
fn max_albedo(table: &MerlBrdf) -> f64 {
    ALBEDO_INCIDENCES_DEG
        .iter()
        .map(|&t| {
            let a = table.directional_albedo(t);
            a.x.max(a.y).max(a.z)
        })
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lobe::{Geometry, Shape};
    use specula_acquisition::device::Device;
    use specula_core::HalfDiff;

    fn lobe(alpha: f64) -> Lobe {
        Lobe {
            shape: Shape { alpha, gamma: 2.0 },
            diffuse: Rgb::splat(0.05),
            specular: Rgb::splat(0.8),
            grazing: Rgb::splat(0.2),
        }
    }

    fn tabulated(truth: &Lobe) -> MerlBrdf {
        MerlBrdf::from_fn("t", |index| {
            let [h, d, p] = Bin::from_index(index).centre_deg();
            Some(truth.eval(&Geometry::of(HalfDiff::from_degrees(h, 0.0, d, p))))
        })
    }

    #[test]
    fn an_invented_spike_falls_back_to_the_values_as_measured_and_the_truth_stays() {
        // GGX alpha 0.05 measured through the UTIA response along theta_h at theta_d 40,
        // phi_d 90. A "deblurred" table with a peak four times sharper (and the lobe fitted
        // to it) reproduces the peak's samples badly: the check fails there, and the
        // un-deblurred table (here the truth itself) takes the peak's cells. The truth as
        // the deblurred table passes and is kept as it is.
        let response = Device::utia().response();
        let nodes = response.capture_nodes(FIT_RESPONSE_NODES);
        let truth = lobe(0.05);
        let samples: Vec<Sample> = (0..40)
            .map(|k| {
                let h = (k as f64 * 1.5).powi(2) / 90.0;
                let hd = HalfDiff::from_degrees(h, 45.0, 40.0, 90.0);
                Sample::new(hd, truth.measured(&nodes, hd))
            })
            .collect();
        let spiky = lobe(0.0125);
        let (kept, guard, replaced) =
            safeguarded(&samples, tabulated(&spiky), Some(&spiky), &response, || {
                Ok::<_, ()>(tabulated(&truth))
            })
            .unwrap();
        assert!(guard.fallback_below_deg.is_some(), "{guard:?}");
        // The deblurred table replaced is kept for the uncertainty's deblurring term.
        assert!(replaced.is_some());
        let peak = Bin {
            theta_h_i: 0,
            theta_d_i: 40,
            phi_d_i: 90,
        }
        .index();
        assert_eq!(kept.cell(peak), tabulated(&truth).cell(peak));
        let failed = guard.deblurred.as_ref().unwrap().region("peak").unwrap();
        assert!(
            failed.relative_error > FAIL_FACTOR * failed.expected_error,
            "{failed:?}"
        );
        assert!(guard
            .lines()
            .iter()
            .any(|l| l.starts_with("deblur_fallback=theta_h below")));

        let (_, guard, replaced) =
            safeguarded(&samples, tabulated(&truth), Some(&truth), &response, || {
                Err("not needed")
            })
            .unwrap();
        assert_eq!(guard.fallback_below_deg, None, "{guard:?}");
        assert!(replaced.is_none());
        let peak = guard.consistency.region("peak").unwrap();
        assert!(
            peak.relative_error < FAIL_FACTOR * peak.expected_error,
            "{peak:?}"
        );
        assert!(guard.max_albedo < 1.0, "{}", guard.max_albedo);
    }
}
