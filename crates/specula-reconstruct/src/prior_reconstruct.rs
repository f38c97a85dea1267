//! The `prior` method: a model of the material times the measured residual, where the model
//! blends the fitted microfacet [`crate::lobe`] with the data-driven [`crate::prior`] by a
//! trust that the material's own samples decide.
//!
//! Model, per channel: `ln(m + eps) = (1 - w) ln(lobe + eps) + w ln(prior + eps)`, with the
//! prior fitted to the samples by ridge regression of noise variance `s2`. The lattice holds
//! `ln((f + eps) / (m + eps))` as the `lobe` method's does ([`crate::domain`]), interpolated
//! by monotone cubics. Nodes no sample reached continue the nearest measured residual
//! ([`crate::extrapolate`]) over the model, so the model's shape, not a copy of the nearest
//! measured value, carries what the device cannot reach; where the prior has a weight there,
//! those cells are marked [`crate::provenance::CellOrigin::Prior`]. (Residual 0 there, the
//! model alone, was measured worse on the RGL files: the residual of the last measured node
//! is the better guess of the level.)
//!
//! **Trust** (`w`, `s2`) by cross-validation on the samples: the lattice's odd theta_d rows
//! are predicted from the even ones (a prior fitted to the even rows' samples only, the
//! residual interpolated linearly between the neighbouring rows), then the odd theta_h
//! columns from the even ones; the pair with the least product of the held-out relative RMSE
//! (cosine-weighted) and log RMSE wins. A near-diffuse material, on which a MERL-shaped prior
//! predicts held-out samples worse than the lobe, keeps `w` near 0.

use crate::domain::{Domain, LOG_OFFSET};
use crate::lattice::{coordinates, Lattice, NodeStatus};
use crate::lobe::{Geometry, Lobe, LobeOnGrid};
use crate::method::Method;
use crate::prior::{PriorBasis, PriorFit};
use crate::reconstruction::{
    measured_lobe, reciprocal_canonical, table_of_domain_values, ReconstructError, Reconstruction,
};
use crate::response_nodes::ResponseNodes;
use rayon::prelude::*;
use specula_core::capture::CaptureResponse;
use specula_core::Sample;
use specula_core::{HalfDiff, Rgb};

/// Candidate noise variances of the ridge fit (mapped domain, squared log units).
pub const NOISE_VARIANCES: [f64; 3] = [0.01, 0.1, 1.0];
/// Candidate weights of the prior in the model (0: the lobe alone, 1: the prior alone).
pub const PRIOR_WEIGHTS: [f64; 5] = [0.0, 0.25, 0.5, 0.75, 1.0];

/// How much a material's samples trust the prior.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Trust {
    /// `w` of the module documentation.
    pub prior_weight: f64,
    /// `s2` of the ridge fit.
    pub noise_variance: f64,
    /// Held-out relative RMSE and log RMSE of the chosen pair.
    pub held_out: [f64; 2],
}

/// The model of a material: the lobe, the fitted prior and the weight between them.
struct Model<'a> {
    lobe: &'a Lobe,
    prior: &'a PriorFit,
    weight: f64,
}

impl Model<'_> {
    fn blend(&self, lobe: Rgb, prior: Rgb) -> Rgb {
        let w = self.weight;
        let mix = |l: f64, p: f64| {
            ((1.0 - w) * (l + LOG_OFFSET).ln() + w * (p + LOG_OFFSET).ln()).exp() - LOG_OFFSET
        };
        Rgb::new(
            mix(lobe.x, prior.x),
            mix(lobe.y, prior.y),
            mix(lobe.z, prior.z),
        )
    }

    fn eval(&self, hd: HalfDiff) -> Rgb {
        self.blend(self.lobe.eval(&Geometry::of(hd)), self.prior.eval(hd))
    }
}

