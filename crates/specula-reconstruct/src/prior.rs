//! A data-driven prior of real BRDF shapes: a principal-component basis of measured
//! materials in a log-mapped domain (Nielsen, Jensen & Ramamoorthi 2015, "On optimal, minimal
//! BRDF sampling for reflectance acquisition", eq. 4), fitted to one material's samples by
//! ridge regression (the basis' own variances as the Gaussian prior of the coefficients).
//!
//! **Domain.** A BRDF value f (1/sr) at a configuration with light and camera at cos_i and
//! cos_o from the normal maps to `x = ln(f w + eps)`, `w = max(cos_i cos_o, W_FLOOR)`,
//! `eps` = [`MAPPED_OFFSET`]: the cosine weight keeps the grazing rise of f from dominating,
//! the log the orders of magnitude of a specular peak.
//!
//! **Grid.** The basis lives on a coarse grid of the half-difference angles:
//! [`THETA_H_NODES`] theta_h nodes at the MERL bin centres (index space, `theta_h =
//! u^2 / 90` deg), theta_d every [`THETA_D_STEP_DEG`] from 0, phi_d (folded into [0, 90])
//! every [`PHI_D_STEP_DEG`]. Between nodes it is interpolated linearly (theta_h in index
//! space), so it is evaluated at any sample and at every MERL bin centre.
//!
//! **Training** ([`PriorBasis::derive`]): any set of BRDFs, each channel one training
//! vector. The basis the front ends reconstruct with, the 100 MERL materials as fitted by
//! three published models, is derived where that training set is loaded
//! (`specula_accuracy::merl_prior`) and given to the reconstruction as a value.

use crate::sample::fold_phi_d_rad;
use nalgebra::{DMatrix, DVector, SymmetricEigen};
use rayon::prelude::*;
use specula_core::merl::{self, theta_h_centre_deg, Bin, CELLS, THETA_H_BINS};
use specula_core::Sample;
use specula_core::{Brdf, HalfDiff, Rgb};
use std::sync::Arc;

/// Offset of the mapped domain (Nielsen et al. 2015 use 0.001).
pub const MAPPED_OFFSET: f64 = 1e-3;
/// The smallest cosine weight `cos_i cos_o` of the mapping (grazing configurations).
pub const W_FLOOR: f64 = 1e-2;
/// theta_h nodes: the MERL bin centres.
pub const THETA_H_NODES: usize = THETA_H_BINS;
/// Step of the theta_d nodes (degrees), from 0 to 88.
pub const THETA_D_STEP_DEG: f64 = 2.0;
/// theta_d nodes.
pub const THETA_D_NODES: usize = 45;
/// Step of the folded phi_d nodes (degrees), from 0 to 90.
pub const PHI_D_STEP_DEG: f64 = 10.0;
/// phi_d nodes.
pub const PHI_D_NODES: usize = 10;
/// Nodes of the prior grid (per channel).
pub const NODES: usize = THETA_H_NODES * THETA_D_NODES * PHI_D_NODES;

/// Why the prior cannot be built.
#[derive(Debug, thiserror::Error)]
pub enum PriorError {
    /// No more training vectors (the first count) than components (the second).
    #[error("{0} training vectors: need more than the {1} components")]
    TooFewMaterials(usize, usize),
}

/// The cosine weight of the mapped domain at a configuration.
fn cosine_weight(hd: HalfDiff) -> f64 {
    let (wi, wo) = hd.to_directions();
    (wi.z * wo.z).max(W_FLOOR)
}

/// f (1/sr) to the mapped domain where the cosine weight is `w`.
pub fn to_mapped(f: f64, w: f64) -> f64 {
    (f.max(0.0) * w + MAPPED_OFFSET).ln()
}

/// The mapped domain back to f (1/sr), clamped at zero.
pub fn from_mapped(x: f64, w: f64) -> f64 {
    ((x.exp() - MAPPED_OFFSET) / w).max(0.0)
}

/// Lower node and fraction of a coordinate on nodes `0, 1, ..., n - 1` (clamped).
fn bracket(u: f64, n: usize) -> (usize, f64) {
    let u = u.clamp(0.0, (n - 1) as f64);
    let lower = (u.floor() as usize).min(n - 2);
    (lower, u - lower as f64)
}

