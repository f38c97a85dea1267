//! The characteristic slice of section 5.1: the BRDF at `phi_d = 90` degrees over theta_h x
//! theta_d, "the most descriptive information on the BRDF" (paper 5.1), held as the mean of
//! R, G and B in 1/sr.
//!
//! It has 90 columns, one per whole degree of theta_d (0 to 89), and the same theta_h nodes
//! in every column:
//! - from an analytic BRDF ([`CharacteristicSlice::of`]): square-root positions,
//!   `theta_h = t^2 / 90` with `t` evenly spaced over `[0, 90]` (90 nodes, the probe's, by
//!   default; [`DENSE_NODES`] = 3 x 89 + 1 to judge placements against a finer truth that
//!   still contains the probe's nodes), at `theta_d = j` degrees exactly, `phi_h = 45`;
//! - from a MERL table ([`crate::merl_slice`]): 90 nodes, the cells `(i, j, phi_d bin 90)`,
//!   each theta_h at its bin centre `(i + 0.5)^2 / 90` degrees (docs/book/src/design.md); column `j` is
//!   theta_d bin `j`, i.e. `[j, j + 1)` degrees.

use crate::column::{scalar_of, Column, Interpolation};
use specula_core::sampling::SamplingFunction;
use specula_core::{Brdf, GridSpec, HalfDiff, ProbeSpec};

/// Number of theta_d columns (whole degrees 0 to 89).
pub const THETA_D_COLUMNS: usize = 90;
/// Number of theta_h nodes per column of a MERL slice, and of the probe (paper 5.2).
pub const THETA_H_NODES: usize = 90;
/// Nodes of a dense slice: every third is a probe node (`t = 90 k / 89`).
pub const DENSE_NODES: usize = 3 * (THETA_H_NODES - 1) + 1;
/// phi_d of the characteristic slice, degrees.
pub const SLICE_PHI_D_DEG: f64 = 90.0;
/// phi_h at which an analytic BRDF is evaluated (the paper's choice for its samples).
pub const SLICE_PHI_H_DEG: f64 = GridSpec::paper().phi_h_deg;
/// The theta_d column of the paper's probe (section 5.2): its theta_d in whole degrees.
pub const PROBE_THETA_D_DEG: usize = ProbeSpec::paper().theta_d_deg as usize;

/// The characteristic slice of one material (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct CharacteristicSlice {
    name: String,
    theta_h_deg: Vec<f64>,
    /// `values[j * nodes + i]`: column j, node i; `None` where not measured.
    values: Vec<Option<f64>>,
}

impl CharacteristicSlice {
    /// A slice from its theta_h nodes (increasing degrees) and values in column-major order
    /// (`values[j * nodes + i]` for theta_d column `j`, theta_h node `i`).
    pub fn from_grid(
        name: impl Into<String>,
        theta_h_deg: Vec<f64>,
        values: Vec<Option<f64>>,
    ) -> Self {
        assert!(theta_h_deg.len() >= 2);
        assert_eq!(values.len(), theta_h_deg.len() * THETA_D_COLUMNS);
        Self {
            name: name.into(),
            theta_h_deg,
            values,
        }
    }

    /// Evaluates an analytic (or any) BRDF on `nodes >= 2` square-root-spaced theta_h nodes
    /// per column.
    pub fn of(brdf: &dyn Brdf, nodes: usize) -> Self {
        let theta_h_deg = SamplingFunction::square_root().positions_deg(nodes);
        let values = (0..THETA_D_COLUMNS)
            .flat_map(|j| theta_h_deg.iter().map(move |&x| (j, x)))
            .map(|(j, x)| {
                let hd = HalfDiff::from_degrees(x, SLICE_PHI_H_DEG, j as f64, SLICE_PHI_D_DEG);
                brdf.eval_half_diff(hd).map(scalar_of)
            })
            .collect();
        Self::from_grid(brdf.name(), theta_h_deg, values)
    }

    /// The name of the BRDF the slice was taken from.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The theta_h nodes shared by every column, deg.
    pub fn theta_h_deg(&self) -> &[f64] {
        &self.theta_h_deg
    }

    /// Number of theta_h nodes per column.
    pub fn nodes(&self) -> usize {
        self.theta_h_deg.len()
    }

    /// The value at theta_d column `j`, theta_h node `i`.
    pub fn value(&self, j: usize, i: usize) -> Option<f64> {
        self.values[j * self.nodes() + i]
    }

    /// Column `j` (theta_d = j degrees), without its missing cells; `None` when fewer than two
    /// cells were measured.
    pub fn column(&self, j: usize) -> Option<Column> {
        let n = self.nodes();
        Column::from_partial(&self.theta_h_deg, &self.values[j * n..(j + 1) * n])
    }