/// Reconstructs the full MERL table named `name` with the `prior` method (see the module
/// documentation), and the trust it used: the one given as `(prior weight, noise
/// variance)`, else the one the samples choose ([`choose_trust`]). With a `response` the lobe
/// is fitted through it and the residual is taken to the model as measured: the lobe as
/// the instrument captures it, blended with the prior (a basis of sharp tables).
pub fn reconstruct_with_prior<R: CaptureResponse + ?Sized>(
    samples: &[Sample],
    basis: &PriorBasis,
    name: &str,
    given: Option<(f64, f64)>,
    response: Option<&R>,
) -> Result<(Reconstruction, Trust), ReconstructError> {
    if samples.is_empty() {
        return Err(ReconstructError::NoSamples);
    }
    let canonical: Vec<Sample> = samples.iter().map(reciprocal_canonical).collect();
    let nodes = ResponseNodes::of(response);
    let lobe = Lobe::fit_through(&canonical, &nodes.fit).ok_or(ReconstructError::NoLobe)?;
    let trust = match given {
        Some((prior_weight, noise_variance)) => Trust {
            prior_weight,
            noise_variance,
            held_out: [f64::NAN; 2],
        },
        None => choose_trust(&canonical, &lobe, basis),
    };
    let prior = basis.fit(&canonical, trust.noise_variance);
    let model = Model {
        lobe: &lobe,
        prior: &prior,
        weight: trust.prior_weight,
    };
    let domain = Method::Prior.domain();
    let residuals: Vec<[f64; 3]> = canonical
        .par_iter()
        .map(|s| {
            let captured = measured_lobe(&lobe, &nodes.residual, s.hd);
            let m = model.blend(captured, prior.eval(s.hd));
            std::array::from_fn(|c| domain.forward(s.value[c], m[c]))
        })
        .collect();
    let residuals = crate::denoise::smoothed(samples, &residuals);
    let lobe_on_grid = LobeOnGrid::new(lobe);
    let prior_on_grid = prior.on_merl_grid();
    let mut reconstruction =
        table_of_domain_values(samples, &residuals, Method::Prior, name, |index| {
            model.blend(lobe_on_grid.at(index), prior_on_grid[index])
        });
    if trust.prior_weight > 0.0 {
        reconstruction.provenance.mark_prior();
    }
    let reconstruction = Reconstruction {
        lobe: Some(lobe),
        resolution_deg: nodes.resolution_deg,
        ..reconstruction
    };
    Ok((reconstruction, trust))
}

/// A measured lattice node: its angles and the mean measured value.
#[derive(Debug, Clone, Copy)]
struct Node {
    hd: HalfDiff,
    value: Rgb,
}

/// One held-out prediction: the node predicted and its two neighbours along the held-out
/// axis, with the interpolation fraction between them.
struct HeldOut {
    target: Node,
    neighbours: [Node; 2],
    t: f64,
}

/// A cross-validation fold: the samples a prior is fitted to and what it predicts.
struct Fold {
    training: Vec<Sample>,
    held_out: Vec<HeldOut>,
}

/// The folds of the module documentation: odd theta_d rows, then odd theta_h columns.
fn folds(samples: &[Sample]) -> Vec<Fold> {
    let values: Vec<[f64; 3]> = samples
        .iter()
        .map(|s| [s.value.x, s.value.y, s.value.z])
        .collect();
    let lattice = Lattice::of_samples(samples, &values);
    let [nh, nd, np] = lattice.shape();
    let node = |h: usize, d: usize, p: usize| {
        let i = lattice.index(h, d, p);
        (lattice.status[i] == NodeStatus::Measured).then(|| Node {
            hd: HalfDiff::from_degrees(
                lattice.theta_h.nodes[h],
                0.0,
                lattice.theta_d.nodes[d],
                lattice.phi_d.nodes[p],
            ),
            value: Rgb::new(
                lattice.values[0][i],
                lattice.values[1][i],
                lattice.values[2][i],
            ),
        })
    };
    let mut out = Vec::new();
    for axis in [1usize, 0] {
        let nodes = if axis == 1 {
            &lattice.theta_d.nodes
        } else {
            &lattice.theta_h.nodes
        };
        let mut held_out = Vec::new();
        for h in 0..nh {
            for d in 0..nd {
                for p in 0..np {
                    let i = if axis == 1 { d } else { h };
                    if i % 2 == 0 || i + 1 >= nodes.len() {
                        continue;
                    }
                    let at = |j: usize| {
                        if axis == 1 {
                            node(h, j, p)
                        } else {
                            node(j, d, p)
                        }
                    };
                    if let (Some(target), Some(a), Some(b)) = (at(i), at(i - 1), at(i + 1)) {
                        let t = (nodes[i] - nodes[i - 1]) / (nodes[i + 1] - nodes[i - 1]);
                        held_out.push(HeldOut {
                            target,
                            neighbours: [a, b],
                            t,
                        });
                    }
                }
            }
        }
        let axis_of = |s: &Sample| {
            let c = coordinates(s.hd);
            if axis == 1 {
                lattice.theta_d.nearest(c[1])
            } else {
                lattice.theta_h.nearest(c[0])
            }
        };
        let training = samples
            .iter()
            .filter(|s| axis_of(s) % 2 == 0)
            .copied()
            .collect();
        if !held_out.is_empty() {
            out.push(Fold { training, held_out });
        }
    }
    out
}

