//! The database analysis of section 5.1: which sampling family, with k fitted on which
//! theta_d column, rebuilds the characteristic slice best from 30 theta_h samples.
//!
//! For one material ([`analyze_slice`]), for each family (power, exponential, base-k) and each
//! candidate column theta_d = 0..89 degrees: fit k to that column (section 5.2's fit, 90
//! square-root-spaced nodes at phi_d = 90), sample every column of the slice at the 30
//! positions of that function, interpolate back and take the mean absolute error over the
//! slice. Over a database ([`DatabaseSummary`]): the mean and the median of that error over
//! the materials, per family and column; the best pair has the lowest mean (the paper found
//! exponential at theta_d = 40 degrees on MERL-100).

use crate::column::{Column, Resampling};
use crate::error::SamplingError;
use crate::fit::{base_of_exponential, FitSearch, KFitter};
use crate::slice::{mean_over_cells, CharacteristicSlice, PROBE_THETA_D_DEG, THETA_D_COLUMNS};
use specula_core::sampling::{Family, SamplingFunction};
use specula_core::shown::plain;
use specula_core::statistics::{median, Statistic};
use std::path::Path;

/// One material's result: per family (in [`Family::ALL`] order) and theta_d column, the
/// fitted k and the slice error (NaN where the column had too few measured cells).
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialAnalysis {
    /// The material's name.
    pub name: String,
    /// `k[f][j]`: k-hat of family `Family::ALL[f]` fitted to column theta_d = j degrees
    /// (paper eq. 3).
    pub k: [Vec<f64>; 3],
    /// `error[f][j]`: the slice error of that fit, 1/sr (NaN where the column is not measured).
    pub error: [Vec<f64>; 3],
}

/// Analyses one material's slice with `n` samples per function.
///
/// The columns are built once, and each family's 90 fits share one [`KFitter`] on the
/// slice's nodes, as the 90 column errors of each fitted function share one
/// [`Resampling`]. Base-k is not fitted: its fit is the exponential one with
/// `k_base = e^k_exp`, the same positions (see [`crate::fit`]); its slice error is that of
/// the base-k function itself.
pub fn analyze_slice(slice: &CharacteristicSlice, n: usize) -> MaterialAnalysis {
    let columns = slice.columns();
    let nodes_deg = slice.theta_h_deg();
    let power = fit_columns(&columns, nodes_deg, Family::Power, n);
    let exponential = fit_columns(&columns, nodes_deg, Family::Exponential, n);
    let base = exponential
        .iter()
        .map(|f| f.and_then(|f| base_of_exponential(f.k).ok()))
        .collect();
    let mut k: [Vec<f64>; 3] = Default::default();
    let mut error: [Vec<f64>; 3] = Default::default();
    for (f, family) in Family::ALL.into_iter().enumerate() {
        let fits = match family {
            Family::Power => &power,
            Family::Exponential => &exponential,
            Family::Base => &base,
        };
        for fit in fits {
            k[f].push(fit.map_or(f64::NAN, |f| f.k));
            error[f].push(fit.map_or(f64::NAN, |f| {
                let resampling = Resampling::new(nodes_deg, &f.positions_deg(n));
                mean_over_cells(&columns, |c| resampling.error(c))
            }));
        }
    }
    MaterialAnalysis {
        name: slice.name().to_string(),
        k,
        error,
    }
}

/// The fitted function of `family` for each column (`None` where the column is missing or
/// `n < 2`); the columns are on `nodes_deg`, but for their missing cells.
fn fit_columns(
    columns: &[Option<Column>],
    nodes_deg: &[f64],
    family: Family,
    n: usize,
) -> Vec<Option<SamplingFunction>> {
    let Ok(mut fitter) = KFitter::new(family, n, &FitSearch::default(), Some(nodes_deg)) else {
        return vec![None; columns.len()];
    };
    columns
        .iter()
        .map(|c| c.as_ref().map(|c| fitter.fit(c).function))
        .collect()
}

