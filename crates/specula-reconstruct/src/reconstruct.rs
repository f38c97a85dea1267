//! Samples to a full MERL table (paper 5.3's last step): fold phi_d by symmetry, place the
//! samples on their lattice in the method's value domain, extrapolate the nodes the device
//! could not reach, interpolate at every MERL bin centre, and record each cell's provenance.

use crate::consistency;
use crate::domain::log_of_measured;
use crate::lobe::{Lobe, LobeOnGrid, BLUR_THETA_H_DEG};
use crate::method::Method;
use crate::prior::PriorBasis;
use crate::prior_reconstruct::reconstruct_with_prior;
use crate::reconstruction::{
    cells_of_domain_values, measured_lobe, reciprocal_canonical, table_of_domain_values,
    ReconstructError, Reconstruction, ResidualModel,
};
use crate::response_nodes::ResponseNodes;
use rayon::prelude::*;
use specula_core::capture::{CaptureNode, CaptureResponse};
use specula_core::merl::MerlBrdf;
use specula_core::{Rgb, Sample};

/// Reconstructs the full MERL table named `name` from the samples with a method that needs
/// no prior basis (`Method::Prior` needs [`reconstruct_through`] and its basis).
pub fn reconstruct(
    samples: &[Sample],
    method: Method,
    name: &str,
) -> Result<Reconstruction, ReconstructError> {
    reconstruct_through(samples, method, name, None::<&dyn CaptureResponse>, None)
}

/// Reconstructs the table from samples measured through an instrument `response`: the
/// `lobe` method fits its lobe through the response (the forward model, see
/// [`crate::lobe`]) and the lattice holds the samples' log ratio to the lobe *as measured*,
/// so the table is the lobe before the blur times the measured residual. The other methods,
/// which have no model of the BRDF, ignore the response; `prior` fits its lobe through it
/// too ([`crate::prior_reconstruct`]). `None`: as [`reconstruct`].
///
/// `prior` is the basis the `prior` method blends in (the caller derives it from its
/// training set, as `specula_accuracy::merl_prior` does for MERL-100); the other methods
/// ignore it, and `Method::Prior` without one is [`ReconstructError::NoPriorBasis`].
pub fn reconstruct_through<R: CaptureResponse + ?Sized>(
    samples: &[Sample],
    method: Method,
    name: &str,
    response: Option<&R>,
    prior: Option<&PriorBasis>,
) -> Result<Reconstruction, ReconstructError> {
    match method {
        Method::Prior => {
            let basis = prior.ok_or(ReconstructError::NoPriorBasis)?;
            reconstruct_with_prior(samples, basis, name, None, response).map(|(r, _)| r)
        }
        Method::Linear | Method::Log | Method::Lobe => {
            reconstruct_on_lattice(samples, method, name, response)
        }
    }
}

/// [`reconstruct_through`] for the methods whose model is at most the fitted lobe: the
/// samples' values in the method's domain, over the lobe as measured when the domain uses
/// one, corrected through the response where the lobe's blur does not reproduce them
/// ([`corrected_through`]).
fn reconstruct_on_lattice<R: CaptureResponse + ?Sized>(
    samples: &[Sample],
    method: Method,
    name: &str,
    response: Option<&R>,
) -> Result<Reconstruction, ReconstructError> {
    let nodes = ResponseNodes::of(response.filter(|_| method.domain().uses_lobe()));
    let (lobe, domain_values) = in_domain(samples, method, &nodes)?;
    let lobe_on_grid = lobe.map(LobeOnGrid::new);
    let model = |index: usize| lobe_on_grid.as_ref().map_or(Rgb::ZERO, |l| l.at(index));
    let build = |values: &[[f64; 3]]| table_of_domain_values(samples, values, method, name, model);
    let (table, residual_models) = match (lobe, &lobe_on_grid) {
        (Some(lobe), Some(on_grid)) if !nodes.residual.is_empty() => {
            let lobe_table = MerlBrdf::from_fn(name, |index| Some(on_grid.at(index)));
            let floor = LobeTableFloor {
                lobe: &lobe,
                table: &lobe_table,
            };
            let (table, values) =
                corrected_through(samples, domain_values, &nodes.residual, floor, build);
            (table, vec![ResidualModel::new(lobe, samples, &values)])
        }
        _ => (build(&domain_values), Vec::new()),
    };
    Ok(Reconstruction {
        lobe,
        resolution_deg: nodes.resolution_deg,
        residual_models,
        ..table
    })
}