/// Sums of the held-out error figures ([`specula_core::compare`]'s definitions).
#[derive(Debug, Default, Clone, Copy)]
struct ErrorSums {
    weighted_error: f64,
    weighted_truth: f64,
    log_error: f64,
    count: usize,
}

impl ErrorSums {
    fn add(&mut self, predicted: Rgb, truth: Rgb, hd: HalfDiff) {
        let (wi, wo) = hd.to_directions();
        let w = wi.z * wo.z;
        for c in 0..3 {
            let (a, b) = (predicted[c], truth[c]);
            self.weighted_error += (w * (a - b)).powi(2);
            self.weighted_truth += (w * b).powi(2);
            self.log_error += ((1.0 + a * wi.z).ln() - (1.0 + b * wi.z).ln()).powi(2);
            self.count += 1;
        }
    }

    /// Relative RMSE and log RMSE.
    fn figures(&self) -> [f64; 2] {
        [
            (self.weighted_error / self.weighted_truth.max(1e-300)).sqrt(),
            (self.log_error / self.count.max(1) as f64).sqrt(),
        ]
    }
}

/// The trust of the module documentation.
pub fn choose_trust(samples: &[Sample], lobe: &Lobe, basis: &PriorBasis) -> Trust {
    let folds = folds(samples);
    let fitted: Vec<Vec<PriorFit>> = NOISE_VARIANCES
        .par_iter()
        .map(|&s2| folds.iter().map(|f| basis.fit(&f.training, s2)).collect())
        .collect();
    let mut best: Option<Trust> = None;
    for (&noise_variance, priors) in NOISE_VARIANCES.iter().zip(&fitted) {
        for &prior_weight in &PRIOR_WEIGHTS {
            let mut sums = ErrorSums::default();
            for (fold, prior) in folds.iter().zip(priors) {
                let model = Model {
                    lobe,
                    prior,
                    weight: prior_weight,
                };
                for h in &fold.held_out {
                    sums.add(predict(&model, h), h.target.value, h.target.hd);
                }
            }
            let held_out = sums.figures();
            let better = best
                .is_none_or(|b| held_out[0] * held_out[1] < b.held_out[0] * b.held_out[1] - 1e-15);
            if better {
                best = Some(Trust {
                    prior_weight,
                    noise_variance,
                    held_out,
                });
            }
        }
    }
    best.unwrap_or(Trust {
        prior_weight: 0.0,
        noise_variance: NOISE_VARIANCES[1],
        held_out: [f64::NAN; 2],
    })
}