/// The mean and median slice error over a database, per family and theta_d column.
#[derive(Debug, Clone, PartialEq)]
pub struct DatabaseSummary {
    /// `mean[f][j]`: family `Family::ALL[f]`, column theta_d = j degrees, 1/sr.
    pub mean: [Vec<f64>; 3],
    /// `median[f][j]`: the median over the materials, same layout, 1/sr.
    pub median: [Vec<f64>; 3],
    /// Materials that entered each figure (those with the column measured).
    pub materials: [Vec<usize>; 3],
}

/// The best (family, column) pair: the lowest mean error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BestPair {
    /// The sampling-function family of the pair.
    pub family: Family,
    /// The theta_d column of the pair, deg.
    pub theta_d_deg: usize,
    /// Mean over the materials of the slice error, 1/sr.
    pub mean: f64,
    /// Median over the materials of the slice error, 1/sr.
    pub median: f64,
}

/// The findings of a database analysis over `materials` materials in words, as `specula
/// analyze` prints them: the best pair, the paper's pair (exponential at the probe's
/// column) and each family's best column; `None` when no material had a measured column.
pub fn findings_text(summary: &DatabaseSummary, materials: usize) -> Option<String> {
    let best = summary.best()?;
    let mut text = format!(
        "best: {} at theta_d = {} deg: mean error {} 1/sr, median {} 1/sr over {materials} materials\n",
        best.family,
        best.theta_d_deg,
        plain(best.mean),
        plain(best.median),
    );
    let f = Family::ALL.iter().position(|f| *f == Family::Exponential)?;
    text.push_str(&format!(
        "paper's pair: exponential at theta_d = {PROBE_THETA_D_DEG} deg: mean error {} 1/sr, median {} 1/sr\n",
        plain(summary.mean[f][PROBE_THETA_D_DEG]),
        plain(summary.median[f][PROBE_THETA_D_DEG])
    ));
    for family in Family::ALL {
        // A family without a measured column shows as column 0 with an infinite error.
        let (j, mean) = summary.best_column(family).unwrap_or((0, f64::INFINITY));
        text.push_str(&format!(
            "  {family:<12} best column theta_d = {j:>2} deg: mean error {} 1/sr\n",
            plain(mean)
        ));
    }
    text.push_str("  (base-k is the exponential family with k_base = e^k_exp: their errors agree to rounding)\n");
    Some(text)
}

impl DatabaseSummary {
    /// The mean and median over `analyses` per family and column, skipping unmeasured (NaN) ones.
    pub fn of(analyses: &[MaterialAnalysis]) -> Self {
        let mut summary = Self {
            mean: Default::default(),
            median: Default::default(),
            materials: Default::default(),
        };
        for f in 0..Family::ALL.len() {
            for j in 0..THETA_D_COLUMNS {
                let mut errors: Vec<f64> = analyses
                    .iter()
                    .map(|a| a.error[f][j])
                    .filter(|e| e.is_finite())
                    .collect();
                summary.materials[f].push(errors.len());
                summary.mean[f].push(errors.iter().sum::<f64>() / errors.len() as f64);
                summary.median[f].push(median(&mut errors));
            }
        }
        summary
    }

    /// The pair with the lowest mean error; ties go to the earlier family of
    /// [`Family::ALL`], then the lower theta_d. `None` for an empty database.
    pub fn best(&self) -> Option<BestPair> {
        let mut best: Option<BestPair> = None;
        for (f, family) in Family::ALL.into_iter().enumerate() {
            for j in 0..THETA_D_COLUMNS {
                let mean = self.mean[f][j];
                if mean.is_finite() && best.is_none_or(|b| mean < b.mean) {
                    best = Some(BestPair {
                        family,
                        theta_d_deg: j,
                        mean,
                        median: self.median[f][j],
                    });
                }
            }
        }
        best
    }

    /// The column of `family` with the lowest mean error, and that error: `(theta_d_deg,
    /// mean)`, the lower theta_d on a tie; `None` when no column of the family is measured.
    pub fn best_column(&self, family: Family) -> Option<(usize, f64)> {
        let f = Family::ALL.iter().position(|&g| g == family)?;
        self.mean[f]
            .iter()
            .copied()
            .enumerate()
            .filter(|(_, m)| m.is_finite())
            .fold(None, |best: Option<(usize, f64)>, (j, m)| match best {
                Some((_, b)) if m >= b => best,
                _ => Some((j, m)),
            })
    }

