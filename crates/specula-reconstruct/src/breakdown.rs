//! Where a reconstruction's error sits (issue 20): the squared error of the cosine-weighted
//! relative RMSE ([`specula_core::compare`], `w^2 |a - b|^2` with `w = cos_i cos_o` at the
//! bin centre, phi_h 0) over the cells within the elevation limit, split by region of the
//! MERL grid. Each partition's shares add up to 1; a region's own relative RMSE is
//! `sqrt(sum w^2 |a - b|^2 / sum w^2 |b|^2)` over its cells.
//!
//! Partitions ([`Partition`]): the cells' origin in the reconstruction (reached by the
//! samples, measured or interpolated, vs extrapolated beyond them, [`crate::provenance`]),
//! theta_d bands, theta_h bands (the specular peak vs off-peak) and phi_d bands (folded into
//! `[0, 90]` deg by reciprocity and isotropy, [`crate::sample::fold_phi_d_rad`]) and the two
//! halves of the MERL phi_d range, which a folded reconstruction makes equal.

use crate::provenance::Provenance;
use crate::sample::fold_phi_d_rad;
use specula_core::merl::{theta_h_centre_deg, Bin, MerlBrdf, CELLS, PHI_D_BINS};

/// A way to split the MERL cells into regions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Partition {
    /// Reached (measured or interpolated) vs extrapolated, by the reconstruction's provenance.
    Origin,
    /// theta_d bands, [`THETA_D_BANDS_DEG`].
    ThetaD,
    /// theta_h bands, [`THETA_H_BANDS_DEG`].
    ThetaH,
    /// Folded phi_d bands, [`PHI_D_BANDS_DEG`].
    PhiD,
    /// The halves of the MERL phi_d range, below and above 90 deg: a configuration and its
    /// light/camera swap, equal for a reciprocal BRDF ([`crate::phi_d_halves`]).
    PhiDHalf,
}

/// Lower edges (degrees) of the theta_d bands of [`Partition::ThetaD`]: retro-reflection
/// (the device keeps light and camera apart), mid, towards grazing, grazing.
pub const THETA_D_BANDS_DEG: [f64; 5] = [0.0, 5.0, 30.0, 60.0, 75.0];
/// Lower edges (degrees) of the theta_h bands of [`Partition::ThetaH`]: the peak, its
/// shoulder, the near tail, the far tail.
pub const THETA_H_BANDS_DEG: [f64; 4] = [0.0, 2.0, 8.0, 25.0];
/// Lower edges (degrees) of the folded phi_d bands of [`Partition::PhiD`].
pub const PHI_D_BANDS_DEG: [f64; 3] = [0.0, 30.0, 60.0];

impl Partition {
    /// Every partition, in the order a report lists them.
    pub const ALL: [Partition; 5] = [
        Partition::Origin,
        Partition::ThetaD,
        Partition::ThetaH,
        Partition::PhiD,
        Partition::PhiDHalf,
    ];

    /// The regions' names, in region order.
    pub fn region_names(self) -> Vec<String> {
        let bands = |axis: &str, edges: &[f64]| -> Vec<String> {
            edges
                .iter()
                .enumerate()
                .map(|(i, lo)| {
                    let hi = edges.get(i + 1).copied().unwrap_or(90.0);
                    format!("{axis} {lo}-{hi}")
                })
                .collect()
        };
        match self {
            Partition::Origin => vec!["reached".into(), "extrapolated".into()],
            Partition::ThetaD => bands("theta_d", &THETA_D_BANDS_DEG),
            Partition::ThetaH => bands("theta_h", &THETA_H_BANDS_DEG),
            Partition::PhiD => bands("phi_d", &PHI_D_BANDS_DEG),
            Partition::PhiDHalf => vec!["phi_d half 0-90".into(), "phi_d half 90-180".into()],
        }
    }

    /// The region of cell `index`.
    fn region(self, index: usize, provenance: &Provenance) -> usize {
        let bin = Bin::from_index(index);
        let band =
            |edges: &[f64], value: f64| edges.iter().rposition(|&lo| value >= lo).unwrap_or(0);
        match self {
            Partition::Origin => usize::from(provenance.cells[index].is_extrapolated()),
            Partition::ThetaD => band(&THETA_D_BANDS_DEG, bin.theta_d_i as f64 + 0.5),
            Partition::ThetaH => band(&THETA_H_BANDS_DEG, theta_h_centre_deg(bin.theta_h_i)),
            Partition::PhiD => band(
                &PHI_D_BANDS_DEG,
                fold_phi_d_rad((bin.phi_d_i as f64 + 0.5).to_radians()).to_degrees(),
            ),
            Partition::PhiDHalf => usize::from(bin.phi_d_i >= PHI_D_BINS / 2),
        }
    }
}

