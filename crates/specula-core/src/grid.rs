//! The measurement grid of paper 5.3: theta_h positions from a sampling function (paper
//! eq. 2-4), theta_d and phi_d in even steps, all at one phi_h. [`GridSpec`] holds the
//! numbers that choose a grid; the theta_h positions themselves come from the sampling
//! function fitted to the probe ([`crate::sampling`], [`crate::probe`]).

/// The numbers of a measurement grid (paper 5.3); [`GridSpec::paper`] is the paper's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridSpec {
    /// Number of theta_h positions of the sampling function.
    pub theta_h_samples: usize,
    /// Step of theta_d in degrees: 0, step, 2 step, ... below 90.
    pub theta_d_step_deg: f64,
    /// Step of phi_d in degrees: 0, step, 2 step, ... up to 90 (the rest of phi_d follows
    /// by reciprocity and isotropy).
    pub phi_d_step_deg: f64,
    /// phi_h in degrees: the sample's orientation on the turntable, chosen away from
    /// scratch directions (paper 4.3).
    pub phi_h_deg: f64,
}

impl GridSpec {
    /// The paper's grid (5.3): 30 theta_h positions, theta_d step 3 deg (0 to 87), phi_d
    /// step 15 deg (0 to 90), phi_h 45 deg: 30 x 30 x 7 = 6300 samples.
    pub const fn paper() -> Self {
        Self {
            theta_h_samples: 30,
            theta_d_step_deg: 3.0,
            phi_d_step_deg: 15.0,
            phi_h_deg: 45.0,
        }
    }

    /// theta_d positions in degrees: `0, step, 2 step, ...` below 90.
    pub fn theta_d_deg(&self) -> Vec<f64> {
        steps_to_90_deg(self.theta_d_step_deg, false)
    }

    /// phi_d positions in degrees: `0, step, 2 step, ...` up to and including 90.
    pub fn phi_d_deg(&self) -> Vec<f64> {
        steps_to_90_deg(self.phi_d_step_deg, true)
    }

    /// The grid's shape, `[theta_h, theta_d, phi_d]` position counts, without building it.
    pub fn shape(&self) -> [usize; 3] {
        [
            self.theta_h_samples,
            steps_to_90_count(self.theta_d_step_deg, false),
            steps_to_90_count(self.phi_d_step_deg, true),
        ]
    }

    /// The number of grid samples: theta_h x theta_d x phi_d positions (6300 for the
    /// paper's), saturating at `usize::MAX`.
    pub fn sample_count(&self) -> usize {
        self.shape()
            .into_iter()
            .fold(1, |product: usize, n| product.saturating_mul(n))
    }
}

impl Default for GridSpec {
    fn default() -> Self {
        Self::paper()
    }
}

/// `0, step, 2 step, ...` below 90 degrees, or up to and including 90 with `include_90`
/// (within float noise); `step_deg` must be positive. Degrees in, degrees out.
pub fn steps_to_90_deg(step_deg: f64, include_90: bool) -> Vec<f64> {
    (0..steps_to_90_count(step_deg, include_90))
        .map(|i| i as f64 * step_deg)
        .collect()
}

/// How many positions [`steps_to_90_deg`] gives, without listing them.
fn steps_to_90_count(step_deg: f64, include_90: bool) -> usize {
    let kept = |i: usize| {
        let v = i as f64 * step_deg;
        if include_90 {
            v <= 90.0 + 1e-9
        } else {
            v < 90.0 - 1e-9
        }
    };
    // The positions grow with i, so the kept ones are a prefix: the last candidates are the
    // only ones that can fall beyond 90.
    let candidates = (90.0 / step_deg + 1e-9).floor() as usize;
    (0..=candidates)
        .rev()
        .find(|&i| kept(i))
        .map_or(0, |i| i + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_paper_grid_has_6300_samples() {
        let paper = GridSpec::paper();
        let theta_d = paper.theta_d_deg();
        let phi_d = paper.phi_d_deg();
        assert_eq!(theta_d.len(), 30);
        assert_eq!(theta_d.last(), Some(&87.0));
        assert_eq!(phi_d, vec![0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 90.0]);
        assert_eq!(paper.theta_h_samples * theta_d.len() * phi_d.len(), 6300);
    }

    #[test]
    fn the_shape_counts_the_positions_the_grid_lists() {
        assert_eq!(GridSpec::paper().shape(), [30, 30, 7]);
        assert_eq!(GridSpec::paper().sample_count(), 6300);
        for step in [0.5, 0.7, 1.2, 7.0, 12.5, 90.0 / 7.0, 45.0, 90.0] {
            let spec = GridSpec {
                theta_h_samples: 4,
                theta_d_step_deg: step,
                phi_d_step_deg: step,
                phi_h_deg: 45.0,
            };
            let [_, theta_d, phi_d] = spec.shape();
            assert_eq!(theta_d, spec.theta_d_deg().len(), "{step}");
            assert_eq!(phi_d, spec.phi_d_deg().len(), "{step}");
            assert_eq!(spec.sample_count(), 4 * theta_d * phi_d);
        }
    }

    #[test]
    fn steps_that_divide_90_stop_before_or_at_it() {
        assert_eq!(steps_to_90_deg(90.0, false), vec![0.0]);
        assert_eq!(steps_to_90_deg(90.0, true), vec![0.0, 90.0]);
        assert_eq!(steps_to_90_deg(40.0, true), vec![0.0, 40.0, 80.0]);
        assert_eq!(steps_to_90_deg(0.1, false).len(), 900);
        assert_eq!(steps_to_90_deg(0.1, true).len(), 901);
    }
}
