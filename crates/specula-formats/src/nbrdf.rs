//! Neural BRDF fits (Sztrajman, Rainer, Ritschel, Weyrich, "Neural BRDF Representation and
//! Importance Sampling", CGF 40(6), 2021): one tiny multilayer perceptron per material, trained
//! on its measured data (MERL-100, the RGL isotropic materials, Nielsen et al. 2015).
//!
//! Layout of one material (675 `f32`, Keras `Dense` convention `y = x K + b`, kernels
//! row-major `[in][out]`): `K1[6][21] b1[21] K2[21][21] b2[21] K3[21][3] b3[3]`.
//! Evaluation: `a1 = relu(x K1 + b1)`, `a2 = relu(a1 K2 + b2)`, `f_r = exp(a2 K3 + b3) - 1`,
//! clamped at zero, in 1/sr (MERL's channel scales already applied). The input is the half
//! and difference vectors with phi_h = 0:
//! `x = [sin th, 0, cos th, sin td cos pd, sin td sin pd, cos td]`.
//! Source and checks: `shared/data/measured/merl_nbrdf/PROVENANCE.md`.

use crate::brdf_source::BrdfSource;
use crate::input::argument_error;
use crate::input::{data_file, file_error, Malformed, Result};
use glam::DVec3;
use specula_core::brdf::both_above_surface;
use specula_core::{Brdf, HalfDiff, Rgb};
use std::sync::Arc;

/// Number of `f32` weights of one material's network.
pub const WEIGHTS_PER_MATERIAL: usize = 675;
const INPUTS: usize = 6;
const HIDDEN: usize = 21;
const OUTPUTS: usize = 3;

/// The three published sets of fitted networks, each with its `model:` prefix.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NbrdfSet {
    /// The 100 MERL materials: `nbrdf:NAME`.
    Merl100,
    /// 51 isotropic materials of the RGL database: `nbrdf-rgl:NAME`.
    RglIsotropic,
    /// 8 materials of Nielsen, Jensen & Ramamoorthi 2015: `nbrdf-nielsen:NAME`.
    Nielsen2015,
}

impl NbrdfSet {
    /// Every set, in the order they are listed.
    pub(crate) const ALL: [NbrdfSet; 3] = [Self::Merl100, Self::RglIsotropic, Self::Nielsen2015];

    /// The `model:` prefix naming this set in BRDF arguments.
    pub fn prefix(self) -> &'static str {
        match self {
            Self::Merl100 => "nbrdf",
            Self::RglIsotropic => "nbrdf-rgl",
            Self::Nielsen2015 => "nbrdf-nielsen",
        }
    }

    /// The set named by a `model:` prefix.
    pub fn from_prefix(prefix: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.prefix() == prefix)
    }

    fn files(self) -> (&'static str, &'static str) {
        match self {
            Self::Merl100 => (
                "merl_nbrdf/merl100_nbrdf_weights_f32le.bin",
                "merl_nbrdf/merl100_names.txt",
            ),
            Self::RglIsotropic => (
                "merl_nbrdf/rgl_isotropic_nbrdf_weights_f32le.bin",
                "merl_nbrdf/rgl_isotropic_names.txt",
            ),
            Self::Nielsen2015 => (
                "merl_nbrdf/nielsen2015_nbrdf_weights_f32le.bin",
                "merl_nbrdf/nielsen2015_names.txt",
            ),
        }
    }

    /// The material names of this set, in the order of its weights file.
    pub fn names(self) -> Result<Vec<String>> {
        let file = data_file(self.files().1)?;
        let text = std::str::from_utf8(&file.bytes)
            .map_err(|_| file_error(&file.path, "is not UTF-8 text"))?;
        Ok(text
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty())
            .map(String::from)
            .collect())
    }
}

impl NbrdfSet {
    /// Every material of this set, in the order of its weights file.
    pub fn load_all(self) -> Result<Vec<BrdfSource>> {
        self.names()?
            .iter()
            .map(|name| Ok(Arc::new(Nbrdf::load(self, name)?) as BrdfSource))
            .collect()
    }
}

/// One material's network, held in `f64`.
#[derive(Debug, Clone)]
pub struct Nbrdf {
    name: String,
    k1: Vec<f64>,
    b1: Vec<f64>,
    k2: Vec<f64>,
    b2: Vec<f64>,
    k3: Vec<f64>,
    b3: Vec<f64>,
}

impl Nbrdf {
    /// The network of `material` in a published set, read from the measured data directory.
    pub fn load(set: NbrdfSet, material: &str) -> Result<Self> {
        let names = set.names()?;
        let row = names.iter().position(|n| n == material).ok_or_else(|| {
            argument_error(
                &format!("{}:{material}", set.prefix()),
                format!(
                    "no such material among the {} of this set{}",
                    names.len(),
                    crate::near_name::did_you_mean(material, &names)
                ),
            )
        })?;
        let file = data_file(set.files().0)?;
        let (path, bytes) = (&file.path, &file.bytes);
        let expected = names.len() * WEIGHTS_PER_MATERIAL * 4;
        if bytes.len() != expected {
            return Err(file_error(
                path,
                format!(
                    "{} bytes, expected {expected} ({} materials x {WEIGHTS_PER_MATERIAL} f32)",
                    bytes.len(),
                    names.len()
                ),
            ));
        }
        let start = row * WEIGHTS_PER_MATERIAL * 4;
        let weights: Vec<f32> = bytes[start..start + WEIGHTS_PER_MATERIAL * 4]
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        Self::from_weights(format!("{}:{material}", set.prefix()), &weights)
            .map_err(|problem| file_error(path, format!("material {material}: {problem}")))
    }

