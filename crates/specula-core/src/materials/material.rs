//! A reference material: a base (rough conductor or clear-coated paint) and an optional
//! scratch lobe, usable wherever a [`Brdf`] is (simulated device, tabulation, comparisons).
//!
//! With a scratch lobe of weight `w`, a fraction `w` of the surface is scratched:
//! `f = (1 - w) f_base + w F_base(wi . h) f_scratch`, where `F_base` is the base's specular
//! Fresnel term (the metal's, or the lacquer's for a paint). Each part keeps its directional
//! albedo within 1, and so does the mixture.
//!
//! Materials are read from and written to TOML (schema in `material_file.rs` and docs/book/src/materials.md).

use super::clearcoat::ClearCoat;
use super::conductor::RoughConductor;
use super::microfacet::{CosineColumns, IsotropicCosines, IsotropicRow};
use super::scratch::ScratchLobe;
use crate::brdf::{
    assert_pairs, eval_pairs_one_by_one, eval_phi_d_row_per_cell, Brdf, PhiDRow, Rgb,
};
use crate::geometry::HalfDiff;
use glam::DVec3;

/// The isotropic part of a material.
#[derive(Debug, Clone, PartialEq)]
pub enum Base {
    /// A polished metal.
    Conductor(RoughConductor),
    /// A lacquer over a pigmented base.
    ClearCoat(ClearCoat),
}

impl Base {
    /// f_r in 1/sr from the cosines of an isotropic configuration.
    pub fn eval_cosines(&self, c: IsotropicCosines) -> Rgb {
        match self {
            Base::Conductor(conductor) => conductor.eval_cosines(c),
            Base::ClearCoat(coat) => coat.eval_cosines(c),
        }
    }

    /// f_r in 1/sr along a row of constant theta_h and theta_d, at each of `cos_phi_d`.
    fn eval_row(&self, row: IsotropicRow, cos_phi_d: &[f64], out: &mut [Option<Rgb>]) {
        fn fill(cos_phi_d: &[f64], out: &mut [Option<Rgb>], f: impl Fn(f64) -> Rgb) {
            for (cos_phi_d, out) in cos_phi_d.iter().zip(out) {
                *out = Some(f(*cos_phi_d));
            }
        }
        match self {
            Base::Conductor(conductor) => fill(cos_phi_d, out, conductor.along_row(row)),
            Base::ClearCoat(coat) => fill(cos_phi_d, out, coat.along_row(row)),
        }
    }

    /// The Fresnel reflectance of the top surface at `cos_d = wi . h`.
    fn fresnel(&self, cos_d: f64) -> Rgb {
        match self {
            Base::Conductor(conductor) => conductor.fresnel(cos_d),
            Base::ClearCoat(coat) => Rgb::splat(coat.fresnel(cos_d)),
        }
    }
}

/// A named reference material (see the module documentation). Its serde form is the
/// material file's (`material_file` implements `Serialize` and `Deserialize` for it).
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// The material's name.
    pub name: String,
    /// The base: a rough conductor or a clear coat over a diffuse colour.
    pub base: Base,
    /// An optional anisotropic scratch lobe over the base.
    pub scratch: Option<ScratchLobe>,
}

impl Material {
    /// An isotropic material without scratches.
    pub fn new(name: impl Into<String>, base: Base) -> Self {
        Self {
            name: name.into(),
            base,
            scratch: None,
        }
    }

    /// The same material with a scratch lobe.
    pub fn with_scratch(self, scratch: ScratchLobe) -> Self {
        Self {
            scratch: Some(scratch),
            ..self
        }
    }

    /// The same material with its scratches along `orientation_deg` (paper 4.3): its own
    /// lobe turned, keeping weight and roughness, or the polishing scratches of paper Fig. 6
    /// ([`ScratchLobe::polishing`]) when it has none.
    pub fn with_scratch_orientation(self, orientation_deg: f64) -> Self {
        let lobe = match &self.scratch {
            Some(lobe) => lobe.turned(orientation_deg),
            None => ScratchLobe::polishing(orientation_deg),
        };
        self.with_scratch(lobe)
    }

