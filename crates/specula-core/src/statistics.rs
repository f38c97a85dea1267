//! Summary statistics of measured values: the median and mean of figures (over materials,
//! over a ring of captures) and the per-channel range, mean and peak of a table's RGB
//! values.

use crate::Rgb;

/// The median of the values (sorted in place); NaN when empty.
pub fn median(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    values.sort_by(f64::total_cmp);
    let mid = values.len() / 2;
    if values.len() % 2 == 1 {
        values[mid]
    } else {
        0.5 * (values[mid - 1] + values[mid])
    }
}

/// The median of `|x|` over a normal distribution of unit standard deviation.
pub const HALF_NORMAL_MEDIAN: f64 = 0.674_489_750_196_081_7;

/// The standard deviation of a normal distribution whose absolute values have the median of
/// `absolute` (non-negative; sorted in place), `median / 0.6745`: robust to the few large
/// values that would set a root mean square; zero when empty.
pub fn normal_scale_of_absolute(absolute: &mut [f64]) -> f64 {
    if absolute.is_empty() {
        return 0.0;
    }
    median(absolute) / HALF_NORMAL_MEDIAN
}

/// A statistic that sums up figures over several materials.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Statistic {
    /// The [`median`].
    Median,
    /// The arithmetic mean.
    Mean,
}

impl Statistic {
    /// Both, in the order they are reported: median, mean.
    pub const ALL: [Statistic; 2] = [Statistic::Median, Statistic::Mean];

    /// The statistic's name: `median` or `mean`.
    pub fn name(self) -> &'static str {
        match self {
            Statistic::Median => "median",
            Statistic::Mean => "mean",
        }
    }

    /// The statistic of the values (which it may reorder); NaN when empty.
    pub fn of(self, values: &mut [f64]) -> f64 {
        match self {
            Statistic::Median => median(values),
            Statistic::Mean => values.iter().sum::<f64>() / values.len() as f64,
        }
    }
}

/// The value with the largest mean of R, G and B, and where it is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Peak {
    /// The index the value came with (a MERL cell, a UTIA node, a row).
    pub index: usize,
    /// The mean of its R, G and B, in the values' unit (1/sr for f_r).
    pub mean: f64,
}

/// Minimum, maximum and mean per channel of indexed RGB values, and their [`Peak`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChannelStats {
    /// How many values there were.
    pub count: usize,
    /// The smallest value of each channel (infinite when there were none).
    pub min: Rgb,
    /// The largest value of each channel (minus infinity when there were none).
    pub max: Rgb,
    /// The sum of each channel.
    sum: Rgb,
    /// The first value with the largest mean of R, G and B; `None` when there were none.
    pub peak: Option<Peak>,
}

impl ChannelStats {
    /// The statistics of `(index, value)` pairs, in one pass.
    pub fn of(values: impl IntoIterator<Item = (usize, Rgb)>) -> Self {
        let mut stats = Self {
            count: 0,
            min: Rgb::splat(f64::INFINITY),
            max: Rgb::splat(f64::NEG_INFINITY),
            sum: Rgb::ZERO,
            peak: None,
        };
        for (index, v) in values {
            stats.count += 1;
            stats.min = stats.min.min(v);
            stats.max = stats.max.max(v);
            stats.sum += v;
            let mean = v.element_sum() / 3.0;
            if stats.peak.is_none_or(|best| mean > best.mean) {
                stats.peak = Some(Peak { index, mean });
            }
        }
        stats
    }

    /// The mean of each channel; `None` when there were no values.
    pub fn mean(&self) -> Option<Rgb> {
        (self.count > 0).then(|| self.sum / self.count as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_even_and_odd_counts() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&mut [4.0, 1.0, 2.0, 3.0]), 2.5);
        assert!(median(&mut []).is_nan());
    }

    #[test]
    fn statistics_by_name() {
        let values = [4.0, 1.0, 2.0, 9.0];
        assert_eq!(Statistic::Median.of(&mut values.clone()), 3.0);
        assert_eq!(Statistic::Mean.of(&mut values.clone()), 4.0);
        assert!(Statistic::Mean.of(&mut []).is_nan());
        assert_eq!(Statistic::ALL.map(Statistic::name), ["median", "mean"]);
    }

    #[test]
    fn channel_stats_give_range_mean_and_the_first_peak() {
        let stats = ChannelStats::of([
            (7, Rgb::new(1.0, 2.0, 3.0)),
            (9, Rgb::new(4.0, 0.0, 5.0)),
            (11, Rgb::new(0.0, 6.0, 3.0)),
        ]);
        assert_eq!(stats.count, 3);
        assert_eq!(stats.min, Rgb::new(0.0, 0.0, 3.0));
        assert_eq!(stats.max, Rgb::new(4.0, 6.0, 5.0));
        assert_eq!(
            stats.mean(),
            Some(Rgb::new(5.0 / 3.0, 8.0 / 3.0, 11.0 / 3.0))
        );
        // 9 and 11 both have the mean 3: the first one is the peak.
        assert_eq!(
            stats.peak,
            Some(Peak {
                index: 9,
                mean: 3.0
            })
        );
        let none = ChannelStats::of(std::iter::empty());
        assert_eq!((none.count, none.mean(), none.peak), (0, None, None));
    }
}
