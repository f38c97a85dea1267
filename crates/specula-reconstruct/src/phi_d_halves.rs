//! Reconstruction that keeps the two halves of phi_d apart (issue 20).
//!
//! The lattice ([`crate::lattice`]) folds phi_d into `[0, 90]` deg, assuming reciprocity
//! (`f(phi_d) = f(phi_d + 180)`) and the mirror symmetry of an isotropic surface
//! (`f(phi_d) = f(-phi_d)`); together they make a MERL cell at phi_d and its partner at
//! `180 - phi_d` equal. Real measurements need not be: a configuration at `180 - phi_d` is the
//! one at phi_d with light and camera swapped, and on the RGL files (Dupuy & Jakob 2018) the
//! two differ by up to ten times at grazing theta_d near the peak (satin_rosaline,
//! colodur_napoli_4f), where most of the folded reconstruction's error sits.
//!
//! When the samples measure both halves, phi_d in `[0, 90]` and in `[90, 180]` (after the
//! mirror fold `phi_d -> |phi_d|` into `[0, 180]`, which keeps light and camera apart), each
//! half is reconstructed from its own samples by the usual pipeline
//! ([`crate::reconstruct_through`]), the second half with phi_d mapped to `180 - phi_d`, and the
//! MERL cells of phi_d below 90 deg come from the first, the others from the second. The
//! samples at phi_d = 90 belong to both, so the halves meet on measured values. Samples of one
//! half only are reconstructed as before.
//!
//! At theta_h 0 the half vector is the normal, and turning the pair of directions about it
//! (phi_d) changes nothing on an isotropic surface: every phi_d of a theta_d names one
//! configuration, which a sequential design measures once, at phi_d 90 deg. Each half takes
//! such a sample at every phi_d plane its samples hold ([`normal_on_every_plane`]), and so do
//! the checks of a deblurred table ([`crate::safeguard`]): the lobe fit, the lattice and the
//! checks weigh the normal as they would if it were measured at every plane. Taken once, the
//! normal's sample let the lobe of a silicon nitride fit drift (0.54 to 0.83 times the
//! paper's way's error through the simulated device), and the checks, counting its misses
//! once, let a phenolic's overshooting peak stay (0.55 to 1.33).

use crate::lattice::at_the_normal;
use crate::prior::PriorBasis;
use crate::provenance::Provenance;
use crate::reconstruct::{reconstruct_cells, reconstruct_cells_over};
use crate::sample::mirror_fold_phi_d_rad;
use crate::{reconstruct_through, ReconstructError, Reconstruction, ResidualModel};
use specula_core::capture::CaptureResponse;
use specula_core::merl::{MerlBrdf, CELLS, PHI_D_BINS};
use specula_core::{HalfDiff, Rgb, Sample};
use std::collections::{BTreeMap, BTreeSet};
use std::f64::consts::{FRAC_PI_2, PI};

/// Angles closer than this (radians) to 90 deg belong to both halves.
const SEAM_TOLERANCE_RAD: f64 = 1e-6;

/// The samples of each half: `[0, 90]` deg as they are, `[90, 180]` deg with phi_d mapped
/// to `180 - phi_d`, each with its samples at the normal at every plane (see the module
/// documentation).
fn halves(samples: &[Sample]) -> [Vec<Sample>; 2] {
    let [first, second] = split(samples);
    [normal_on_every_plane(first), normal_on_every_plane(second)]
}

/// The key of an angle in radians for telling planes apart.
fn plane_key(rad: f64) -> i64 {
    (rad * 1e6).round() as i64
}