    /// Writes `family,theta_d,mean_error,median_error,materials` (errors in 1/sr).
    pub fn write_csv(&self, path: &Path) -> Result<(), SamplingError> {
        let mut w = csv::Writer::from_writer(Vec::new());
        w.write_record([
            "family",
            "theta_d",
            "mean_error",
            "median_error",
            "materials",
        ])
        .map_err(SamplingError::csv_write(path))?;
        for (f, family) in Family::ALL.into_iter().enumerate() {
            for j in 0..THETA_D_COLUMNS {
                w.write_record([
                    family.name().to_string(),
                    j.to_string(),
                    format!("{:e}", self.mean[f][j]),
                    format!("{:e}", self.median[f][j]),
                    self.materials[f][j].to_string(),
                ])
                .map_err(SamplingError::csv_write(path))?;
            }
        }
        let bytes = w
            .into_inner()
            .map_err(|e| SamplingError::io(path, "write")(e.into_error()))?;
        specula_core::atomic_file::write_bytes(path, &bytes)
            .map_err(SamplingError::io(path, "write"))
    }
}

/// One statistic of an analysis file ([`DatabaseSummary::write_csv`]) read back: a row per
/// family, in the order the file gives them, and a column per theta_d, increasing.
#[derive(Debug, Clone, PartialEq)]
pub struct ErrorTable {
    /// The families, as the file names them.
    pub families: Vec<String>,
    /// The theta_d columns k was fitted on, degrees, increasing.
    pub theta_d_deg: Vec<f64>,
    /// `values[f][j]`: the statistic of the slice error, 1/sr (NaN where the file has no row).
    pub values: Vec<Vec<f64>>,
}

#[derive(serde::Deserialize)]
struct AnalysisRow {
    family: String,
    theta_d: f64,
    mean_error: f64,
    median_error: f64,
}

impl ErrorTable {
    /// Reads the `statistic` (the mean or the median error) of an analysis file; its other
    /// columns are passed over. A file without rows is an error.
    pub fn read_csv(path: &Path, statistic: Statistic) -> Result<Self, SamplingError> {
        let csv_error = |place: String| SamplingError::csv(path, place);
        let mut reader = SamplingError::open_csv(path)?;
        let mut families: Vec<String> = Vec::new();
        let mut theta_d_deg: Vec<f64> = Vec::new();
        let mut cells: Vec<(usize, f64, f64)> = Vec::new();
        for (line, row) in reader.deserialize::<AnalysisRow>().enumerate() {
            let row = row.map_err(csv_error(format!("row {}", line + 2)))?;
            let f = match families.iter().position(|f| *f == row.family) {
                Some(f) => f,
                None => {
                    families.push(row.family.clone());
                    families.len() - 1
                }
            };
            if !theta_d_deg.contains(&row.theta_d) {
                theta_d_deg.push(row.theta_d);
            }
            let value = match statistic {
                Statistic::Median => row.median_error,
                Statistic::Mean => row.mean_error,
            };
            cells.push((f, row.theta_d, value));
        }
        if cells.is_empty() {
            return Err(SamplingError::NoRows {
                path: path.to_path_buf(),
            });
        }
        theta_d_deg.sort_by(f64::total_cmp);
        let mut values = vec![vec![f64::NAN; theta_d_deg.len()]; families.len()];
        for (f, theta_d, value) in cells {
            let j = theta_d_deg
                .iter()
                .position(|c| *c == theta_d)
                .unwrap_or_default();
            values[f][j] = value;
        }
        Ok(Self {
            families,
            theta_d_deg,
            values,
        })
    }

    /// The cell `(family row, theta_d column)` of the lowest finite value, the first on a
    /// tie; `None` when no value is finite.
    pub fn best(&self) -> Option<(usize, usize)> {
        self.values
            .iter()
            .enumerate()
            .flat_map(|(f, row)| row.iter().enumerate().map(move |(j, v)| (f, j, *v)))
            .filter(|c| c.2.is_finite())
            .min_by(|a, b| a.2.total_cmp(&b.2))
            .map(|(f, j, _)| (f, j))
    }
}

