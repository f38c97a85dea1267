//! The harness's figures summed up over several materials: each figure of [`Accuracy`]
//! combined by a [`Statistic`] (median or mean), over all materials or per set of truths,
//! the real measured truths first: they are the ones that judge a method (docs/book/src/results.md, "Real
//! measured truths first").

use crate::Accuracy;
use specula_core::compare::ErrorFigures;
use specula_core::statistics::Statistic;

/// The set of the real measured truths, summarised before every other set.
pub const REAL_SET: &str = "real";

impl Accuracy {
    /// The figures of several materials combined figure by figure by `statistic`, in the
    /// order given; the cell counts too, rounded to a whole cell (NaN figures and 0 cells
    /// for none).
    pub fn combined(accuracies: &[Accuracy], statistic: Statistic) -> Accuracy {
        let of = |figures: fn(&Accuracy) -> &ErrorFigures| {
            let figure = |value: fn(&ErrorFigures) -> f64| {
                let mut values: Vec<f64> = accuracies.iter().map(|a| value(figures(a))).collect();
                statistic.of(&mut values)
            };
            let cells = figure(|e| e.cells as f64);
            ErrorFigures {
                cells: if cells.is_finite() {
                    cells.round() as usize
                } else {
                    0
                },
                relative_rmse: figure(|e| e.relative_rmse),
                log_rmse: figure(|e| e.log_rmse),
                slice_mae: figure(|e| e.slice_mae),
            }
        };
        Accuracy {
            within: of(|a| &a.within),
            all: of(|a| &a.all),
        }
    }
}

/// One statistic of one set's figures.
#[derive(Debug, Clone, PartialEq)]
pub struct SetSummary {
    /// The set: [`REAL_SET`], or another name the caller gave its truths.
    pub set: String,
    /// How the materials' figures are combined.
    pub statistic: Statistic,
    /// How many materials the set holds.
    pub materials: usize,
    /// The combined figures ([`Accuracy::combined`]).
    pub accuracy: Accuracy,
}

impl SetSummary {
    /// For each set of `rows` (set, a material's figures), [`REAL_SET`] first and the others
    /// by name: its median, then its mean.
    pub fn of<'a>(rows: impl IntoIterator<Item = (&'a str, Accuracy)>) -> Vec<SetSummary> {
        let rows: Vec<(&str, Accuracy)> = rows.into_iter().collect();
        let mut sets: Vec<&str> = rows.iter().map(|(set, _)| *set).collect();
        sets.sort_by_key(|s| (*s != REAL_SET, *s));
        sets.dedup();
        let mut summaries = Vec::with_capacity(2 * sets.len());
        for set in sets {
            let members: Vec<Accuracy> = rows
                .iter()
                .filter(|(s, _)| *s == set)
                .map(|(_, a)| *a)
                .collect();
            for statistic in Statistic::ALL {
                summaries.push(SetSummary {
                    set: set.to_string(),
                    statistic,
                    materials: members.len(),
                    accuracy: Accuracy::combined(&members, statistic),
                });
            }
        }
        summaries
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn accuracy(x: f64, cells: usize) -> Accuracy {
        let figures = ErrorFigures {
            cells,
            relative_rmse: x,
            log_rmse: 2.0 * x,
            slice_mae: 3.0 * x,
        };
        Accuracy {
            within: figures,
            all: ErrorFigures {
                relative_rmse: 10.0 * x,
                ..figures
            },
        }
    }

    #[test]
    fn figures_combine_one_by_one() {
        let all = [accuracy(1.0, 10), accuracy(2.0, 11), accuracy(6.0, 30)];
        let mean = Accuracy::combined(&all, Statistic::Mean);
        assert_eq!(mean.within.relative_rmse, 3.0);
        assert_eq!(mean.within.slice_mae, 9.0);
        assert_eq!(mean.all.relative_rmse, 30.0);
        assert_eq!(mean.within.cells, 17);
        let median = Accuracy::combined(&all, Statistic::Median);
        assert_eq!(median.within.log_rmse, 4.0);
        assert_eq!(median.all.cells, 11);
        let none = Accuracy::combined(&[], Statistic::Mean);
        assert!(none.within.relative_rmse.is_nan() && none.all.cells == 0);
    }

    #[test]
    fn sets_are_summarised_real_first_median_then_mean() {
        let rows = [
            ("builtin", accuracy(1.0, 5)),
            (REAL_SET, accuracy(4.0, 5)),
            ("given", accuracy(3.0, 5)),
            (REAL_SET, accuracy(2.0, 5)),
            ("builtin", accuracy(3.0, 5)),
            (REAL_SET, accuracy(9.0, 5)),
        ];
        let summaries = SetSummary::of(rows);
        let order: Vec<(&str, &str, usize)> = summaries
            .iter()
            .map(|s| (s.set.as_str(), s.statistic.name(), s.materials))
            .collect();
        assert_eq!(
            order,
            [
                ("real", "median", 3),
                ("real", "mean", 3),
                ("builtin", "median", 2),
                ("builtin", "mean", 2),
                ("given", "median", 1),
                ("given", "mean", 1),
            ]
        );
        assert_eq!(summaries[0].accuracy.within.relative_rmse, 4.0);
        assert_eq!(summaries[1].accuracy.within.relative_rmse, 5.0);
        assert_eq!(summaries[2].accuracy.within.relative_rmse, 2.0);
    }
}