/// `samples` with each sample at the normal (theta_h 0) repeated at every other phi_d plane
/// they hold where its theta_d has none: at the normal every phi_d of a theta_d is one
/// configuration, so one sample there measures every plane, and the fit and the lattice take
/// it at each.
fn normal_on_every_plane(mut samples: Vec<Sample>) -> Vec<Sample> {
    let at_normal = |s: &Sample| at_the_normal(s.hd.theta_h.to_degrees());
    let planes: BTreeMap<i64, f64> = samples
        .iter()
        .map(|s| (plane_key(s.hd.phi_d), s.hd.phi_d))
        .collect();
    let mut held: BTreeSet<(i64, i64)> = samples
        .iter()
        .filter(|s| at_normal(s))
        .map(|s| (plane_key(s.hd.theta_d), plane_key(s.hd.phi_d)))
        .collect();
    let normal: Vec<Sample> = samples.iter().filter(|s| at_normal(s)).cloned().collect();
    for s in normal {
        for (&key, &phi_d) in &planes {
            if held.insert((plane_key(s.hd.theta_d), key)) {
                let hd = HalfDiff { phi_d, ..s.hd };
                samples.push(Sample { hd, ..s });
            }
        }
    }
    samples
}

/// The samples of each half of phi_d, the second mirrored onto the first.
fn split(samples: &[Sample]) -> [Vec<Sample>; 2] {
    let mut first = Vec::new();
    let mut second = Vec::new();
    for s in samples {
        let phi_d = mirror_fold_phi_d_rad(s.hd.phi_d);
        if phi_d <= FRAC_PI_2 + SEAM_TOLERANCE_RAD {
            first.push(Sample {
                hd: HalfDiff { phi_d, ..s.hd },
                ..*s
            });
        }
        if phi_d >= FRAC_PI_2 - SEAM_TOLERANCE_RAD {
            let hd = HalfDiff {
                phi_d: (PI - phi_d).max(0.0),
                ..s.hd
            };
            second.push(Sample { hd, ..*s });
        }
    }
    [first, second]
}

/// Whether each half of phi_d holds samples at two phi_d positions at least (one of them may
/// be the seam at 90 deg): then [`reconstruct_halves`] reconstructs the halves apart.
pub fn measures_both_halves(samples: &[Sample]) -> bool {
    split(samples).iter().all(|half| {
        let mut phi_d: Vec<f64> = half.iter().map(|s| s.hd.phi_d).collect();
        phi_d.sort_by(f64::total_cmp);
        phi_d.dedup_by(|a, b| (*a - *b).abs() < SEAM_TOLERANCE_RAD);
        phi_d.len() >= 2
    })
}

/// Reconstructs the table named `name` with each half of phi_d from its own samples when
/// they measure both ([`measures_both_halves`]; see the module documentation), otherwise as
/// [`reconstruct_through`]. The lobe, resolution and lattice figures reported are the first
/// half's; the node counts are the two halves' sums. A table deblurred through `response` is
/// checked against the samples and falls back where it fails ([`crate::safeguard`]).
/// `prior`: the basis of the `prior` method, as for [`reconstruct_through`].
pub fn reconstruct_halves<R: CaptureResponse + ?Sized>(
    samples: &[Sample],
    method: crate::Method,
    name: &str,
    response: Option<&R>,
    prior: Option<&PriorBasis>,
) -> Result<Reconstruction, ReconstructError> {
    let table = reconstruct_halves_with(samples, |half| {
        reconstruct_through(half, method, name, response, prior)
    })?;
    match response {
        Some(response) if table.resolution_deg.is_some() => {
            // The table made without the response: what the checks compare with, and
            // kept for the uncertainty's deblurring term.
            let plain = reconstruct_halves_with(samples, |half| {
                reconstruct_through(half, method, name, None::<&R>, prior)
            })?
            .brdf;
            // The checks take the normal's samples at every plane, as the halves do.
            let (brdf, safeguard, replaced) = crate::safeguard::safeguarded(
                &normal_on_every_plane(samples.to_vec()),
                table.brdf,
                table.lobe.as_ref(),
                response,
                &plain,
            );
            Ok(Reconstruction {
                brdf,
                safeguard: Some(safeguard),
                deblurred_replaced: replaced,
                undeblurred: Some(plain),
                ..table
            })
        }
        _ => Ok(table),
    }
}