/// The cells `indices` of the table [`reconstruct`] makes from `samples` with `method`,
/// `None` where it has no value: the same values bit for bit, without tabulating the
/// 1.5 million cells, for a caller that reads a few (a cross-validation reads its left-out
/// samples' cells). `prior`: as for [`reconstruct_through`].
pub fn reconstruct_cells(
    samples: &[Sample],
    method: Method,
    indices: &[usize],
    prior: Option<&PriorBasis>,
) -> Result<Vec<Option<Rgb>>, ReconstructError> {
    if method == Method::Prior {
        let none = None::<&dyn CaptureResponse>;
        let table = reconstruct_through(samples, method, "cells", none, prior)?.brdf;
        return Ok(indices.iter().map(|&index| table.cell(index)).collect());
    }
    let (lobe, domain_values) = in_domain(
        samples,
        method,
        &ResponseNodes::of(None::<&dyn CaptureResponse>),
    )?;
    let lobe_on_grid = lobe.map(LobeOnGrid::new);
    let model = |index: usize| lobe_on_grid.as_ref().map_or(Rgb::ZERO, |l| l.at(index));
    Ok(cells_of_domain_values(
        samples,
        &domain_values,
        method,
        model,
        indices,
    ))
}

/// The cells `indices` of the table a deblurred `lobe` reconstruction makes from `samples`
/// over `model`, without fitting a lobe or correcting through the response again: the
/// table of those samples' values as the deblurred table holds them
/// ([`ResidualModel`]; a sample it was not made from is left out). The uncertainty's
/// cross-validation reconstructs its folds so ([`crate::uncertainty`]): a fold that refitted
/// the lobe would judge another table.
pub fn reconstruct_cells_over(
    samples: &[Sample],
    method: Method,
    indices: &[usize],
    model: &ResidualModel,
) -> Result<Vec<Option<Rgb>>, ReconstructError> {
    let (held, values): (Vec<Sample>, Vec<[f64; 3]>) = samples
        .iter()
        .filter_map(|s| Some((*s, model.value(s)?)))
        .unzip();
    if held.is_empty() {
        return Err(ReconstructError::NoSamples);
    }
    let on_grid = LobeOnGrid::new(model.lobe);
    Ok(cells_of_domain_values(
        &held,
        &values,
        method,
        |index| on_grid.at(index),
        indices,
    ))
}

/// The lobe of `method`'s domain fitted through the response's `nodes` (none for the
/// methods without one) and each sample's value in the domain, over the lobe as measured.
fn in_domain(
    samples: &[Sample],
    method: Method,
    nodes: &ResponseNodes,
) -> Result<(Option<Lobe>, Vec<[f64; 3]>), ReconstructError> {
    if samples.is_empty() {
        return Err(ReconstructError::NoSamples);
    }
    let canonical: Vec<Sample> = samples.iter().map(reciprocal_canonical).collect();
    let lobe = if method.domain().uses_lobe() {
        Some(Lobe::fit_through(&canonical, &nodes.fit).ok_or(ReconstructError::NoLobe)?)
    } else {
        None
    };
    let values: Vec<[f64; 3]> = canonical
        .par_iter()
        .map(|s| {
            let model = lobe.map_or(Rgb::ZERO, |l| measured_lobe(&l, &nodes.residual, s.hd));
            std::array::from_fn(|c| method.domain().forward(s.value[c], model[c]))
        })
        .collect();
    let domain_values = match method.domain().uses_lobe() {
        true => crate::denoise::smoothed(samples, &values),
        false => values,
    };
    Ok((lobe, domain_values))
}

/// At most this many rounds of [`corrected_through`].
const MAX_CORRECTIONS: usize = 4;

/// A round of [`corrected_through`] is kept only when it lowers the samples' reproduction
/// error near the peak by at least this fraction.
const MIN_CORRECTION_GAIN: f64 = 0.1;

