//! The symmetries that fold a measured sample's phi_d ([`specula_core::Sample`]): the mirror
//! of an isotropic BRDF alone, into `[0, pi]`, and with reciprocity, into the quarter of the
//! phi_d range that an isotropic, reciprocal BRDF needs (paper 5.3); and how far from the
//! normal the samples reach.

use specula_core::geometry::elevation_deg;
use specula_core::Sample;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// Folds phi_d (radians, any value) into `[0, pi/2]`.
///
/// Reciprocity gives `f(phi_d) = f(phi_d + pi)` and isotropy the mirror
/// `f(phi_d) = f(pi - phi_d)` (paper 5.3, docs/book/src/design.md); together the BRDF is even about both
/// 0 and pi/2, so `[0, pi/2]` holds every distinct value.
pub(crate) fn fold_phi_d_rad(phi_d_rad: f64) -> f64 {
    let half_turn = phi_d_rad.rem_euclid(PI);
    if half_turn > FRAC_PI_2 {
        PI - half_turn
    } else {
        half_turn
    }
}

/// phi_d folded into `[0, pi]` by the mirror symmetry alone (`f(phi_d) = f(-phi_d)`).
pub(crate) fn mirror_fold_phi_d_rad(phi_d_rad: f64) -> f64 {
    let turn = phi_d_rad.rem_euclid(TAU);
    if turn > PI {
        TAU - turn
    } else {
        turn
    }
}

/// The samples' reach: the largest elevation of light or camera among `samples` (degrees).
pub(crate) fn reach_deg(samples: &[Sample]) -> f64 {
    samples
        .iter()
        .map(|s| elevation_deg(s.hd))
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folding_applies_reciprocity_and_the_mirror() {
        let deg = |d: f64| fold_phi_d_rad(d.to_radians()).to_degrees();
        for (input, folded) in [
            (0.0, 0.0),
            (15.0, 15.0),
            (90.0, 90.0),
            (165.0, 15.0),
            (195.0, 15.0),
            (345.0, 15.0),
            (-15.0, 15.0),
            (270.0, 90.0),
        ] {
            assert!(
                (deg(input) - folded).abs() < 1e-9,
                "{input} -> {}",
                deg(input)
            );
        }
    }

    #[test]
    fn the_mirror_fold_keeps_the_half_turn() {
        let deg = |v: f64| mirror_fold_phi_d_rad(v.to_radians()).to_degrees();
        assert!((deg(135.0) - 135.0).abs() < 1e-9);
        assert!((deg(-135.0) - 135.0).abs() < 1e-9);
        assert!((deg(200.0) - 160.0).abs() < 1e-9);
        assert!((deg(360.0)).abs() < 1e-9);
    }
}