/// As [`reconstruct_halves`], with `reconstruct_half` turning the samples of one half (or of
/// both, when they do not measure both halves) into a table: any reconstruction, e.g. the
/// `prior` method's ([`crate::prior_reconstruct`]).
pub fn reconstruct_halves_with<E>(
    samples: &[Sample],
    reconstruct_half: impl Fn(&[Sample]) -> Result<Reconstruction, E>,
) -> Result<Reconstruction, E> {
    if !measures_both_halves(samples) {
        return reconstruct_half(&normal_on_every_plane(samples.to_vec()));
    }
    let [first, second] = halves(samples);
    let first = reconstruct_half(&first)?;
    let second = reconstruct_half(&second)?;
    Ok(joined(first, second))
}

/// The cells `indices` of the table [`reconstruct_halves`] makes without a response, bit
/// for bit ([`reconstruct_cells`]): each from the half whose table [`joined`] takes it from.
/// With residual models (a deblurred table's, [`Reconstruction::residual_models`]), each
/// half's cells are made over its model instead of a lobe fitted to the samples
/// ([`reconstruct_cells_over`]; samples that do not measure both halves, over the first).
pub fn reconstruct_halves_cells(
    samples: &[Sample],
    method: crate::Method,
    indices: &[usize],
    prior: Option<&PriorBasis>,
    over: &[ResidualModel],
) -> Result<Vec<Option<Rgb>>, ReconstructError> {
    let cells = |half: &[Sample], indices: &[usize], model: Option<&ResidualModel>| {
        model.map_or_else(
            || reconstruct_cells(half, method, indices, prior),
            |model| reconstruct_cells_over(half, method, indices, model),
        )
    };
    if !measures_both_halves(samples) {
        return cells(
            &normal_on_every_plane(samples.to_vec()),
            indices,
            over.first(),
        );
    }
    let [first, second] = halves(samples);
    let (of_second, of_first): (Vec<usize>, Vec<usize>) =
        indices.iter().partition(|&&index| in_second(index));
    let mut first = cells(&first, &of_first, over.first())?.into_iter();
    let mut second = cells(&second, &of_second, over.get(1).or(over.first()))?.into_iter();
    Ok(indices
        .iter()
        .map(|&index| {
            let half = if in_second(index) {
                &mut second
            } else {
                &mut first
            };
            half.next().flatten()
        })
        .collect())
}

/// Whether MERL cell `index` lies in the second half of phi_d, `[90, 180)` deg.
pub(crate) fn in_second(index: usize) -> bool {
    index % PHI_D_BINS >= PHI_D_BINS / 2
}

