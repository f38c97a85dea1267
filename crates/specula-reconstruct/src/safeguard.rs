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
//!    the material's departure from the lobe. A region whose normalised chi-square exceeds
//!    [`CHI2_LIMIT`] fails.
//! 2. **Energy**: the table's directional albedo ([`MerlBrdf::directional_albedo`]) must stay
//!    at most 1 (plus the quadrature's [`ALBEDO_TOLERANCE`]) at every incidence; an invented
//!    spike breaks it first.
//!
//! Where either fails, the table is reconstructed again without the response (the samples
//! as measured, blur and all) and its cells below the failing region's upper theta_h take
//! the deblurred ones' place when they reproduce the samples there better. The summary says
//! so: a bound at the instrument's resolution, not a resolved peak.

use crate::consistency::{self, Consistency, Instrument};
use crate::lobe::{Lobe, LobeOnGrid};
use crate::reconstruct::FIT_RESPONSE_NODES;
use crate::Reconstruction;
use specula_core::capture::{CaptureNode, CaptureResponse};
use specula_core::merl::{Bin, MerlBrdf};
use specula_core::{Rgb, Sample};

/// A region fails when its normalised chi-square exceeds this: the table misses its samples
/// by more than three of their standard uncertainties, root mean square.
pub const CHI2_LIMIT: f64 = 9.0;

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
    /// The summary's lines: the consistency per region, the albedo and any fallback.
    pub fn lines(&self) -> Vec<String> {
        let mut lines = self.consistency.lines();
        lines.push(format!("max_directional_albedo={:.4}", self.max_albedo));
        match (self.fallback_below_deg, &self.reason) {
            (Some(limit), Some(reason)) => lines.push(format!(
                "deblur_fallback=theta_h below {limit:.2} deg holds the un-deblurred values ({reason})"
            )),
            _ => lines.push("deblur_fallback=none".into()),
        }
        if let Some(d) = &self.deblurred {
            lines.extend(d.lines().into_iter().map(|l| format!("deblurred_{l}")));
        }
        lines
    }
}

/// Checks `deblurred` (made through `response` from `samples`) and falls back per region to
/// `without_response()` where it fails (see the module documentation).
pub(crate) fn safeguarded<R: CaptureResponse + ?Sized, E>(
    samples: &[Sample],
    mut deblurred: Reconstruction,
    response: &R,
    without_response: impl FnOnce() -> Result<Reconstruction, E>,
) -> Result<Reconstruction, E> {
    let nodes = response.capture_nodes(FIT_RESPONSE_NODES);
    let instrument = Instrument {
        nodes: &nodes,
        resolution_deg: Some(response.resolution_deg()),
    };
    let u = prediction_uncertainty(samples, deblurred.lobe.as_ref(), &deblurred.brdf, &nodes);
    let check = Consistency::check(samples, &u, &deblurred.brdf, instrument);
    let albedo = max_albedo(&deblurred.brdf);
    let Some((limit_deg, reason)) = failure(&check, albedo) else {
        deblurred.safeguard = Some(Safeguard {
            consistency: check,
            deblurred: None,
            fallback_below_deg: None,
            reason: None,
            max_albedo: albedo,
        });
        return Ok(deblurred);
    };
    let plain = without_response()?;
    let merged = replaced_below(&deblurred.brdf, &plain.brdf, limit_deg);
    let merged_check = Consistency::check(samples, &u, &merged, instrument);
    let merged_albedo = max_albedo(&merged);
    let better = fits_better(&merged_check, &check, limit_deg) || albedo > ALBEDO_TOLERANCE;
    if !better {
        deblurred.safeguard = Some(Safeguard {
            consistency: check,
            deblurred: None,
            fallback_below_deg: None,
            reason: Some(format!("{reason}; the un-deblurred values reproduce the samples no better, so the deblurred ones stay")),
            max_albedo: albedo,
        });
        return Ok(deblurred);
    }
    deblurred.brdf = merged;
    deblurred.safeguard = Some(Safeguard {
        consistency: merged_check,
        deblurred: Some(check),
        fallback_below_deg: Some(limit_deg),
        reason: Some(reason),
        max_albedo: merged_albedo,
    });
    Ok(deblurred)
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
    let representation = consistency::representation_error(samples, lobe, &lobe_table, nodes);
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
            .filter(|r| r.chi2_per_value > CHI2_LIMIT)
            .map(|r| format!("{name} chi2 per value {:.3e} above {CHI2_LIMIT}", r.chi2_per_value))
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

/// True when `merged` reproduces the samples below `limit_deg` better than `deblurred`.
fn fits_better(merged: &Consistency, deblurred: &Consistency, limit_deg: f64) -> bool {
    let chi2_below = |c: &Consistency| {
        let regions: Vec<_> = ["peak", "flank"]
            .iter()
            .filter(|name| *name == &"peak" || limit_deg > c.peak_limit_deg)
            .filter_map(|name| c.region(name))
            .collect();
        let n: usize = regions.iter().map(|r| r.samples).sum();
        regions
            .iter()
            .map(|r| r.chi2_per_value * r.samples as f64)
            .sum::<f64>()
            / n.max(1) as f64
    };
    chi2_below(merged) < chi2_below(deblurred)
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