/// One region's part of the error.
#[derive(Debug, Clone, PartialEq)]
pub struct RegionError {
    /// The region, as [`Partition::region_names`] names it.
    pub name: String,
    /// Cells within the elevation limit in the region.
    pub cells: usize,
    /// The region's share of the squared error of the whole (0 to 1).
    pub share: f64,
    /// The region's own cosine-weighted relative RMSE.
    pub relative_rmse: f64,
}

/// The error of `reconstructed` against `truth` split by each region of `partition`, over
/// the cells whose light and camera are within `max_elevation_deg` (see the module
/// documentation). `provenance` is the reconstruction's (used by [`Partition::Origin`]).
pub fn error_by_region(
    reconstructed: &MerlBrdf,
    truth: &MerlBrdf,
    provenance: &Provenance,
    max_elevation_deg: f64,
    partition: Partition,
) -> Vec<RegionError> {
    let names = partition.region_names();
    let mut cells = vec![0usize; names.len()];
    let mut diff = vec![0.0; names.len()];
    let mut reference = vec![0.0; names.len()];
    let min_cos = max_elevation_deg.to_radians().cos().max(1e-12);
    for index in 0..CELLS {
        let (Some(a), Some(b)) = (reconstructed.cell(index), truth.cell(index)) else {
            continue;
        };
        let (wi, wo) = Bin::from_index(index).centre(0.0).to_directions();
        if wi.z < min_cos || wo.z < min_cos {
            continue;
        }
        let w2 = (wi.z * wo.z).powi(2);
        let r = partition.region(index, provenance);
        cells[r] += 1;
        diff[r] += w2 * (a - b).length_squared();
        reference[r] += w2 * b.length_squared();
    }
    let total: f64 = diff.iter().sum();
    names
        .into_iter()
        .enumerate()
        .map(|(r, name)| RegionError {
            name,
            cells: cells[r],
            share: if total > 0.0 { diff[r] / total } else { 0.0 },
            relative_rmse: if reference[r] > 0.0 {
                (diff[r] / reference[r]).sqrt()
            } else {
                0.0
            },
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::provenance::CellOrigin;
    use specula_core::compare::compare;
    use specula_core::Rgb;

    fn table(value: impl Fn(Bin) -> f64 + Sync) -> MerlBrdf {
        MerlBrdf::from_fn("t", |i| Some(Rgb::splat(value(Bin::from_index(i)))))
    }

    #[test]
    fn shares_add_up_and_the_whole_is_the_compare_figure() {
        let truth = table(|b| 0.2 + 0.01 * b.theta_h_i as f64);
        let wrong =
            table(|b| 0.2 + 0.01 * b.theta_h_i as f64 + if b.theta_d_i < 5 { 0.3 } else { 0.01 });
        let provenance = Provenance {
            cells: vec![CellOrigin::Interpolated; CELLS],
        };
        let whole = compare(&wrong, &truth, 75.0).relative_rmse;
        for partition in Partition::ALL {
            let regions = error_by_region(&wrong, &truth, &provenance, 75.0, partition);
            let share: f64 = regions.iter().map(|r| r.share).sum();
            assert!((share - 1.0).abs() < 1e-9, "{partition:?}: {share}");
            let cells: usize = regions.iter().map(|r| r.cells).sum();
            assert_eq!(cells, compare(&wrong, &truth, 75.0).cells);
            // The regions' own figures recombine into compare's: each region's reference sum
            // is its share of the squared error over its relative RMSE squared.
            let reference: f64 = regions
                .iter()
                .filter(|r| r.share > 0.0)
                .map(|r| r.share / r.relative_rmse.powi(2))
                .sum();
            let recombined = reference.recip().sqrt();
            assert!(
                (recombined / whole - 1.0).abs() < 1e-9,
                "{recombined} vs {whole}"
            );
        }
        let theta_d = error_by_region(&wrong, &truth, &provenance, 75.0, Partition::ThetaD);
        // theta_d < 5 holds the large error: its share is far above its share of cells.
        let cells: usize = theta_d.iter().map(|r| r.cells).sum();
        assert!(theta_d[0].share > 5.0 * theta_d[0].cells as f64 / cells as f64);
        let halves = error_by_region(&wrong, &truth, &provenance, 75.0, Partition::PhiDHalf);
        assert_eq!(halves[0].cells, halves[1].cells);
        let origin = error_by_region(&wrong, &truth, &provenance, 75.0, Partition::Origin);
        assert_eq!((origin[0].share, origin[1].cells), (1.0, 0));
    }
}
