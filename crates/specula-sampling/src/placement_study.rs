//! How well each way of placing n theta_h samples rebuilds a material's characteristic slice.
//!
//! Every method but the oracle sees only the probe (section 5.2: the column at theta_d = 40
//! degrees, 90 square-root-spaced samples), and places one set of theta_h positions that the
//! measurement then uses at every theta_d. The error is the slice's re-interpolation error
//! (mean absolute error over its cells, 1/sr), the figure of section 5.1, over the columns
//! theta_d = 0, 3, ..., 87 degrees of the paper's plan (5.3), taken against a
//! truth three times denser than the probe ([`crate::slice::DENSE_NODES`] nodes per column
//! for a BRDF; a MERL file has only its 90 bins). A truth no denser than the probe would let
//! the oracle pick exactly the nodes where the error is measured and report a near-zero error
//! that no real placement can approach.
//!
//! - square root: MERL's mapping (eq. 1) with n samples;
//! - paper: the exponential function (eq. 3) with k-hat fitted to the probe (section 5.2);
//! - DP on the probe's own samples: the dynamic programme of [`crate::placement`] run on the
//!   probe, samples restricted to the probe's positions;
//! - ours: the same run on the probe's dense log-domain model ([`crate::probe_model`]), so
//!   samples can fall between the probe's;
//! - oracle: for every column its own optimal placement among the truth's nodes, computed
//!   from the truth: the lower bound for placements on those nodes, out of reach of a real
//!   measurement.

use crate::column::Column;
use crate::column::Interpolation;
use crate::error::SamplingError;
use crate::fit::fit_k;
use crate::placement::{optimal_placement, place_on_probe_column};
use crate::slice::{mean_over_cells, CharacteristicSlice, THETA_D_COLUMNS};
use specula_core::sampling::{Family, SamplingFunction};
use specula_core::statistics::median;
use std::io::Write;
use std::path::Path;

/// A way to place the samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlacementRule {
    /// The square-root mapping of paper eq. 1.
    SquareRoot,
    /// The paper's exponential mapping with k-hat fitted to the probe (eq. 3).
    PaperExponential,
    /// Dynamic programming over the probe's own theta_h samples.
    ProbeSamples,
    /// Dynamic programming on the probe's log-spline model (this project's placement).
    Ours,
    /// Dynamic programming per column on the true slice (an oracle, for reference).
    Oracle,
}

impl PlacementRule {
    /// Every method, in table order.
    pub const ALL: [PlacementRule; 5] = [
        PlacementRule::SquareRoot,
        PlacementRule::PaperExponential,
        PlacementRule::ProbeSamples,
        PlacementRule::Ours,
        PlacementRule::Oracle,
    ];

    /// The method's description in tables and plots.
    pub fn label(self) -> &'static str {
        match self {
            PlacementRule::SquareRoot => "square root (eq. 1)",
            PlacementRule::PaperExponential => "paper: exponential, k-hat (eq. 3)",
            PlacementRule::ProbeSamples => "DP on the probe's own samples",
            PlacementRule::Ours => "ours: DP on the probe's log-spline model",
            PlacementRule::Oracle => "oracle: DP per column on the truth",
        }
    }

    /// A short name for files.
    pub fn key(self) -> &'static str {
        match self {
            PlacementRule::SquareRoot => "square_root",
            PlacementRule::PaperExponential => "paper",
            PlacementRule::ProbeSamples => "probe_samples",
            PlacementRule::Ours => "ours",
            PlacementRule::Oracle => "oracle",
        }
    }
}

/// The theta_d columns the study evaluates: 0, 3, ..., 87 degrees, the paper's plan (5.3).
pub fn evaluated_columns() -> impl Iterator<Item = usize> {
    (0..THETA_D_COLUMNS).step_by(3)
}

/// One material's slice error per method, in [`PlacementRule::ALL`] order, 1/sr.
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialPlacement {
    /// The material's name.
    pub name: String,
    /// The paper's k-hat, fitted to the probe.
    pub k_hat: f64,
    /// The slice error of each method, in [`PlacementRule::ALL`] order, 1/sr.
    pub error: [f64; 5],
    /// The mean value of the evaluated cells, 1/sr: the scale of the errors.
    pub mean_value: f64,
}

/// A material whose oracle error is below this fraction of its mean value is rebuilt exactly
/// (to rounding) by the oracle; ratios to that error mean nothing and are left out.
pub const EXACT_FRACTION: f64 = 1e-6;