/// The flat index of node `(h, d, p)`.
fn node_index(h: usize, d: usize, p: usize) -> usize {
    (h * THETA_D_NODES + d) * PHI_D_NODES + p
}

/// The configuration of node `(h, d, p)` (phi_h 0: the prior is isotropic).
fn node_angles(index: usize) -> HalfDiff {
    let h = index / (THETA_D_NODES * PHI_D_NODES);
    let d = (index / PHI_D_NODES) % THETA_D_NODES;
    let p = index % PHI_D_NODES;
    HalfDiff::from_degrees(
        theta_h_centre_deg(h),
        0.0,
        d as f64 * THETA_D_STEP_DEG,
        p as f64 * PHI_D_STEP_DEG,
    )
}

/// The up-to-eight nodes around a configuration and their trilinear weights.
#[derive(Debug, Clone, Copy)]
pub struct Stencil {
    nodes: [usize; 8],
    weights: [f64; 8],
}

impl Stencil {
    /// Around the configuration `hd` (phi_d folded by the symmetries).
    pub fn of(hd: HalfDiff) -> Self {
        Self::at(
            // MERL index space, node i at the centre of bin i.
            merl::theta_h_coordinate(hd.theta_h.to_degrees()) - 0.5,
            hd.theta_d.to_degrees() / THETA_D_STEP_DEG,
            fold_phi_d_rad(hd.phi_d).to_degrees() / PHI_D_STEP_DEG,
        )
    }

    /// Around grid coordinates (node units on each axis).
    fn at(u_h: f64, u_d: f64, u_p: f64) -> Self {
        let (h, th) = bracket(u_h, THETA_H_NODES);
        let (d, td) = bracket(u_d, THETA_D_NODES);
        let (p, tp) = bracket(u_p, PHI_D_NODES);
        let mut nodes = [0; 8];
        let mut weights = [0.0; 8];
        for corner in 0..8 {
            let (a, b, c) = (corner >> 2 & 1, corner >> 1 & 1, corner & 1);
            nodes[corner] = node_index(h + a, d + b, p + c);
            let w = |bit: usize, t: f64| if bit == 1 { t } else { 1.0 - t };
            weights[corner] = w(a, th) * w(b, td) * w(c, tp);
        }
        Self { nodes, weights }
    }

    /// The interpolated value of a field on the grid.
    pub fn apply(&self, field: &[f32]) -> f64 {
        self.nodes
            .iter()
            .zip(&self.weights)
            .map(|(&n, &w)| w * field[n] as f64)
            .sum()
    }
}

/// The mean and the principal components of the training vectors on the prior grid.
#[derive(Debug, Clone)]
pub struct PriorBasis {
    /// Mean of the training vectors, mapped domain, one value per node.
    pub mean: Vec<f32>,
    /// Unit-norm principal components, largest variance first.
    pub components: Vec<Vec<f32>>,
    /// Variance of each component's coefficient over the training vectors.
    pub variances: Vec<f64>,
    /// How many training vectors (materials x channels) built it.
    pub training_vectors: usize,
}