/// The held-out node as the model times the residual interpolated from its neighbours.
fn predict(model: &Model, h: &HeldOut) -> Rgb {
    let domain = Domain::LobeResidual;
    let m = model.eval(h.target.hd);
    let [a, b] = h.neighbours.map(|n| (n.value, model.eval(n.hd)));
    Rgb::from_array(std::array::from_fn(|c| {
        let ra = domain.forward(a.0[c], a.1[c]);
        let rb = domain.forward(b.0[c], b.1[c]);
        domain.inverse(ra + h.t * (rb - ra), m[c])
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::provenance::CellOrigin;
    use glam::DVec3;
    use specula_core::materials::preset;
    use specula_core::Brdf;
    use std::sync::Arc;

    /// A Lambertian surface: the near-diffuse material a specular prior must not spike.
    struct Lambertian;

    impl Brdf for Lambertian {
        fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
            Some(if wi.z > 0.0 && wo.z > 0.0 {
                Rgb::new(0.2, 0.3, 0.4) / std::f64::consts::PI
            } else {
                Rgb::ZERO
            })
        }
        fn name(&self) -> String {
            "lambertian".into()
        }
    }

    /// A basis of four components derived from built-in presets.
    fn basis_of(presets: &[&str]) -> PriorBasis {
        let training: Vec<Arc<dyn Brdf>> = presets
            .iter()
            .map(|n| Arc::new(preset(n).unwrap()) as Arc<dyn Brdf>)
            .collect();
        PriorBasis::derive(&training, 4).unwrap()
    }

    fn samples_of(truth: &dyn Brdf) -> Vec<Sample> {
        let mut configurations = Vec::new();
        for h in [0.0, 0.5, 2.0, 5.0, 10.0, 20.0, 35.0, 55.0] {
            for d in (0..90).step_by(5) {
                for p in [0.0, 30.0, 60.0, 90.0] {
                    let hd = HalfDiff::from_degrees(h, 45.0, d as f64, p);
                    let (wi, wo) = hd.to_directions();
                    let min_cos = 75f64.to_radians().cos() - 1e-12;
                    if wi.z >= min_cos && wo.z >= min_cos {
                        configurations.push(hd);
                    }
                }
            }
        }
        configurations
            .iter()
            .filter_map(|&hd| truth.eval_half_diff(hd).map(|v| Sample::new(hd, v)))
            .collect()
    }

    #[test]
    fn a_diffuse_material_does_not_trust_a_specular_prior() {
        let basis = basis_of(&["chrome", "silver-925", "steel"]);
        let samples = samples_of(&Lambertian);
        let (chosen, trust) =
            reconstruct_with_prior(&samples, &basis, "t", None, None::<&dyn CaptureResponse>)
                .unwrap();
        assert_eq!(trust.prior_weight, 0.0, "{trust:?}");
        // No prior weight: the unreached cells are extrapolated, none from the prior.
        assert_eq!(chosen.provenance.prior_count(), 0);
        let expected = Lambertian.eval_half_diff(HalfDiff::from_degrees(0.0, 0.0, 1.0, 0.0));
        let at_peak = chosen.brdf.cell(0).unwrap();
        assert!(
            (at_peak - expected.unwrap()).abs().max_element() < 1e-3,
            "{at_peak:?}"
        );
        // The prior forced on it: the peak the specular basis brings, and cells marked.
        let (forced, _) = reconstruct_with_prior(
            &samples,
            &basis,
            "t",
            Some((1.0, 1.0)),
            None::<&dyn CaptureResponse>,
        )
        .unwrap();
        assert!(forced.provenance.prior_count() > 0);
        assert!(forced.provenance.cells.contains(&CellOrigin::Prior));
    }

    #[test]
    fn without_the_prior_s_weight_it_is_the_lobe_method() {
        // w = 0 makes the model the lobe alone: the table must be the `lobe` method's with a
        // point light. (Through a response the `lobe` method then corrects its residual
        // through the response, `reconstruct::corrected_through`, which this method does not:
        // there the two differ by that correction, and only the lobe and resolution agree.)
        let basis = basis_of(&["chrome", "green-paint", "steel"]);
        let samples = samples_of(&preset("silver-925").unwrap());
        let utia = specula_acquisition::device::Device::utia().response();
        let (prior, _) =
            reconstruct_with_prior(&samples, &basis, "p", Some((0.0, 0.1)), Some(&utia)).unwrap();
        let lobe =
            crate::reconstruct_through(&samples, crate::Method::Lobe, "l", Some(&utia), None)
                .unwrap();
        assert_eq!(prior.resolution_deg, lobe.resolution_deg);
        assert_eq!(prior.lobe, lobe.lobe);
        let response = None::<&dyn CaptureResponse>;
        let (prior, _) =
            reconstruct_with_prior(&samples, &basis, "p", Some((0.0, 0.1)), response).unwrap();
        let lobe =
            crate::reconstruct_through(&samples, crate::Method::Lobe, "l", response, None).unwrap();
        assert_eq!(prior.provenance, lobe.provenance);
        for index in (0..specula_core::merl::CELLS).step_by(997) {
            let (a, b) = (
                prior.brdf.cell(index).unwrap(),
                lobe.brdf.cell(index).unwrap(),
            );
            let scale = b.abs().max_element().max(1e-6);
            assert!(
                (a - b).abs().max_element() < 1e-9 * scale,
                "cell {index}: {a:?} against {b:?}"
            );
        }
    }
}