/// Evaluates every method on one material with `n` samples, interpolating in `domain`, over
/// the [`evaluated_columns`].
pub fn study_slice(
    slice: &CharacteristicSlice,
    n: usize,
    domain: Interpolation,
) -> Result<MaterialPlacement, SamplingError> {
    let probe = slice.probe().ok_or_else(|| SamplingError::NoProbeColumn {
        material: slice.name().to_string(),
    })?;
    let k_hat = fit_k(&probe, Family::Exponential, n)?.function;
    let columns: Vec<Option<Column>> = evaluated_columns().map(|j| slice.column(j)).collect();
    let error_of = |positions: &[f64]| {
        mean_over_cells(&columns, |c| c.reinterpolation_error(positions, domain))
    };
    let error = PlacementRule::ALL.map(|method| match method {
        PlacementRule::SquareRoot => error_of(&SamplingFunction::square_root().positions_deg(n)),
        PlacementRule::PaperExponential => error_of(&k_hat.positions_deg(n)),
        PlacementRule::ProbeSamples => error_of(&optimal_placement(&probe, n, domain).theta_h_deg),
        PlacementRule::Ours => error_of(&place_on_probe_column(&probe, n, domain)),
        PlacementRule::Oracle => {
            mean_over_cells(&columns, |c| optimal_placement(c, n, domain).error)
        }
    });
    let mean_value = mean_over_cells(&columns, |c| {
        c.values().iter().sum::<f64>() / c.len() as f64
    });
    Ok(MaterialPlacement {
        name: slice.name().to_string(),
        k_hat: k_hat.k,
        error,
        mean_value,
    })
}

/// One row of the comparison table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MethodSummary {
    /// The method of the row.
    pub method: PlacementRule,
    /// Mean over the materials of the slice error, 1/sr.
    pub mean_error: f64,
    /// `mean_error` over the oracle's.
    pub ratio_of_means: f64,
    /// Geometric mean over the materials of each one's error over its oracle error
    /// (materials the oracle rebuilds exactly, see [`EXACT_FRACTION`], are left out).
    pub geometric_mean_ratio: f64,
    /// Median of the same per-material ratios.
    pub median_ratio: f64,
    /// Largest per-material ratio.
    pub worst_ratio: f64,
    /// Materials left out of the ratios (rebuilt exactly by the oracle).
    pub exact_materials: usize,
}

/// The comparison table over a database.
pub fn summarize(materials: &[MaterialPlacement]) -> Vec<MethodSummary> {
    let oracle = PlacementRule::ALL
        .iter()
        .position(|m| *m == PlacementRule::Oracle)
        .expect("listed");
    let mean_of =
        |i: usize| materials.iter().map(|m| m.error[i]).sum::<f64>() / materials.len() as f64;
    let oracle_mean = mean_of(oracle);
    PlacementRule::ALL
        .iter()
        .enumerate()
        .map(|(i, &method)| {
            let mut ratios: Vec<f64> = materials
                .iter()
                .filter(|m| m.error[oracle] > EXACT_FRACTION * m.mean_value)
                .map(|m| m.error[i] / m.error[oracle])
                .collect();
            MethodSummary {
                method,
                mean_error: mean_of(i),
                ratio_of_means: mean_of(i) / oracle_mean,
                geometric_mean_ratio: (ratios.iter().map(|r| r.ln()).sum::<f64>()
                    / ratios.len() as f64)
                    .exp(),
                worst_ratio: ratios.iter().copied().fold(f64::NAN, f64::max),
                exact_materials: materials.len() - ratios.len(),
                median_ratio: median(&mut ratios),
            }
        })
        .collect()
}

/// Writes every material's errors per interpolation domain as CSV: the header
/// `material,k_hat,domain,` and one column per method ([`PlacementRule::key`], in [`PlacementRule::ALL`]
/// order), then a row per material and domain; `rows[m][d]` is material `m` interpolated in
/// `domains[d]`, errors in 1/sr.
pub fn write_csv(
    path: &Path,
    domains: &[Interpolation],
    rows: &[Vec<MaterialPlacement>],
) -> Result<(), SamplingError> {
    specula_core::atomic_file::write_with(path, |out| write_rows(out, domains, rows))
        .map_err(SamplingError::io(path, "write"))
}

