//! What a reconstruction returns, why it can fail, and the steps every method shares: the
//! samples' reciprocal canonical form, the lobe as a capture measures it, and the table of
//! values in a method's domain (lattice, extrapolation, interpolation at the MERL bin
//! centres, provenance).

use crate::extrapolate::fill_missing;
use crate::grid::{extrapolated_cells, interpolate_cell, interpolate_to_merl};
use crate::lattice::Lattice;
use crate::lobe::{Geometry, Lobe, BLUR_THETA_H_DEG};
use crate::method::Method;
use crate::provenance::Provenance;
use crate::safeguard::Safeguard;
use rayon::prelude::*;
use specula_core::capture::CaptureNode;
use specula_core::merl::{stored_round_trip, MerlBrdf};
use specula_core::{HalfDiff, Rgb, Sample};
use std::collections::HashMap;

/// Why samples cannot be reconstructed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReconstructError {
    /// There are no samples.
    #[error("no samples to reconstruct from")]
    NoSamples,
    /// No sample has both light and camera above the surface, so no lobe can be fitted.
    #[error("no sample has both light and camera above the surface: cannot fit a lobe")]
    NoLobe,
    /// The `prior` method was asked for without the basis it blends in.
    #[error("the prior method needs a prior basis, and none was given")]
    NoPriorBasis,
}

/// A reconstructed table with what it was made from.
#[derive(Debug, Clone)]
pub struct Reconstruction {
    /// The reconstructed table, f_r in 1/sr per MERL cell.
    pub brdf: MerlBrdf,
    /// Where each cell's value comes from.
    pub provenance: Provenance,
    /// The fitted lobe of the `lobe` method.
    pub lobe: Option<Lobe>,
    /// The instrument's resolution in theta_h (degrees) when the lobe was fitted through its
    /// response; `None` without one.
    pub resolution_deg: Option<f64>,
    /// Lattice nodes along theta_h, theta_d, phi_d.
    pub lattice_shape: [usize; 3],
    /// Lattice nodes measured and extrapolated.
    pub measured_nodes: usize,
    /// Lattice nodes filled by extrapolation.
    pub filled_nodes: usize,
    /// What the checks of a deblurred table found ([`crate::safeguard`]); `None` when the
    /// table was not deblurred.
    pub safeguard: Option<Safeguard>,
    /// The deblurred table whose cells the safeguard replaced by the un-deblurred ones or
    /// bounded ([`Safeguard::fallback_below_deg`], [`Safeguard::bounded_below_deg`]): what the uncertainty's deblurring term compares
    /// them with ([`crate::uncertainty`]); `None` when nothing was replaced.
    pub deblurred_replaced: Option<MerlBrdf>,
    /// The table made from the same samples without the response, which the safeguard
    /// checked the deblurred one against; `None` when the table was not deblurred.
    pub undeblurred: Option<MerlBrdf>,
    /// The models a deblurred `lobe` table holds its samples' residuals over, one per half of
    /// phi_d reconstructed apart (first, second) or one for the whole: what the uncertainty
    /// cross-validates the table with ([`crate::uncertainty`]). Empty when the table was not
    /// deblurred, or deblurred by another method.
    pub residual_models: Vec<ResidualModel>,
}

/// What a deblurred `lobe` table is made of: the lobe fitted through the instrument's
/// response and each sample's value in the method's domain over that lobe as measured, after
/// the corrections through the response ([`crate::reconstruct`]). The table is the lobe
/// times those values interpolated; a table of some of the samples over the same model is
/// what the uncertainty's cross-validation compares with it.
#[derive(Debug, Clone, PartialEq)]
pub struct ResidualModel {
    /// The lobe before the blur.
    pub lobe: Lobe,
    /// Each sample's domain value, by its reciprocal canonical form ([`configuration_key`]).
    values: HashMap<[u64; 6], [f64; 3]>,
}

impl ResidualModel {
    /// The model of `lobe` whose samples hold `values` in the method's domain.
    pub(crate) fn new(lobe: Lobe, samples: &[Sample], values: &[[f64; 3]]) -> Self {
        let values = samples
            .iter()
            .zip(values)
            .map(|(s, v)| (configuration_key(s), *v))
            .collect();
        Self { lobe, values }
    }

    /// The domain value the table holds for `sample`, `None` for a sample it was not made
    /// from.
    pub(crate) fn value(&self, sample: &Sample) -> Option<[f64; 3]> {
        self.values.get(&configuration_key(sample)).copied()
    }
}