/// Writes every material's k and error: `material,family,theta_d,k,error`.
pub fn write_materials_csv(
    analyses: &[MaterialAnalysis],
    path: &Path,
) -> Result<(), SamplingError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(["material", "family", "theta_d", "k", "error"])
        .map_err(SamplingError::csv_write(path))?;
    for a in analyses {
        for (f, family) in Family::ALL.into_iter().enumerate() {
            for j in 0..THETA_D_COLUMNS {
                w.write_record([
                    a.name.clone(),
                    family.name().to_string(),
                    j.to_string(),
                    format!("{}", a.k[f][j]),
                    format!("{:e}", a.error[f][j]),
                ])
                .map_err(SamplingError::csv_write(path))?;
            }
        }
    }
    let bytes = w
        .into_inner()
        .map_err(|e| SamplingError::io(path, "write")(e.into_error()))?;
    specula_core::atomic_file::write_bytes(path, &bytes).map_err(SamplingError::io(path, "write"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::column::Interpolation;
    use crate::fit::{fit_error, fit_k};
    use crate::slice::THETA_H_NODES;

    /// A slice whose columns are Gaussian lobes whose width grows with theta_d.
    fn lobe_slice(name: &str, scale: f64) -> CharacteristicSlice {
        let xs = SamplingFunction::square_root().positions_deg(THETA_H_NODES);
        let values = (0..THETA_D_COLUMNS)
            .flat_map(|j| {
                let width = 1.0 + j as f64 / 30.0;
                xs.iter()
                    .map(move |x| Some(scale * (0.05 + 20.0 * (-(x / width).powi(2)).exp())))
                    .collect::<Vec<_>>()
            })
            .collect();
        CharacteristicSlice::from_grid(name, xs, values)
    }

    #[test]
    fn each_pair_reports_the_slice_error_of_its_fitted_function() {
        let slice = lobe_slice("lobes", 1.0);
        let a = analyze_slice(&slice, 30);
        assert_eq!(a.error[0].len(), THETA_D_COLUMNS);
        let (f, j) = (1, 40);
        let function = SamplingFunction::new(Family::Exponential, a.k[f][j]).unwrap();
        let direct = slice.error(&function.positions_deg(30), Interpolation::Linear);
        assert!((a.error[f][j] - direct).abs() < 1e-12);
        // The fitted function beats the square-root mapping on this peaked slice.
        let sqrt = slice.error(
            &SamplingFunction::square_root().positions_deg(30),
            Interpolation::Linear,
        );
        assert!(a.error[f][j] < sqrt, "{} vs sqrt {sqrt}", a.error[f][j]);
        // Base-k is the exponential family reparameterised (see fit.rs).
        assert!((a.error[2][j] - a.error[1][j]).abs() <= 1e-9 * a.error[1][j]);
    }

    /// The analysis is what fitting every family on every column with [`fit_k`] and taking
    /// [`CharacteristicSlice::error`] gives: to the last bit for power and exponential. For
    /// base-k, derived from the exponential fit (not fitted), against a base-k fit: the same
    /// k to within Brent's tolerance, and never a higher fit error beyond rounding (green
    /// paint is a material where rounding steers the two fits' Brent apart). Columns with
    /// missing cells take the walk instead of the shared [`Resampling`].
    #[test]
    fn matches_a_fit_of_every_family_on_every_column() {
        let material = |name| specula_core::materials::preset(name).unwrap();
        let lobes = lobe_slice("lobes", 1.0);
        // Cells missing near grazing, as in MERL files: those columns are on fewer nodes.
        let holes = (0..THETA_D_COLUMNS)
            .flat_map(|j| (0..THETA_H_NODES).map(move |i| (j, i)))
            .map(|(j, i)| lobes.value(j, i).filter(|_| j < 60 || (i + j) % 7 != 0))
            .collect();
        let holed = CharacteristicSlice::from_grid("holed", lobes.theta_h_deg().to_vec(), holes);
        assert!(holed.column(70).unwrap().len() < THETA_H_NODES);
        for slice in [
            lobes,
            holed,
            CharacteristicSlice::of(&material("silver-925"), THETA_H_NODES),
            CharacteristicSlice::of(&material("green-paint"), THETA_H_NODES),
        ] {
            let a = analyze_slice(&slice, 30);
            for (f, family) in Family::ALL.into_iter().enumerate() {
                for j in 0..THETA_D_COLUMNS {
                    let column = slice.column(j).unwrap();
                    let fit = fit_k(&column, family, 30).unwrap();
                    let ours = SamplingFunction::new(family, a.k[f][j]).unwrap();
                    let slice_error = slice.error(&ours.positions_deg(30), Interpolation::Linear);
                    assert_eq!(a.error[f][j], slice_error, "{family} {j}");
                    if family != Family::Base {
                        assert_eq!(ours, fit.function, "{family} {j}");
                        continue;
                    }
                    assert_eq!(ours.k, a.k[1][j].exp());
                    // Brent stops within 1e-8 (relative) of the scan coordinate ln ln k.
                    let (ours_ln, fit_ln) = (ours.k.ln(), fit.function.k.ln());
                    assert!(
                        (ours_ln - fit_ln).abs() <= 1e-7 * fit_ln,
                        "{j}: {ours:?} vs {fit:?}"
                    );
                    let ours_fit_error = fit_error(&column, &ours, 30);
                    assert!(
                        ours_fit_error <= fit.error * (1.0 + 1e-12),
                        "{j}: {ours_fit_error} vs {fit:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn summary_takes_mean_and_median_over_materials() {
        let analyses: Vec<MaterialAnalysis> = [1.0, 2.0, 6.0]
            .iter()
            .map(|&s| analyze_slice(&lobe_slice("x", s), 30))
            .collect();
        let summary = DatabaseSummary::of(&analyses);
        let (f, j) = (0, 12);
        let e: Vec<f64> = analyses.iter().map(|a| a.error[f][j]).collect();
        assert!((summary.mean[f][j] - (e[0] + e[1] + e[2]) / 3.0).abs() < 1e-12);
        // The error scales with the material: the median is the middle one.
        assert!((summary.median[f][j] - e[1]).abs() < 1e-12);
        assert_eq!(summary.materials[f][j], 3);
        let best = summary.best().unwrap();
        let lowest = summary
            .mean
            .iter()
            .flatten()
            .copied()
            .fold(f64::INFINITY, f64::min);
        assert_eq!(best.mean, lowest);
        let (j, mean) = summary.best_column(best.family).unwrap();
        assert_eq!((j, mean), (best.theta_d_deg, best.mean));
        for family in Family::ALL {
            let f = Family::ALL.iter().position(|&g| g == family).unwrap();
            let (j, mean) = summary.best_column(family).unwrap();
            assert_eq!(summary.mean[f][j], mean);
            assert!(summary.mean[f]
                .iter()
                .filter(|m| m.is_finite())
                .all(|m| *m >= mean));
        }
    }

    #[test]
    fn an_analysis_file_reads_back_as_a_table_of_one_statistic() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("analysis.csv");
        std::fs::write(
            &path,
            "family,theta_d,mean_error,median_error,materials\n\
             power,40,3,30,5\npower,2,2,20,5\nbase,40,1,10,5\n",
        )
        .unwrap();
        let mean = ErrorTable::read_csv(&path, Statistic::Mean).unwrap();
        assert_eq!(mean.families, ["power", "base"]);
        assert_eq!(mean.theta_d_deg, [2.0, 40.0]);
        assert_eq!(mean.values[0], [2.0, 3.0]);
        assert!(mean.values[1][0].is_nan() && mean.values[1][1] == 1.0);
        assert_eq!(mean.best(), Some((1, 1)));
        let median = ErrorTable::read_csv(&path, Statistic::Median).unwrap();
        assert_eq!(median.values[0], [20.0, 30.0]);

        std::fs::write(&path, "family,theta_d,mean_error,median_error\n").unwrap();
        let err = ErrorTable::read_csv(&path, Statistic::Mean).unwrap_err();
        assert!(err.to_string().ends_with("analysis.csv: no rows"), "{err}");
        std::fs::write(
            &path,
            "family,theta_d,mean_error,median_error\npower,x,1,1\n",
        )
        .unwrap();
        let err = ErrorTable::read_csv(&path, Statistic::Mean).unwrap_err();
        assert!(err.to_string().contains("row 2"), "{err}");
    }
}
