//! The forward model of one capture as quadrature: a capture does not see one pair of
//! directions but integrates the BRDF over small spreads of the light's and the camera's
//! directions,
//!
//! ```text
//! m(wi, wo) = E[ f(wi', wo') cos(theta_i') ] / cos(theta_i)
//! ```
//!
//! (Ferrero et al., "Deconvolution of non-zero solid angles effect in BSDF measurements",
//! Proc. SPIE 8083, 2011). The expectation is a mean over equal-weight [`CaptureNode`]s, the
//! offsets of `wi` and `wo` in the planes orthogonal to them. Where the nodes come from (the
//! light's disk, the camera's pupil, the measured area) is the instrument's business
//! (`specula_acquisition::response::InstrumentResponse` implements [`CaptureResponse`]);
//! this module holds what the simulator, the calibration and the reconstruction share: the
//! node type and the integral over nodes.

use crate::{Brdf, Rgb};
use glam::{DVec2, DVec3};

/// One quadrature node of a capture: the offsets of the light's and the camera's directions,
/// radians, in the planes orthogonal to them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CaptureNode {
    /// Offset of the light's direction (radians, tangent plane of `wi`).
    pub light: DVec2,
    /// Offset of the camera's direction (radians, tangent plane of `wo`).
    pub camera: DVec2,
}

/// An instrument's response seen as quadrature: what the reconstruction needs to fit a
/// lobe through the blur of a capture (`specula_acquisition::response::InstrumentResponse`
/// implements it).
pub trait CaptureResponse {
    /// `count` equal-weight nodes (at least 1) of a capture.
    fn capture_nodes(&self, count: usize) -> Vec<CaptureNode>;
    /// True when a capture sees exactly one pair of directions (no blur).
    fn is_point(&self) -> bool;
    /// The resolution in theta_h, degrees: the width below which a peak is a bound, not a
    /// measurement.
    fn resolution_deg(&self) -> f64;
}

/// The mean of `g(wi', wo')` over the pairs of directions `nodes` make of the nominal
/// `wi`, `wo` (unit): the light's and the camera's offsets in the planes orthogonal to
/// them.
pub fn integrate(
    nodes: &[CaptureNode],
    wi: DVec3,
    wo: DVec3,
    mut g: impl FnMut(DVec3, DVec3) -> Rgb,
) -> Rgb {
    let (li, lj) = orthonormal_basis(wi);
    let (ci, cj) = orthonormal_basis(wo);
    let sum: Rgb = nodes
        .iter()
        .map(|node| {
            let wi2 = (wi + node.light.x * li + node.light.y * lj).normalize();
            let wo2 = (wo + node.camera.x * ci + node.camera.y * cj).normalize();
            g(wi2, wo2)
        })
        .sum();
    sum / nodes.len() as f64
}

/// What a capture at the nominal directions `wi`, `wo` (unit, sample frame) measures of
/// `f`, integrated over `nodes`: `mean f(wi', wo') cos theta_i' / cos theta_i`, zero where
/// a direction is below the surface.
pub fn measure(
    nodes: &[CaptureNode],
    wi: DVec3,
    wo: DVec3,
    mut f: impl FnMut(DVec3, DVec3) -> Rgb,
) -> Rgb {
    if wi.z <= 0.0 {
        return Rgb::ZERO;
    }
    integrate(nodes, wi, wo, |a, b| {
        if a.z <= 0.0 || b.z <= 0.0 {
            Rgb::ZERO
        } else {
            f(a, b) * a.z
        }
    }) / wi.z
}

/// What a capture measures of a BRDF at `wi`, `wo` over `nodes` ([`measure`]).
pub fn measure_brdf(nodes: &[CaptureNode], brdf: &dyn Brdf, wi: DVec3, wo: DVec3) -> Rgb {
    measure(nodes, wi, wo, |a, b| brdf.eval(a, b).unwrap_or(Rgb::ZERO))
}

/// Two unit vectors orthogonal to `n` and to each other.
pub fn orthonormal_basis(n: DVec3) -> (DVec3, DVec3) {
    let helper = if n.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    let u = n.cross(helper).normalize();
    (u, n.cross(u))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_basis_is_orthonormal() {
        for n in [DVec3::Z, DVec3::X, DVec3::new(0.3, -0.5, 0.8).normalize()] {
            let (u, v) = orthonormal_basis(n);
            for (a, b) in [(u, v), (u, n), (v, n)] {
                assert!(a.dot(b).abs() < 1e-15);
            }
            assert!((u.length() - 1.0).abs() < 1e-15 && (v.length() - 1.0).abs() < 1e-15);
        }
    }

    #[test]
    fn one_centred_node_measures_the_nominal_value() {
        let node = [CaptureNode {
            light: DVec2::ZERO,
            camera: DVec2::ZERO,
        }];
        let wi = DVec3::new(0.5, 0.1, 0.8).normalize();
        let wo = DVec3::new(-0.3, 0.2, 0.9).normalize();
        let m = measure(&node, wi, wo, |a, b| Rgb::splat(a.dot(b)));
        assert!((m.x - wi.dot(wo)).abs() < 1e-15);
        assert_eq!(measure(&node, -wi, wo, |_, _| Rgb::ONE), Rgb::ZERO);
    }
}