impl PriorBasis {
    /// The basis of `components` principal components of the training BRDFs, each channel
    /// one vector (PCA through the Gram matrix of the centred vectors).
    pub fn derive(training: &[Arc<dyn Brdf>], components: usize) -> Result<Self, PriorError> {
        let vectors: Vec<Vec<f32>> = training
            .par_iter()
            .flat_map_iter(|brdf| mapped_on_grid(brdf.as_ref()))
            .collect();
        let n = vectors.len();
        if n <= components {
            return Err(PriorError::TooFewMaterials(n, components));
        }
        let mut mean = vec![0.0f64; NODES];
        for v in &vectors {
            for (m, x) in mean.iter_mut().zip(v) {
                *m += *x as f64;
            }
        }
        mean.iter_mut().for_each(|m| *m /= n as f64);
        let centred: Vec<Vec<f32>> = vectors
            .into_par_iter()
            .map(|v| v.iter().zip(&mean).map(|(x, m)| x - *m as f32).collect())
            .collect();
        let gram = gram_matrix(&centred);
        let eigen = SymmetricEigen::new(gram);
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| eigen.eigenvalues[b].total_cmp(&eigen.eigenvalues[a]));
        let mut out_components = Vec::with_capacity(components);
        let mut variances = Vec::with_capacity(components);
        for &k in order.iter().take(components) {
            let lambda = eigen.eigenvalues[k].max(1e-300);
            let coefficients = eigen.eigenvectors.column(k);
            let component: Vec<f32> = (0..NODES)
                .into_par_iter()
                .map(|node| {
                    let dot: f64 = centred
                        .iter()
                        .zip(coefficients.iter())
                        .map(|(v, c)| v[node] as f64 * c)
                        .sum();
                    (dot / lambda.sqrt()) as f32
                })
                .collect();
            out_components.push(component);
            variances.push(lambda / n as f64);
        }
        Ok(Self {
            mean: mean.into_iter().map(|m| m as f32).collect(),
            components: out_components,
            variances,
            training_vectors: n,
        })
    }

    /// Fits the basis to samples, each channel apart: the coefficients maximise the
    /// posterior with a Gaussian prior of the basis' variances and Gaussian errors of
    /// variance `noise_variance` in the mapped domain (ridge regression).
    pub fn fit(&self, samples: &[Sample], noise_variance: f64) -> PriorFit {
        let k = self.components.len();
        let rows: Vec<(Stencil, f64, Rgb)> = samples
            .iter()
            .map(|s| (Stencil::of(s.hd), cosine_weight(s.hd), s.value))
            .collect();
        let design = DMatrix::from_fn(rows.len(), k, |r, c| rows[r].0.apply(&self.components[c]));
        let mut normal = design.transpose() * &design;
        for c in 0..k {
            normal[(c, c)] += noise_variance / self.variances[c];
        }
        let cholesky = normal.cholesky();
        let coefficients = std::array::from_fn(|channel| {
            let target = DVector::from_fn(rows.len(), |r, _| {
                let (stencil, w, value) = &rows[r];
                to_mapped(value[channel], *w) - stencil.apply(&self.mean)
            });
            let rhs = design.transpose() * target;
            cholesky.as_ref().map_or_else(
                || vec![0.0; k],
                |ch| ch.solve(&rhs).iter().copied().collect(),
            )
        });
        self.field_of(coefficients)
    }

    /// The mapped field of given coefficients on the grid, per channel.
    fn field_of(&self, coefficients: [Vec<f64>; 3]) -> PriorFit {
        let field = coefficients.each_ref().map(|a| {
            (0..NODES)
                .map(|node| {
                    let x = self.mean[node] as f64
                        + a.iter()
                            .zip(&self.components)
                            .map(|(c, u)| c * u[node] as f64)
                            .sum::<f64>();
                    x as f32
                })
                .collect()
        });
        PriorFit { field }
    }
}

/// The mapped values of a BRDF at every node of the prior grid, one vector per channel.
fn mapped_on_grid(brdf: &dyn Brdf) -> [Vec<f32>; 3] {
    let values: Vec<[f32; 3]> = (0..NODES)
        .map(|node| {
            let hd = node_angles(node);
            let w = cosine_weight(hd);
            let f = brdf.eval_half_diff(hd).unwrap_or(Rgb::ZERO);
            std::array::from_fn(|c| to_mapped(if f[c].is_finite() { f[c] } else { 0.0 }, w) as f32)
        })
        .collect();
    std::array::from_fn(|c| values.iter().map(|v| v[c]).collect())
}

/// `G_ij = v_i . v_j` of the centred training vectors.
fn gram_matrix(vectors: &[Vec<f32>]) -> DMatrix<f64> {
    let n = vectors.len();
    let rows: Vec<Vec<f64>> = (0..n)
        .into_par_iter()
        .map(|i| {
            (0..=i)
                .map(|j| {
                    vectors[i]
                        .iter()
                        .zip(&vectors[j])
                        .map(|(a, b)| (a * b) as f64)
                        .sum()
                })
                .collect()
        })
        .collect();
    DMatrix::from_fn(n, n, |i, j| if j <= i { rows[i][j] } else { rows[j][i] })
}

/// A prior fitted to one material: its mapped field on the prior grid, per channel.
#[derive(Debug, Clone)]
pub struct PriorFit {
    field: [Vec<f32>; 3],
}