/// The table whose cells of phi_d below 90 deg are `first`'s and the others `second`'s.
fn joined(first: Reconstruction, second: Reconstruction) -> Reconstruction {
    let brdf = MerlBrdf::from_fn(specula_core::Brdf::name(&first.brdf), |index| {
        if in_second(index) {
            second.brdf.cell(index)
        } else {
            first.brdf.cell(index)
        }
    });
    let cells = (0..CELLS)
        .map(|index| {
            if in_second(index) {
                second.provenance.cells[index]
            } else {
                first.provenance.cells[index]
            }
        })
        .collect();
    Reconstruction {
        brdf,
        provenance: Provenance { cells },
        lobe: first.lobe,
        resolution_deg: first.resolution_deg,
        lattice_shape: first.lattice_shape,
        measured_nodes: first.measured_nodes + second.measured_nodes,
        filled_nodes: first.filled_nodes + second.filled_nodes,
        safeguard: None,
        deblurred_replaced: None,
        undeblurred: None,
        residual_models: [first.residual_models, second.residual_models].concat(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Method;
    use specula_core::merl::Bin;
    use specula_core::Rgb;

    /// A sample at the normal measured at one phi_d stands at every other plane the samples
    /// hold, with its value; one off the normal does not, nor is a plane that has its own
    /// sample at the normal given a second.
    #[test]
    fn a_sample_at_the_normal_stands_at_every_phi_d_plane() {
        let at = |h: f64, d: f64, p: f64, v: f64| {
            Sample::new(HalfDiff::from_degrees(h, 0.0, d, p), Rgb::splat(v))
        };
        let samples = vec![
            at(0.0, 30.0, 90.0, 5.0),
            at(0.0, 50.0, 0.0, 7.0),
            at(0.0, 50.0, 90.0, 7.5),
            at(2.0, 30.0, 0.0, 1.0),
            at(2.0, 30.0, 60.0, 2.0),
        ];
        let all = normal_on_every_plane(samples.clone());
        let normal_at = |d: f64, p: f64| -> Vec<f64> {
            all.iter()
                .filter(|s| s.hd.theta_h == 0.0)
                .filter(|s| (s.hd.theta_d.to_degrees() - d).abs() < 1e-9)
                .filter(|s| (s.hd.phi_d.to_degrees() - p).abs() < 1e-9)
                .map(|s| s.value.x)
                .collect()
        };
        assert_eq!(normal_at(30.0, 0.0), vec![5.0]);
        assert_eq!(normal_at(30.0, 60.0), vec![5.0]);
        assert_eq!(normal_at(50.0, 60.0), vec![7.0]);
        assert_eq!(normal_at(50.0, 0.0), vec![7.0]);
        assert_eq!(normal_at(50.0, 90.0), vec![7.5]);
        // Three planes (0, 60, 90 deg) at two theta_d: six at the normal, two off it.
        assert_eq!(all.len(), 8);
    }

    /// A surface that is not reciprocal: f rises with cos(phi_d) from 1 to 3, so a
    /// configuration and its partner at 180 - phi_d differ, and f(phi_d) = f(-phi_d).
    fn tilted(hd: HalfDiff) -> Rgb {
        Rgb::splat(2.0 + hd.phi_d.cos())
    }

    fn samples(phi_d_deg: &[f64]) -> Vec<Sample> {
        let mut out = Vec::new();
        for h in [0.0, 5.0, 20.0, 40.0] {
            for d in [5.0, 25.0, 45.0, 65.0] {
                for &p in phi_d_deg {
                    let hd = HalfDiff::from_degrees(h, 45.0, d, p);
                    out.push(Sample::new(hd, tilted(hd)));
                }
            }
        }
        out
    }

    fn value_at(brdf: &MerlBrdf, phi_d_i: usize) -> f64 {
        let bin = Bin {
            theta_h_i: 20,
            theta_d_i: 30,
            phi_d_i,
        };
        brdf.cell(bin.index()).unwrap().x
    }

    #[test]
    fn both_halves_measured_keep_a_surface_that_is_not_reciprocal() {
        let both = samples(&[0.0, 45.0, 90.0, 135.0, 180.0]);
        assert!(measures_both_halves(&both));
        let r = reconstruct_halves(
            &both,
            Method::Linear,
            "t",
            None::<&dyn CaptureResponse>,
            None,
        )
        .unwrap();
        // Linear between the nodes of each half: cos(phi_d) interpolated at 22.5 and 157.5
        // deg (bins 22 and 157 hold 22.5 and 157.5).
        let expect = |p0: f64, p1: f64, p: f64| {
            let t = (p - p0) / (p1 - p0);
            2.0 + (1.0 - t) * p0.to_radians().cos() + t * p1.to_radians().cos()
        };
        assert!((value_at(&r.brdf, 22) - expect(0.0, 45.0, 22.5)).abs() < 1e-9);
        assert!((value_at(&r.brdf, 157) - expect(135.0, 180.0, 157.5)).abs() < 1e-9);
        // Folded, the two halves are averaged into one value, 2 at both.
        let folded = crate::reconstruct(&both, Method::Linear, "f").unwrap();
        assert!((value_at(&folded.brdf, 22) - value_at(&folded.brdf, 157)).abs() < 1e-12);
        assert!((value_at(&folded.brdf, 22) - 2.0).abs() < 1e-9);
        // The cells beside the seam come from measured nodes on both sides.
        let seam = [89, 90].map(|k| value_at(&r.brdf, k));
        assert!((seam[0] - seam[1]).abs() < 0.05, "{seam:?}");
    }

    #[test]
    fn the_sidecar_marks_measured_only_the_bins_of_each_half_that_hold_a_sample() {
        // The first half at 0, 45, 90 deg, the second at 90, 120, 180: phi_d 120 is
        // measured, its fold partner 60 is not; 45 is, its partner 135 is not. The fold
        // marks both partners.
        let both = samples(&[0.0, 45.0, 90.0, 120.0, 180.0]);
        assert!(measures_both_halves(&both));
        let r = reconstruct_halves(&both, Method::Lobe, "t", None::<&dyn CaptureResponse>, None)
            .unwrap();
        let folded = crate::reconstruct(&both, Method::Lobe, "f").unwrap();
        let at =
            |phi_d_deg: f64| Bin::of(HalfDiff::from_degrees(20.0, 45.0, 25.0, phi_d_deg)).index();
        use crate::provenance::CellOrigin::Measured;
        for (phi_d_deg, measured) in [(45.0, true), (135.0, false), (120.0, true), (60.0, false)] {
            assert_eq!(
                r.provenance.cells[at(phi_d_deg)] == Measured,
                measured,
                "{phi_d_deg}"
            );
            assert_eq!(
                folded.provenance.cells[at(phi_d_deg)],
                Measured,
                "{phi_d_deg}"
            );
        }
        // Per (theta_h, theta_d) of the samples: the bins 0 (which 180 shares), 45, 90 and
        // 120 measured apart; folded, 60 and 135 as well.
        assert_eq!(r.provenance.counts().0, 16 * 4);
        assert_eq!(folded.provenance.counts().0, 16 * 6);
    }

    #[test]
    fn one_half_measured_is_reconstructed_as_before() {
        let quarter = samples(&[0.0, 45.0, 90.0]);
        assert!(!measures_both_halves(&quarter));
        let a = reconstruct_halves(
            &quarter,
            Method::Lobe,
            "a",
            None::<&dyn CaptureResponse>,
            None,
        )
        .unwrap();
        let b = crate::reconstruct(&quarter, Method::Lobe, "b").unwrap();
        assert!((0..CELLS).all(|i| a.brdf.cell(i) == b.brdf.cell(i)));
        assert_eq!(a.provenance, b.provenance);
    }

    /// A glossy peak over a surface that is not reciprocal, sampled on a lattice with holes
    /// (so that nodes are extrapolated) in both halves of phi_d or in one.
    fn peaked_with_holes(phi_d_deg: &[f64]) -> Vec<Sample> {
        let mut out = Vec::new();
        for h in [0.0, 0.4, 1.5, 4.0, 12.0, 30.0, 60.0] {
            for d in [2.0, 20.0, 41.0, 63.0, 79.0] {
                for &p in phi_d_deg {
                    if h > 20.0 && d > 70.0 {
                        continue;
                    }
                    let hd = HalfDiff::from_degrees(h, 45.0, d, p);
                    let peak = (-(h / 2.5) * (h / 2.5)).exp() * (1.0 + d / 40.0);
                    out.push(Sample::new(
                        hd,
                        tilted(hd) * 0.1 + Rgb::new(9.0, 6.0, 3.0) * peak,
                    ));
                }
            }
        }
        out
    }

    #[test]
    fn a_few_cells_are_the_table_s_bit_for_bit() {
        let cells: Vec<usize> = (0..CELLS).step_by(89).collect();
        for phi_d_deg in [&[0.0, 30.0, 90.0, 150.0, 180.0][..], &[0.0, 40.0, 90.0][..]] {
            let samples = peaked_with_holes(phi_d_deg);
            for method in [Method::Linear, Method::Log, Method::Lobe] {
                let none = None::<&dyn CaptureResponse>;
                let table = reconstruct_halves(&samples, method, "t", none, None).unwrap();
                assert!(table.filled_nodes > 0);
                let read = reconstruct_halves_cells(&samples, method, &cells, None, &[]).unwrap();
                for (&index, value) in cells.iter().zip(&read) {
                    let expected = table.brdf.cell(index);
                    let same = match (expected, value) {
                        (Some(e), Some(v)) => (0..3).all(|c| e[c].to_bits() == v[c].to_bits()),
                        (e, v) => e.is_none() && v.is_none(),
                    };
                    assert!(same, "{method:?} cell {index}: {expected:?} read {value:?}");
                }
            }
        }
    }
}