    /// f_r in 1/sr for unit directions; zero at or below the horizon.
    pub fn eval_rgb(&self, wi: DVec3, wo: DVec3) -> Rgb {
        let Some(c) = IsotropicCosines::from_directions(wi, wo) else {
            return Rgb::ZERO;
        };
        let base = self.base.eval_cosines(c);
        match &self.scratch {
            None => base,
            Some(lobe) => {
                let scratched = self.base.fresnel(c.cos_d) * lobe.reflection(wi, wo);
                base * (1.0 - lobe.weight) + scratched * lobe.weight
            }
        }
    }
}

impl Brdf for Material {
    fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
        Some(self.eval_rgb(wi, wo))
    }

    /// Isotropic materials skip building the directions (tabulation's fast path); a scratch
    /// lobe needs them, for it depends on `phi_h`.
    fn eval_half_diff(&self, hd: HalfDiff) -> Option<Rgb> {
        if self.scratch.is_some() {
            let (wi, wo) = hd.to_directions();
            return Some(self.eval_rgb(wi, wo));
        }
        Some(IsotropicCosines::from_half_diff(hd).map_or(Rgb::ZERO, |c| self.base.eval_cosines(c)))
    }

    /// Isotropic materials compute their row factors once (tabulation's fast path); a
    /// scratch lobe depends on `phi_h`, so it is evaluated cell by cell.
    fn eval_phi_d_row(&self, row: &PhiDRow, out: &mut [Option<Rgb>]) {
        if self.scratch.is_some() {
            return eval_phi_d_row_per_cell(self, row, out);
        }
        let cosines = IsotropicRow::new(row.theta_h, row.theta_d);
        self.base.eval_row(cosines, row.cos_phi_d, out);
    }

    /// Without a scratch lobe the base's model is chosen once for the whole batch, and each
    /// pair goes straight from its directions to the cosines the model needs (a conductor
    /// then evaluates blocks of them together, [`RoughConductor::eval_columns`]); a scratch
    /// lobe is evaluated pair by pair.
    fn eval_pairs(&self, wi: &[DVec3], wo: &[DVec3], out: &mut [Option<Rgb>]) {
        match (&self.base, &self.scratch) {
            (Base::Conductor(conductor), None) => {
                assert_pairs(wi, wo, out);
                const CAPACITY: usize = CosineColumns::CAPACITY;
                let (mut columns, mut values) = (CosineColumns::default(), [Rgb::ZERO; CAPACITY]);
                let blocks = wi.chunks(CAPACITY).zip(wo.chunks(CAPACITY));
                for ((wi, wo), out) in blocks.zip(out.chunks_mut(CAPACITY)) {
                    columns.set_directions(wi, wo);
                    conductor.eval_columns(&columns, &mut values[..wi.len()]);
                    for (out, value) in out.iter_mut().zip(&values) {
                        *out = Some(*value);
                    }
                }
            }
            (Base::ClearCoat(coat), None) => {
                eval_isotropic_pairs(wi, wo, out, |c| coat.eval_cosines(c))
            }
            (_, Some(_)) => eval_pairs_one_by_one(self, wi, wo, out),
        }
    }

    fn name(&self) -> String {
        self.name.clone()
    }
}

/// An isotropic model `f` of the cosines at each direction pair, zero at or below the
/// horizon ([`Material::eval_rgb`] without a scratch lobe).
fn eval_isotropic_pairs(
    wi: &[DVec3],
    wo: &[DVec3],
    out: &mut [Option<Rgb>],
    f: impl Fn(IsotropicCosines) -> Rgb,
) {
    assert_pairs(wi, wo, out);
    for ((wi, wo), out) in wi.iter().zip(wo).zip(out) {
        *out = Some(IsotropicCosines::from_directions(*wi, *wo).map_or(Rgb::ZERO, &f));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::materials::microfacet::Distribution;
    use crate::materials::preset;

    #[test]
    fn a_scratch_orientation_turns_the_lobe_or_adds_the_polishing_one() {
        let plain = preset("silver-925")
            .unwrap()
            .with_scratch_orientation(135.0);
        assert_eq!(plain.scratch, Some(ScratchLobe::polishing(135.0)));
        let own = ScratchLobe::new(Distribution::Beckmann, 0.2, 0.01, 0.3, 10.0);
        let scratched = preset("silver-925")
            .unwrap()
            .with_scratch(own.clone())
            .with_scratch_orientation(-20.0);
        assert_eq!(scratched.scratch, Some(own.turned(-20.0)));
        assert_eq!(scratched.scratch.unwrap().orientation_deg, -20.0);
    }
}