fn write_rows(
    out: &mut impl Write,
    domains: &[Interpolation],
    rows: &[Vec<MaterialPlacement>],
) -> std::io::Result<()> {
    let methods: Vec<&str> = PlacementRule::ALL.iter().map(|m| m.key()).collect();
    writeln!(out, "material,k_hat,domain,{}", methods.join(","))?;
    for per_domain in rows {
        for (domain, row) in domains.iter().zip(per_domain) {
            let errors: Vec<String> = row.error.iter().map(|e| format!("{e:e}")).collect();
            writeln!(
                out,
                "{},{},{},{}",
                row.name,
                row.k_hat,
                domain.name(),
                errors.join(",")
            )?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::slice::{THETA_D_COLUMNS, THETA_H_NODES};

    /// Lobes of the same shape in every column, scaled by a Fresnel-like factor of theta_d.
    fn same_shape_slice(width_deg: f64) -> CharacteristicSlice {
        let xs = SamplingFunction::square_root().positions_deg(THETA_H_NODES);
        let values = (0..THETA_D_COLUMNS)
            .flat_map(|j| {
                let scale = 1.0 + (j as f64 / 90.0).powi(5) * 10.0;
                xs.iter()
                    .map(move |x| Some(scale * (0.02 + 30.0 * (-(x / width_deg).powi(2)).exp())))
                    .collect::<Vec<_>>()
            })
            .collect();
        CharacteristicSlice::from_grid("same-shape", xs, values)
    }

    #[test]
    fn when_every_column_has_the_probe_shape_the_probe_dp_is_the_oracle() {
        let result = study_slice(&same_shape_slice(8.0), 30, Interpolation::Linear).unwrap();
        let [sqrt, paper, on_probe, _, oracle] = result.error;
        assert!(
            oracle > 1e-4 && (on_probe - oracle).abs() <= 1e-9 * oracle,
            "{result:?}"
        );
        assert!(oracle < paper && oracle < sqrt, "{result:?}");
        assert!(result.k_hat > 1.0);
    }

    #[test]
    fn the_table_reports_ratios_to_the_oracle() {
        let materials = vec![
            MaterialPlacement {
                name: "a".into(),
                k_hat: 5.0,
                error: [4.0, 3.0, 2.5, 2.0, 1.0],
                mean_value: 10.0,
            },
            MaterialPlacement {
                name: "b".into(),
                k_hat: 5.0,
                error: [8.0, 6.0, 5.0, 4.0, 4.0],
                mean_value: 10.0,
            },
            // Rebuilt exactly by the oracle: out of the ratios, in the means.
            MaterialPlacement {
                name: "c".into(),
                k_hat: 5.0,
                error: [3.0, 3.0, 2.5, 2.0, 1e-12],
                mean_value: 10.0,
            },
        ];
        let table = summarize(&materials);
        assert_eq!(table[4].ratio_of_means, 1.0);
        let ours = table[3];
        assert_eq!(ours.exact_materials, 1);
        assert!((ours.mean_error - 8.0 / 3.0).abs() < 1e-12);
        assert!((ours.ratio_of_means - 8.0 / 5.0).abs() < 1e-9);
        assert!((ours.geometric_mean_ratio - 2f64.sqrt()).abs() < 1e-12);
        assert_eq!(ours.worst_ratio, 2.0);
        assert_eq!(table[0].median_ratio, 3.0);
    }

    #[test]
    fn the_csv_has_a_row_per_material_and_domain() {
        let row = |name: &str, k_hat| MaterialPlacement {
            name: name.into(),
            k_hat,
            error: [0.5, 0.25, 2.0, 1e-3, 1.0],
            mean_value: 1.0,
        };
        let rows = vec![
            vec![row("a", 4.5), row("a", 4.5)],
            vec![row("b", 6.0), row("b", 6.0)],
        ];
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("placement.csv");
        write_csv(&path, &Interpolation::ALL, &rows).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let keys: Vec<&str> = PlacementRule::ALL.iter().map(|m| m.key()).collect();
        assert_eq!(
            lines[0],
            format!("material,k_hat,domain,{}", keys.join(","))
        );
        assert_eq!(lines.len(), 5);
        assert_eq!(
            lines[1],
            format!(
                "a,4.5,{},5e-1,2.5e-1,2e0,1e-3,1e0",
                Interpolation::ALL[0].name()
            )
        );
        assert!(lines[4].starts_with(&format!("b,6,{},", Interpolation::ALL[1].name())));
        let err = write_csv(
            &dir.path().join("no/such/x.csv"),
            &Interpolation::ALL,
            &rows,
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("x.csv: cannot write"), "{err}");
    }
}