/// The table whose blur reproduces the samples, where the lobe's own blur did not.
///
/// The lattice holds each sample's log ratio to the lobe *as measured*, so the table is the
/// sharp lobe times that ratio: exact when the material's shape under the response is the
/// lobe's, off where it is not (on a real glossy paint the lobe's Fresnel and shadowing at
/// grazing theta_d differ from the material's, and the table blurred by the response came
/// out 12 % below its own samples there). Each round predicts every sample within
/// [`BLUR_THETA_H_DEG`] of the peak from the table through the response's `nodes`
/// ([`crate::consistency`]'s forward model), adds `ln(S / P)` to its lattice value and
/// rebuilds the table: a multiplicative Van Cittert iteration on the residual, which changes
/// the table only where the samples ask for it. It stops when a round lowers the
/// reproduction error `sqrt(sum (P - S)^2 / sum S^2)` by less than
/// [`MIN_CORRECTION_GAIN`] (the samples' noise and the table's binning are then what is
/// left, and further rounds would fit them) or after [`MAX_CORRECTIONS`] rounds; a round
/// that makes it worse is not kept. Returns the table and the samples' values it holds.
fn corrected_through(
    samples: &[Sample],
    mut values: Vec<[f64; 3]>,
    nodes: &[CaptureNode],
    floor: LobeTableFloor<'_>,
    build: impl Fn(&[[f64; 3]]) -> Reconstruction,
) -> (Reconstruction, Vec<[f64; 3]>) {
    let blurred: Vec<usize> = (0..samples.len())
        .filter(|&i| samples[i].hd.theta_h.to_degrees() < BLUR_THETA_H_DEG)
        .collect();
    let chosen: Vec<Sample> = blurred.iter().map(|&i| samples[i]).collect();
    let lobe = consistency::LobeCaptures::of(&chosen, floor.lobe, floor.table, nodes);
    let representation = log_errors(&lobe);
    let positioning = positioning_log_uncertainty(&chosen, &lobe.tabulated, floor.table, nodes);
    let noise: Vec<[f64; 3]> = chosen
        .iter()
        .map(|s| crate::denoise::value_sigma(s).map(|n| n.unwrap_or(0.0)))
        .collect();
    let mut table = build(&values);
    let mut predictions = predict(samples, &blurred, &table.brdf, nodes);
    let mut error = reproduction_error(samples, &blurred, &predictions);
    for _ in 0..MAX_CORRECTIONS {
        let mut candidate_values = values.clone();
        for (k, (&i, p)) in blurred.iter().zip(&predictions).enumerate() {
            for c in 0..3 {
                let miss = log_of_measured(samples[i].value[c]) - log_of_measured(p[c]);
                let (r, u) = (representation[k][c], positioning[k][c]);
                let band = DEADBAND_UNCERTAINTIES * r.hypot(u).hypot(noise[k][c]);
                candidate_values[i][c] += shrunk(miss - r, band);
            }
        }
        let candidate = build(&candidate_values);
        let candidate_predictions = predict(samples, &blurred, &candidate.brdf, nodes);
        let candidate_error = reproduction_error(samples, &blurred, &candidate_predictions);
        if candidate_error >= error {
            break;
        }
        let gain = 1.0 - candidate_error / error;
        (values, table, predictions, error) = (
            candidate_values,
            candidate,
            candidate_predictions,
            candidate_error,
        );
        if gain < MIN_CORRECTION_GAIN {
            break;
        }
    }
    (table, values)
}

/// A sample's miss is corrected only by what exceeds this many of its uncertainties: the
/// table's representation of the lobe, the device's positioning through the table and the
/// value's own noise ([`crate::denoise::value_sigma`]: the values the lattice holds were
/// smoothed within it, and a correction must not put it back).
const DEADBAND_UNCERTAINTIES: f64 = 2.0;

/// `x` moved towards zero by `band`, zero within it (soft thresholding): a miss the sample's
/// own uncertainty explains asks for no correction, a larger one for its excess only.
fn shrunk(x: f64, band: f64) -> f64 {
    x.signum() * (x.abs() - band).max(0.0)
}

/// Per sample, the log change of its capture for the device's positioning error
/// ([`consistency::positioning_uncertainty`] through `table`, relative to its capture
/// `tabulated` there): on a sharp flank several percent, which no correction should chase.
fn positioning_log_uncertainty(
    samples: &[Sample],
    tabulated: &[Rgb],
    table: &MerlBrdf,
    nodes: &[CaptureNode],
) -> Vec<[f64; 3]> {
    let u = consistency::positioning_uncertainty(samples, table, nodes);
    u.iter()
        .zip(tabulated)
        .map(|(u, p)| std::array::from_fn(|c| u[c] / p[c].max(f64::MIN_POSITIVE)))
        .collect()
}

/// What the captures of the samples `which` measure of the table through `nodes`.
fn predict(
    samples: &[Sample],
    which: &[usize],
    table: &MerlBrdf,
    nodes: &[CaptureNode],
) -> Vec<Rgb> {
    which
        .par_iter()
        .map(|&i| consistency::predicted(table, nodes, samples[i].hd))
        .collect()
}

/// The lobe and its own table: what a table's bins (interpolated between their centres)
/// lose of a function under the response, which no correction should chase.
struct LobeTableFloor<'a> {
    lobe: &'a Lobe,
    table: &'a MerlBrdf,
}

/// Per sample, `ln(P_table / M_lobe)`: the log error with which the lobe's table, blurred
/// through the response, predicts the lobe's exact capture. Near a sharp peak the bins'
/// interpolation alone is a few percent off; [`corrected_through`] subtracts this from each
/// sample's miss, so it corrects the material's departure from the lobe and not the table's
/// representation of it.
fn log_errors(lobe: &consistency::LobeCaptures) -> Vec<[f64; 3]> {
    lobe.tabulated
        .iter()
        .zip(&lobe.exact)
        .map(|(p, m)| std::array::from_fn(|c| log_of_measured(p[c]) - log_of_measured(m[c])))
        .collect()
}

/// `sqrt(sum (P - S)^2 / sum S^2)` over the samples `which`.
fn reproduction_error(samples: &[Sample], which: &[usize], predictions: &[Rgb]) -> f64 {
    let (error, signal) = which
        .iter()
        .zip(predictions)
        .fold((0.0, 0.0), |(e, s), (&i, p)| {
            let v = samples[i].value;
            (e + (*p - v).length_squared(), s + v.length_squared())
        });
    if signal > 0.0 {
        (error / signal).sqrt()
    } else {
        0.0
    }
}