/// A sample's reciprocal canonical configuration and value, bit for bit: the same key for
/// a sample and its light/camera swap.
fn configuration_key(sample: &Sample) -> [u64; 6] {
    let s = reciprocal_canonical(sample);
    [
        s.hd.theta_h.to_bits(),
        s.hd.theta_d.to_bits(),
        s.hd.phi_d.to_bits(),
        s.value.x.to_bits(),
        s.value.y.to_bits(),
        s.value.z.to_bits(),
    ]
}

/// The lobe as a capture at `hd` measures it: through the nodes near the peak, where the fit
/// used them ([`crate::lobe::BLUR_THETA_H_DEG`]), else the lobe itself.
pub(crate) fn measured_lobe(lobe: &Lobe, nodes: &[CaptureNode], hd: HalfDiff) -> Rgb {
    if hd.theta_h.to_degrees() < BLUR_THETA_H_DEG {
        lobe.measured(nodes, hd)
    } else {
        lobe.eval(&Geometry::of(hd))
    }
}

/// The sample with phi_d folded into `[0, pi)` by reciprocity (paper 3: phi_d and
/// phi_d + pi are the same configuration) and rounded to 1e-9 rad, far below the device's
/// 0.03 deg accuracy. The rounding makes a sample and its light/camera swap bit-identical, so
/// the lobe fit, which can be ill-conditioned on data far from a lobe, cannot amplify the
/// last-bit difference between the two into different lobes. Only the lobe (its fit and the
/// samples' ratios to it) sees it: bins and provenance keep the samples' own angles.
pub(crate) fn reciprocal_canonical(sample: &Sample) -> Sample {
    const QUANTUM_RAD: f64 = 1e-9;
    let folded = sample.hd.phi_d.rem_euclid(std::f64::consts::PI);
    let phi_d = ((folded / QUANTUM_RAD).round() * QUANTUM_RAD).rem_euclid(std::f64::consts::PI);
    Sample {
        hd: HalfDiff { phi_d, ..sample.hd },
        ..*sample
    }
}

/// The steps every method shares once each sample has its value in `method`'s domain: the
/// lattice, its missing nodes extrapolated ([`crate::extrapolate`]), interpolation at every
/// MERL bin centre with the method's kernel, and the way back from the domain over `model`
/// (the model's value at a MERL cell index; zero for the methods without one). No lobe and
/// no resolution: the caller adds its own.
pub(crate) fn table_of_domain_values(
    samples: &[Sample],
    domain_values: &[[f64; 3]],
    method: Method,
    name: &str,
    model: impl Fn(usize) -> Rgb + Sync,
) -> Reconstruction {
    let (lattice, measured_nodes) = filled_lattice(samples, domain_values);
    let planes = interpolate_to_merl(&lattice, method.kernel());
    let brdf = MerlBrdf::from_fn(name, |index| {
        let values = planes.each_ref().map(|plane| plane[index]);
        Some(from_domain(method, values, model(index)))
    });
    Reconstruction {
        brdf,
        provenance: Provenance::new(samples, &extrapolated_cells(&lattice)),
        lobe: None,
        resolution_deg: None,
        lattice_shape: lattice.shape(),
        measured_nodes,
        filled_nodes: lattice.status.len() - measured_nodes,
        safeguard: None,
        deblurred_replaced: None,
        undeblurred: None,
        residual_models: Vec::new(),
    }
}

/// The cells `indices` of the table [`table_of_domain_values`] makes, bit for bit, without
/// making the table: the lattice and its extrapolation as there, then each cell's
/// interpolation alone ([`interpolate_cell`]).
pub(crate) fn cells_of_domain_values(
    samples: &[Sample],
    domain_values: &[[f64; 3]],
    method: Method,
    model: impl Fn(usize) -> Rgb + Sync,
    indices: &[usize],
) -> Vec<Option<Rgb>> {
    let (lattice, _) = filled_lattice(samples, domain_values);
    indices
        .par_iter()
        .map(|&index| {
            let values = interpolate_cell(&lattice, method.kernel(), index);
            stored_round_trip(Some(from_domain(method, values, model(index))))
        })
        .collect()
}

/// The samples' lattice with its missing nodes extrapolated ([`crate::extrapolate`]), and
/// how many nodes were measured.
fn filled_lattice(samples: &[Sample], domain_values: &[[f64; 3]]) -> (Lattice, usize) {
    let mut lattice = Lattice::of_samples(samples, domain_values);
    let (measured_nodes, _, _) = lattice.status_counts();
    fill_missing(&mut lattice);
    (lattice, measured_nodes)
}

/// f_r in 1/sr of a cell's interpolated `values` in `method`'s domain over the model's value
/// `model` there.
fn from_domain(method: Method, values: [f64; 3], model: Rgb) -> Rgb {
    let domain = method.domain();
    Rgb::new(
        domain.inverse(values[0], model.x),
        domain.inverse(values[1], model.y),
        domain.inverse(values[2], model.z),
    )
}