    /// A network from its 675 weights in the published layout; every weight must be finite.
    pub fn from_weights(name: impl Into<String>, weights: &[f32]) -> Result<Self, Malformed> {
        if weights.len() != WEIGHTS_PER_MATERIAL {
            return Err(
                format!("{} weights, expected {WEIGHTS_PER_MATERIAL}", weights.len()).into(),
            );
        }
        if let Some(pos) = weights.iter().position(|w| !w.is_finite()) {
            return Err(format!("weight {pos} is not finite ({})", weights[pos]).into());
        }
        let mut rest = weights.iter().map(|w| *w as f64);
        let mut take = |n: usize| rest.by_ref().take(n).collect::<Vec<f64>>();
        Ok(Self {
            name: name.into(),
            k1: take(INPUTS * HIDDEN),
            b1: take(HIDDEN),
            k2: take(HIDDEN * HIDDEN),
            b2: take(HIDDEN),
            k3: take(HIDDEN * OUTPUTS),
            b3: take(OUTPUTS),
        })
    }

    /// f_r in 1/sr at half-difference angles (radians; phi_h is ignored, the fit is isotropic).
    pub fn eval_angles(&self, theta_h: f64, theta_d: f64, phi_d: f64) -> Rgb {
        let (sin_h, cos_h) = theta_h.sin_cos();
        let (sin_d, cos_d) = theta_d.sin_cos();
        let (sin_pd, cos_pd) = phi_d.sin_cos();
        let x = [sin_h, 0.0, cos_h, sin_d * cos_pd, sin_d * sin_pd, cos_d];
        let a1 = dense(&x, &self.k1, &self.b1, true);
        let a2 = dense(&a1, &self.k2, &self.b2, true);
        let out = dense(&a2, &self.k3, &self.b3, false);
        Rgb::new(out[0], out[1], out[2]).map(|v| v.exp_m1().max(0.0))
    }
}

/// A Keras `Dense` layer `y = x K + b` with `K` row-major `[in][out]`, optionally with ReLU.
fn dense(x: &[f64], kernel: &[f64], bias: &[f64], relu: bool) -> Vec<f64> {
    let outputs = bias.len();
    let mut y = bias.to_vec();
    for (xi, row) in x.iter().zip(kernel.chunks_exact(outputs)) {
        for (yj, kij) in y.iter_mut().zip(row) {
            *yj += xi * kij;
        }
    }
    if relu {
        y.iter_mut().for_each(|v| *v = v.max(0.0));
    }
    y
}

impl Brdf for Nbrdf {
    fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
        if !both_above_surface(wi, wo) {
            return Some(Rgb::ZERO);
        }
        self.eval_half_diff(HalfDiff::from_directions(wi, wo))
    }

    fn eval_half_diff(&self, hd: HalfDiff) -> Option<Rgb> {
        let (wi, wo) = hd.to_directions();
        if !both_above_surface(wi, wo) {
            return Some(Rgb::ZERO);
        }
        Some(self.eval_angles(hd.theta_h, hd.theta_d, hd.phi_d))
    }

    fn name(&self) -> String {
        self.name.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dense_layer_follows_keras_layout() {
        // x = [1, 2], K = [[1, 2, 3], [4, 5, 6]] (row-major [in][out]), b = [0, 0, -100].
        let y = dense(
            &[1.0, 2.0],
            &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
            &[0.0, 0.0, -100.0],
            true,
        );
        assert_eq!(y, vec![9.0, 12.0, 0.0]);
    }

    #[test]
    fn a_whole_set_loads_in_the_order_of_its_names() {
        let all = NbrdfSet::Merl100.load_all().unwrap();
        let names = NbrdfSet::Merl100.names().unwrap();
        assert_eq!(all.len(), 100);
        assert_eq!(all.len(), names.len());
        assert_eq!(all[7].name(), format!("nbrdf:{}", names[7]));
    }

    #[test]
    fn a_network_of_zero_weights_gives_zero() {
        let net = Nbrdf::from_weights("zero", &[0.0; WEIGHTS_PER_MATERIAL]).unwrap();
        assert_eq!(net.eval_angles(0.3, 0.2, 1.0), Rgb::ZERO);
        let mut bad = [0.0f32; WEIGHTS_PER_MATERIAL];
        bad[500] = f32::NAN;
        assert!(Nbrdf::from_weights("bad", &bad)
            .unwrap_err()
            .contains("weight 500"));
        assert!(Nbrdf::from_weights("short", &bad[..10])
            .unwrap_err()
            .contains("10 weights"));
    }
}