impl PriorFit {
    /// f (1/sr) at a configuration.
    pub fn eval(&self, hd: HalfDiff) -> Rgb {
        let stencil = Stencil::of(hd);
        let w = cosine_weight(hd);
        Rgb::new(
            from_mapped(stencil.apply(&self.field[0]), w),
            from_mapped(stencil.apply(&self.field[1]), w),
            from_mapped(stencil.apply(&self.field[2]), w),
        )
    }

    /// f (1/sr) at the centre of every MERL cell (phi_h 0), in cell order; zero below the
    /// surface.
    pub fn on_merl_grid(&self) -> Vec<Rgb> {
        (0..CELLS)
            .into_par_iter()
            .map(|index| {
                let bin = Bin::from_index(index);
                let hd = HalfDiff::from_degrees(
                    theta_h_centre_deg(bin.theta_h_i),
                    0.0,
                    bin.theta_d_i as f64 + 0.5,
                    bin.phi_d_i as f64 + 0.5,
                );
                let (wi, wo) = hd.to_directions();
                if wi.z <= 0.0 || wo.z <= 0.0 {
                    Rgb::ZERO
                } else {
                    self.eval(hd)
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::materials::preset;

    #[test]
    fn the_mapping_round_trips() {
        for (f, w) in [(0.0, 0.5), (3.2, 0.01), (1500.0, 0.9), (0.02, 1.0)] {
            assert!((from_mapped(to_mapped(f, w), w) - f).abs() < 1e-9 * (1.0 + f));
        }
    }

    #[test]
    fn stencils_reproduce_a_field_linear_in_the_grid_coordinates() {
        let field: Vec<f32> = (0..NODES)
            .map(|n| {
                let (h, d, p) = (
                    n / (THETA_D_NODES * PHI_D_NODES),
                    (n / PHI_D_NODES) % THETA_D_NODES,
                    n % PHI_D_NODES,
                );
                (h as f64 * 0.5 + d as f64 * 0.25 + p as f64) as f32
            })
            .collect();
        // theta_h 1.6 deg is u = 12 - 0.5 = 11.5; theta_d 33 deg is 16.5; phi_d 165 folds to 15, 1.5.
        let hd = HalfDiff::from_degrees(1.6, 0.0, 33.0, 165.0);
        let expected = 11.5 * 0.5 + 16.5 * 0.25 + 1.5;
        assert!((Stencil::of(hd).apply(&field) - expected).abs() < 1e-4);
    }

    /// A basis of materials spans each of them: the ridge fit to dense samples of a training
    /// material with a tiny noise variance gives the material back.
    #[test]
    fn a_basis_fits_its_own_training_materials() {
        let names = ["silver-925", "green-paint", "chrome", "steel"];
        let training: Vec<Arc<dyn Brdf>> = names
            .iter()
            .map(|n| Arc::new(preset(n).unwrap()) as Arc<dyn Brdf>)
            .collect();
        let basis = PriorBasis::derive(&training, 11).unwrap();
        assert_eq!((basis.components.len(), basis.training_vectors), (11, 12));
        let truth = &training[1];
        // Samples on grid nodes, where the basis holds the training vectors exactly.
        let mut samples = Vec::new();
        for h in [0, 3, 10, 20, 40, 60] {
            for d in (0..80).step_by(4) {
                for p in [0.0, 30.0, 60.0, 90.0] {
                    let hd = HalfDiff::from_degrees(theta_h_centre_deg(h), 0.0, d as f64, p);
                    samples.push(Sample::new(hd, truth.eval_half_diff(hd).unwrap()));
                }
            }
        }
        let fit = basis.fit(&samples, 1e-8);
        let on_node = HalfDiff::from_degrees(theta_h_centre_deg(20), 0.0, 40.0, 30.0);
        let want = truth.eval_half_diff(on_node).unwrap();
        let got = fit.eval(on_node);
        for c in 0..3 {
            assert!(
                (got[c] - want[c]).abs() < 1e-3 * want[c] + 1e-6,
                "{got:?} vs {want:?}"
            );
        }
        // Too few vectors for the components asked.
        assert!(matches!(
            PriorBasis::derive(&training[..1], 11),
            Err(PriorError::TooFewMaterials(3, 11))
        ));
    }
}
