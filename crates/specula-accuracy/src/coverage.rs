//! Whether a table's stated uncertainty covers its error, where the truth is known (the
//! simulator): the share of cells within `max_elevation_deg` whose truth lies within two
//! standard uncertainties (k = 2) of the reconstructed value, over the cells measured and
//! interpolated (the extrapolated ones are left out: their uncertainty only says "large").

use specula_core::merl::{Bin, MerlBrdf, CELLS};
use specula_reconstruct::provenance::{CellOrigin, Provenance};

/// Coverage figures of one set of cells.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Coverage {
    /// Values compared (cells times channels).
    pub values: usize,
    /// Values whose truth lies within `2 u` of the reconstruction.
    pub covered: usize,
    /// Values whose error exceeds `2 u` with the reconstruction above the truth.
    pub above: usize,
}

impl Coverage {
    /// The share covered, `None` with no value.
    pub fn fraction(&self) -> Option<f64> {
        (self.values > 0).then(|| self.covered as f64 / self.values as f64)
    }

    fn count(&mut self, value: f64, u: f64, truth: f64) {
        self.values += 1;
        if (value - truth).abs() <= 2.0 * u {
            self.covered += 1;
        } else if value > truth {
            self.above += 1;
        }
    }
}

/// Coverage of the measured cells, the interpolated ones and both together.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CellCoverage {
    /// Cells a sample lies in.
    pub measured: Coverage,
    /// Cells interpolated between measured lattice nodes.
    pub interpolated: Coverage,
    /// Both.
    pub both: Coverage,
}

/// The coverage of `table` with its standard `uncertainty` (1/sr, negative where none) and
/// `provenance` against `truth` (tabulated on the same grid), over the cells with light and
/// camera within `max_elevation_deg` ([`crate::within_elevation`]); a cell without an
/// uncertainty or a truth is left out.
pub fn cell_coverage(
    table: &MerlBrdf,
    uncertainty: &MerlBrdf,
    provenance: &Provenance,
    truth: &MerlBrdf,
    max_elevation_deg: f64,
) -> CellCoverage {
    let mut coverage = CellCoverage::default();
    for index in 0..CELLS {
        let origin = provenance.cells[index];
        if origin.is_extrapolated()
            || !crate::within_elevation(Bin::from_index(index).centre(0.0), max_elevation_deg)
        {
            continue;
        }
        let (Some(v), Some(u), Some(t)) = (
            table.cell(index),
            uncertainty.cell(index),
            truth.cell(index),
        ) else {
            continue;
        };
        for c in 0..3 {
            if !(v[c].is_finite() && u[c].is_finite() && t[c].is_finite()) {
                continue;
            }
            coverage.both.count(v[c], u[c], t[c]);
            let set = if origin == CellOrigin::Measured {
                &mut coverage.measured
            } else {
                &mut coverage.interpolated
            };
            set.count(v[c], u[c], t[c]);
        }
    }
    coverage
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::Rgb;

    #[test]
    fn a_value_counts_as_covered_within_two_uncertainties_of_the_truth() {
        let table = MerlBrdf::from_fn("t", |_| Some(Rgb::splat(1.0)));
        let truth = MerlBrdf::from_fn("truth", |i| {
            Some(Rgb::splat(if i % 2 == 0 { 1.15 } else { 0.7 }))
        });
        let u = MerlBrdf::from_fn("u", |_| Some(Rgb::splat(0.1)));
        let provenance = Provenance {
            cells: (0..CELLS)
                .map(|i| {
                    if i % 3 == 0 {
                        CellOrigin::Measured
                    } else {
                        CellOrigin::Interpolated
                    }
                })
                .collect(),
        };
        let c = cell_coverage(&table, &u, &provenance, &truth, 75.0);
        // Even cells are 0.15 off (within 0.2), odd ones 0.3 off with the table above.
        let both = c.both;
        assert!(both.values > 0);
        assert!((both.fraction().unwrap() - 0.5).abs() < 0.01, "{both:?}");
        assert_eq!(both.above, both.values - both.covered);
        assert_eq!(c.measured.values + c.interpolated.values, both.values);
        // Extrapolated cells are left out.
        let extrapolated = Provenance {
            cells: vec![CellOrigin::Extrapolated; CELLS],
        };
        assert_eq!(
            cell_coverage(&table, &u, &extrapolated, &truth, 75.0)
                .both
                .values,
            0
        );
    }
}
