//! A measured sample: one BRDF value at one configuration of light and camera, held in
//! Rusinkiewicz's half-difference angles (radians), and the symmetry that folds it into the
//! quarter of the phi_d range that an isotropic, reciprocal BRDF needs (paper 5.3).

use specula_core::{HalfDiff, Rgb};
use std::f64::consts::{FRAC_PI_2, PI};

/// One measured BRDF value (1/sr per channel) at half-difference angles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// The sample's half-difference angles, rad.
    pub hd: HalfDiff,
    /// f_r per channel, 1/sr.
    pub value: Rgb,
}

impl Sample {
    /// A sample of `value` at `hd`.
    pub fn new(hd: HalfDiff, value: Rgb) -> Self {
        Self { hd, value }
    }
}

/// Folds phi_d (radians, any value) into `[0, pi/2]`.
///
/// Reciprocity gives `f(phi_d) = f(phi_d + pi)` and isotropy the mirror
/// `f(phi_d) = f(pi - phi_d)` (paper 5.3, DESIGN.md); together the BRDF is even about both
/// 0 and pi/2, so `[0, pi/2]` holds every distinct value.
pub fn fold_phi_d_rad(phi_d_rad: f64) -> f64 {
    let half_turn = phi_d_rad.rem_euclid(PI);
    if half_turn > FRAC_PI_2 {
        PI - half_turn
    } else {
        half_turn
    }
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
}