    /// The probe of section 5.2 as this slice holds it: the column at theta_d = 40 degrees at
    /// the probe's 90 square-root positions when the slice's nodes include them (a slice of
    /// `89 m + 1` square-root nodes, as [`CharacteristicSlice::of`] makes), else the whole
    /// column (a MERL slice: its 90 bins).
    pub fn probe(&self) -> Option<Column> {
        let n = self.nodes();
        let stride = (n - 1) / (THETA_H_NODES - 1);
        let values = &self.values[PROBE_THETA_D_DEG * n..(PROBE_THETA_D_DEG + 1) * n];
        let probe_nodes = SamplingFunction::square_root().positions_deg(THETA_H_NODES);
        let includes_probe = stride >= 1
            && (n - 1).is_multiple_of(THETA_H_NODES - 1)
            && probe_nodes
                .iter()
                .enumerate()
                .all(|(k, x)| (self.theta_h_deg[k * stride] - x).abs() < 1e-9);
        if !includes_probe {
            return Column::from_partial(&self.theta_h_deg, values);
        }
        let picked: Vec<Option<f64>> = (0..THETA_H_NODES).map(|k| values[k * stride]).collect();
        Column::from_partial(&probe_nodes, &picked)
    }

    /// All 90 columns (see [`CharacteristicSlice::column`]).
    pub fn columns(&self) -> Vec<Option<Column>> {
        (0..THETA_D_COLUMNS).map(|j| self.column(j)).collect()
    }

    /// The error of sampling every column of the slice at the same theta_h positions
    /// (increasing, degrees) and interpolating back in `domain`: the mean absolute
    /// difference over all measured cells, 1/sr (paper 5.1).
    pub fn error(&self, positions_deg: &[f64], domain: Interpolation) -> f64 {
        mean_over_cells(&self.columns(), |c| {
            c.reinterpolation_error(positions_deg, domain)
        })
    }
}

/// The mean over all cells of per-column mean errors: each column weighs by its cell count.
/// NaN when no column exists.
pub fn mean_over_cells(columns: &[Option<Column>], error: impl Fn(&Column) -> f64) -> f64 {
    let (sum, cells) = columns.iter().flatten().fold((0.0, 0usize), |(s, n), c| {
        (s + error(c) * c.len() as f64, n + c.len())
    });
    sum / cells as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;
    use specula_core::Rgb;

    /// f = theta_h_deg + 100 theta_d_deg (grey), known everywhere.
    struct Plane;
    impl Brdf for Plane {
        fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
            let hd = HalfDiff::from_directions(wi, wo);
            Some(Rgb::splat(
                hd.theta_h.to_degrees() + 100.0 * hd.theta_d.to_degrees(),
            ))
        }
        fn name(&self) -> String {
            "plane".into()
        }
    }

    #[test]
    fn of_evaluates_at_the_documented_angles() {
        let s = CharacteristicSlice::of(&Plane, THETA_H_NODES);
        assert_eq!(s.name(), "plane");
        let xs = s.theta_h_deg().to_vec();
        assert_eq!((xs[0], xs[89]), (0.0, 90.0));
        for (j, i) in [(0, 0), (40, 13), (89, 88), (15, 60)] {
            let v = s.value(j, i).unwrap();
            assert!(
                (v - (xs[i] + 100.0 * j as f64)).abs() < 1e-6,
                "({j}, {i}): {v}"
            );
        }
    }

    #[test]
    fn a_slice_linear_in_theta_h_is_rebuilt_from_two_samples() {
        let s = CharacteristicSlice::of(&Plane, THETA_H_NODES);
        assert!(s.error(&[0.0, 90.0], Interpolation::Linear) < 1e-6);
        // A sample set that misses the end at 90 clamps there: column j's error is then
        // the mean over nodes of (x - 45)+, the same in every column.
        let xs = s.theta_h_deg();
        let expected = xs.iter().map(|x| (x - 45.0).max(0.0)).sum::<f64>() / xs.len() as f64;
        assert!((s.error(&[0.0, 45.0], Interpolation::Linear) - expected).abs() < 1e-6);
    }

    #[test]
    fn the_probe_is_the_column_at_40_degrees_at_the_probe_positions() {
        let dense = CharacteristicSlice::of(&Plane, DENSE_NODES);
        assert_eq!(dense.nodes(), 268);
        let probe = dense.probe().unwrap();
        let taken = crate::probe::Probe::take(&Plane, &ProbeSpec::default()).unwrap();
        assert_eq!(probe.theta_h_deg(), taken.theta_h_deg());
        for (a, b) in probe.values().iter().zip(taken.column().values()) {
            assert!((a - b).abs() < 1e-9, "{a} vs {b}");
        }
        // A slice without the probe's nodes gives its whole column.
        let coarse = CharacteristicSlice::of(&Plane, 50);
        assert_eq!(
            coarse.probe().unwrap(),
            coarse.column(PROBE_THETA_D_DEG).unwrap()
        );
    }

    #[test]
    fn missing_cells_are_left_out() {
        let xs = SamplingFunction::square_root().positions_deg(THETA_H_NODES);
        let mut values = vec![Some(1.0); THETA_H_NODES * THETA_D_COLUMNS];
        values[5] = None;
        for v in &mut values[THETA_H_NODES..2 * THETA_H_NODES] {
            *v = None;
        }
        let s = CharacteristicSlice::from_grid("holes", xs, values);
        assert_eq!(s.column(0).unwrap().len(), THETA_H_NODES - 1);
        assert!(s.column(1).is_none());
        assert_eq!(s.error(&[0.0, 90.0], Interpolation::Linear), 0.0);
    }
}
