//! The candidate lattice of a sequential measurement and the sub-lattice measured so far.
//!
//! The candidates are the grid the fixed plan would measure (paper 5.3): theta_h from the
//! fitted sampling function, theta_d and phi_d from the grid. The reconstruction interpolates
//! a tensor lattice spanned by the samples' coordinates and continues it from the nearest
//! node where a node is missing (`specula_reconstruct`'s lattice and extrapolation), so a
//! sequential measurement keeps what it measures a tensor sub-lattice: it chooses *planes*
//! (one theta_h, theta_d or phi_d node of the candidates) and measures every reachable
//! position of the product of the chosen nodes. An isolated sample would open a lattice line
//! that the rest of the lattice fills by nearest-node continuation.
//!
//! One product node is left out of every plane: theta_h 0 at a phi_d other than 90 deg. At
//! theta_h 0 the half vector is the normal, and turning the pair of directions about it
//! (phi_d) changes nothing for an isotropic surface, so each theta_d there is one
//! configuration whatever phi_d names it; the reconstruction gives the one measured to every
//! phi_d plane (`specula_reconstruct::phi_d_halves`). phi_d 90 deg is where the two halves of
//! phi_d meet (both take its samples), and a first design always measures it
//! ([`CandidateLattice::choose_initial`]). On a near-diffuse fabric the normal at five phi_d
//! was a ninth of the first design's samples.

use specula_acquisition::device::Device;
use specula_acquisition::plan::Plan;
use specula_core::{GridSpec, HalfDiff};
use std::cmp::Reverse;

/// The three axes of the lattice, in its index order.
pub(crate) const AXES: usize = 3;
/// The axes' names, in their index order.
const AXIS_NAMES: [&str; AXES] = ["theta_h", "theta_d", "phi_d"];

/// The candidates' nodes on every axis (theta_h, theta_d, phi_d; degrees), which products
/// the device reaches, and the nodes chosen so far.
#[derive(Debug, Clone)]
pub(crate) struct CandidateLattice {
    /// The nodes of each axis, degrees, increasing.
    pub nodes_deg: [Vec<f64>; AXES],
    /// The sample's orientation, degrees.
    pub phi_h_deg: f64,
    /// Whether the device reaches the product node `(h, d, p)`, at [`Self::flat`].
    reachable: Vec<bool>,
    /// The chosen nodes of each axis.
    pub chosen: [Vec<bool>; AXES],
}

impl CandidateLattice {
    /// The lattice `theta_h x theta_d x phi_d` (degrees) at `phi_h_deg`, with what `device`
    /// reaches; nothing chosen yet.
    pub(crate) fn new(
        theta_h_deg: Vec<f64>,
        theta_d_deg: Vec<f64>,
        phi_d_deg: Vec<f64>,
        phi_h_deg: f64,
        device: &Device,
    ) -> Self {
        let nodes_deg = [theta_h_deg, theta_d_deg, phi_d_deg];
        let plan = Plan::from_grid(
            &nodes_deg[0],
            &nodes_deg[1],
            &nodes_deg[2],
            phi_h_deg,
            device,
        );
        let mut reachable = vec![false; nodes_deg.iter().map(Vec::len).product()];
        for (sample, _) in plan.measured() {
            reachable[sample.index] = true;
        }
        if let Some(kept) = normal_phi_d(&nodes_deg) {
            // theta_h is outermost: the normal's nodes are the first theta_d x phi_d.
            let np = nodes_deg[2].len();
            let at_the_normal = reachable.iter_mut().take(nodes_deg[1].len() * np);
            for (i, reaches) in at_the_normal.enumerate() {
                *reaches &= i % np == kept;
            }
        }
        let chosen = nodes_deg.clone().map(|n| vec![false; n.len()]);
        Self {
            nodes_deg,
            phi_h_deg,
            reachable,
            chosen,
        }
    }

    /// The index of the product node `(h, d, p)` (theta_h outermost, as `Plan::from_grid`).
    fn flat(&self, [h, d, p]: [usize; AXES]) -> usize {
        (h * self.nodes_deg[1].len() + d) * self.nodes_deg[2].len() + p
    }

    /// Whether the device reaches the product node `(h, d, p)`.
    pub(crate) fn reaches(&self, node: [usize; AXES]) -> bool {
        self.reachable[self.flat(node)]
    }

    /// The half-difference angles of the product node `(h, d, p)`.
    pub(crate) fn half_diff(&self, [h, d, p]: [usize; AXES]) -> HalfDiff {
        HalfDiff::from_degrees(
            self.nodes_deg[0][h],
            self.phi_h_deg,
            self.nodes_deg[1][d],
            self.nodes_deg[2][p],
        )
    }

    /// The reachable product nodes of `chosen` (theta_h outermost).
    pub(crate) fn product(&self, chosen: &[Vec<bool>; AXES]) -> Vec<[usize; AXES]> {
        let picked =
            |a: usize| -> Vec<usize> { (0..chosen[a].len()).filter(|&i| chosen[a][i]).collect() };
        let (hs, ds, ps) = (picked(0), picked(1), picked(2));
        let mut out = Vec::new();
        for &h in &hs {
            for &d in &ds {
                for &p in &ps {
                    if self.reaches([h, d, p]) {
                        out.push([h, d, p]);
                    }
                }
            }
        }
        out
    }

    /// The reachable product nodes of the chosen nodes.
    pub(crate) fn chosen_product(&self) -> Vec<[usize; AXES]> {
        self.product(&self.chosen)
    }

    /// Chooses the nodes a first design measures: on each axis every `stride`-th node and the
    /// last, and on phi_d over a half-turn the node at 90 deg too. Of the strides whose
    /// reachable product has at most `max_samples` positions, the finest on theta_h down to
    /// [`FIRST_THETA_H_NODES`] nodes, then the largest product; the coarsest when none is
    /// that small.
    ///
    /// theta_h comes first because its nodes are the sampling function's (paper 5.2), fitted
    /// to the material's peak from the probe, while theta_d and phi_d are the grid's uniform
    /// steps, which the batches refine where the table asks for it. The largest product alone
    /// took every third theta_h and every theta_d on near-diffuse materials (6 theta_h planes
    /// 15 deg apart, 50 theta_d ones), whose structure in theta_h no batch could afford to fill
    /// in: a theta_h plane at every theta_d and phi_d costs more than the time left. Finer
    /// than [`FIRST_THETA_H_NODES`] it does not go: the grid for a peak the instrument does
    /// not resolve has about 30 theta_h nodes, most of them within the instrument's
    /// resolution, and taking them all left the first design 5 theta_d planes.
    ///
    /// The halves of phi_d (0 to 90 and 90 to 180 deg) are reconstructed apart, each from its
    /// own planes: without the plane at 90 deg where they meet, every other stride would
    /// leave each half extrapolating over its last gap (0, 60, 120, 180 deg measures 60 to
    /// 120 deg nowhere).
    pub(crate) fn choose_initial(&mut self, max_samples: usize) {
        let lens = self.nodes_deg.each_ref().map(Vec::len);
        let meeting = self.nodes_deg[2]
            .iter()
            .position(|&p| (p - 90.0).abs() < 1e-9)
            .filter(|&i| i + 1 < lens[2]);
        let designs = initial_strides(lens).into_iter().map(|stride| {
            let mut chosen: [Vec<bool>; AXES] = std::array::from_fn(|a| every(lens[a], stride[a]));
            if let Some(i) = meeting {
                chosen[2][i] = true;
            }
            let bends = each_half_bends(&chosen[2], meeting);
            (self.product(&chosen).len(), stride, chosen, bends)
        });
        let (fitting, too_large): (Vec<_>, Vec<_>) =
            designs.partition(|(count, ..)| *count <= max_samples);
        let finest_theta_h = (1..lens[0].max(1))
            .find(|&stride| {
                every(lens[0], stride).iter().filter(|&&c| c).count() <= FIRST_THETA_H_NODES
            })
            .unwrap_or(1);
        // Strides at or above the finest allowed first, the finest of them first; finer ones last.
        let theta_h_rank = |stride: usize| (stride >= finest_theta_h, Reverse(stride));
        // Then those whose halves of phi_d each hold a plane between their ends.
        let best = fitting
            .into_iter()
            .max_by_key(|(count, stride, _, bends)| (theta_h_rank(stride[0]), *bends, *count))
            .or_else(|| too_large.into_iter().min_by_key(|d| d.0));
        if let Some((_, _, chosen, _)) = best {
            self.chosen = chosen;
        }
    }

    /// Takes the chosen nodes a journal kept; `false` (nothing changed) when their counts
    /// are not this lattice's.
    pub(crate) fn restore(&mut self, chosen: &[Vec<bool>]) -> bool {
        let fits =
            chosen.len() == AXES && (0..AXES).all(|a| chosen[a].len() == self.nodes_deg[a].len());
        if fits {
            self.chosen = std::array::from_fn(|a| chosen[a].clone());
        }
        fits
    }

    /// The nodes `chosen` holds that this lattice has not chosen, in words:
    /// `theta_d 33, 39 deg; phi_d 60 deg`.
    pub(crate) fn planes_added_by(&self, chosen: &[Vec<bool>; AXES]) -> String {
        let parts: Vec<String> = (0..AXES)
            .filter_map(|a| {
                let added: Vec<String> = (0..chosen[a].len())
                    .filter(|&i| chosen[a][i] && !self.chosen[a][i])
                    .map(|i| {
                        format!("{:.4}", self.nodes_deg[a][i])
                            .trim_end_matches('0')
                            .trim_end_matches('.')
                            .to_string()
                    })
                    .collect();
                (!added.is_empty()).then(|| format!("{} {} deg", AXIS_NAMES[a], added.join(", ")))
            })
            .collect();
        parts.join("; ")
    }

    /// The chosen nodes' counts against the candidates', in words:
    /// `8 of 16 theta_h x 12 of 50 theta_d x 4 of 7 phi_d`.
    pub(crate) fn design_text(&self) -> String {
        let parts: Vec<String> = (0..AXES)
            .map(|a| {
                let chosen = self.chosen[a].iter().filter(|&&c| c).count();
                format!("{chosen} of {} {}", self.nodes_deg[a].len(), AXIS_NAMES[a])
            })
            .collect();
        parts.join(" x ")
    }

    /// How many positions choosing node `i` of `axis` would add to the product of `chosen`:
    /// the reachable ones of its plane across the other axes' chosen nodes.
    pub(crate) fn added_by(&self, chosen: &[Vec<bool>; AXES], axis: usize, i: usize) -> usize {
        if chosen[axis][i] {
            return 0;
        }
        let mut plane = chosen.clone();
        plane[axis] = (0..plane[axis].len()).map(|j| j == i).collect();
        self.product(&plane).len()
    }
}

/// The phi_d node at which the normal is measured, when the candidates start at theta_h 0
/// and hold phi_d 90 deg: the node at 90 deg (see the module documentation). `None` measures
/// the normal at every phi_d.
fn normal_phi_d(nodes_deg: &[Vec<f64>; AXES]) -> Option<usize> {
    let starts_at_the_normal = nodes_deg[0].first().is_some_and(|&h| h.abs() < 1e-9);
    let at_90 = nodes_deg[2].iter().position(|&p| (p - 90.0).abs() < 1e-9);
    at_90.filter(|_| starts_at_the_normal && nodes_deg[2].len() > 1)
}

/// A first design takes theta_h nodes no finer than this many: the recommended grid's theta_h
/// count, every node of its axis ([`CandidateLattice::choose_initial`]).
const FIRST_THETA_H_NODES: usize = GridSpec::recommended().theta_h_samples;

/// Whether each half of phi_d (from its first node to `meeting`, and from there to its last;
/// the whole axis without a meeting node) holds a chosen node strictly between its ends: the
/// interpolation of a half with its ends only is a straight line, which no batch would bend
/// if it never took a phi_d plane.
fn each_half_bends(chosen: &[bool], meeting: Option<usize>) -> bool {
    let last = chosen.len().saturating_sub(1);
    let ends: Vec<usize> = std::iter::once(0)
        .chain(meeting)
        .chain(std::iter::once(last))
        .collect();
    ends.windows(2)
        .all(|w| w[1] <= w[0] + 1 || (w[0] + 1..w[1]).any(|i| chosen[i]))
}

/// Every `stride`-th of `len` nodes, and the last.
fn every(len: usize, stride: usize) -> Vec<bool> {
    (0..len).map(|i| i % stride == 0 || i + 1 == len).collect()
}

/// The strides a first design chooses among (theta_h, theta_d, phi_d), each axis's at most
/// its node count less one (beyond it the stride keeps only the ends).
fn initial_strides(lens: [usize; AXES]) -> Vec<[usize; AXES]> {
    let mut out = Vec::new();
    for h in [1, 2, 3] {
        for d in [1, 2, 3, 4, 6, 8, 12] {
            for p in [1, 2, 3] {
                let stride = [h, d, p];
                if (0..AXES).all(|a| stride[a] == 1 || stride[a] < lens[a]) {
                    out.push(stride);
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn utia() -> Device {
        Device::utia()
    }

    #[test]
    fn the_product_of_the_chosen_nodes_is_what_the_device_reaches() {
        let device = utia();
        let mut lattice = CandidateLattice::new(
            vec![0.0, 1.0, 4.0, 10.0],
            vec![10.0, 30.0, 50.0, 70.0, 85.0],
            vec![0.0, 90.0, 180.0],
            45.0,
            &device,
        );
        lattice.chosen = lattice.nodes_deg.each_ref().map(|n| vec![true; n.len()]);
        let all = lattice.chosen_product();
        let plan = Plan::from_grid(
            &lattice.nodes_deg[0],
            &lattice.nodes_deg[1],
            &lattice.nodes_deg[2],
            45.0,
            &device,
        );
        // The plan's positions, but the normal (theta_h 0) at phi_d 90 deg only.
        let off_the_normal_or_at_90 = plan
            .measured()
            .filter(|(s, _)| s.hd.theta_h > 1e-9 || (s.hd.phi_d.to_degrees() - 90.0).abs() < 1e-6)
            .count();
        assert_eq!(all.len(), off_the_normal_or_at_90);
        assert!(plan.measured().count() > all.len());
        assert!(
            all.len() < 4 * 5 * 3,
            "theta_d 85 is beyond the camera's 75 deg"
        );
    }

    /// At theta_h 0 every phi_d is one configuration: a phi_d plane adds no position there
    /// but at 90 deg, and without phi_d 90 deg among the candidates the normal is measured at
    /// every phi_d.
    #[test]
    fn the_normal_is_measured_at_phi_d_90_only() {
        let device = utia();
        let candidates = |phi_d: Vec<f64>| {
            let mut lattice =
                CandidateLattice::new(vec![0.0, 2.0, 8.0], vec![20.0, 40.0], phi_d, 45.0, &device);
            lattice.chosen = lattice.nodes_deg.each_ref().map(|n| vec![true; n.len()]);
            lattice
        };
        let with_90 = candidates(vec![0.0, 60.0, 90.0, 120.0, 180.0]);
        let at_the_normal = |l: &CandidateLattice| -> Vec<usize> {
            l.chosen_product()
                .iter()
                .filter(|n| n[0] == 0)
                .map(|n| n[2])
                .collect()
        };
        assert_eq!(at_the_normal(&with_90), vec![2, 2]);
        let mut without = with_90.chosen.clone();
        without[2][0] = false;
        assert_eq!(
            with_90.added_by(&without, 2, 0),
            2 * 2,
            "theta_h 2 and 8 deg only"
        );
        let without_90 = candidates(vec![0.0, 60.0, 120.0, 180.0]);
        assert_eq!(at_the_normal(&without_90).len(), 2 * 4);
    }

    #[test]
    fn a_first_design_keeps_every_axis_ends_and_fits_its_budget() {
        let device = utia();
        let theta_d: Vec<f64> = (0..30).map(|i| 1.5 + 3.0 * i as f64).collect();
        let mut lattice = CandidateLattice::new(
            (0..16).map(|i| (i * i) as f64 * 0.2).collect(),
            theta_d,
            vec![0.0, 30.0, 60.0, 90.0, 120.0, 150.0, 180.0],
            45.0,
            &device,
        );
        lattice.choose_initial(400);
        let n = lattice.chosen_product().len();
        assert!(n <= 400 && n > 100, "{n} positions");
        for axis in 0..AXES {
            let c = &lattice.chosen[axis];
            assert!(c[0] && c[c.len() - 1], "axis {axis} keeps its ends");
        }
        assert!(lattice.chosen[2][3], "phi_d 90, where the halves meet");
        let design = lattice.design_text();
        assert!(design.contains(" of 30 theta_d x "), "{design}");
        // Choosing a theta_d node adds one position per reachable (theta_h, phi_d) pair.
        let free = (0..30).find(|&i| !lattice.chosen[1][i]).unwrap();
        let added = lattice.added_by(&lattice.chosen, 1, free);
        assert!(added > 0 && added <= 16 * 7);
        let mut more = lattice.chosen.clone();
        more[1][free] = true;
        let words = lattice.planes_added_by(&more);
        assert_eq!(words, format!("theta_d {} deg", 1.5 + 3.0 * free as f64));
    }

    /// The first design takes every theta_h node (the sampling function's, fitted to the
    /// peak) when a design with all of them fits, however many theta_d planes that leaves to
    /// the batches; with less room every second theta_h node. The largest design alone would
    /// take every third theta_h node and every theta_d one here.
    #[test]
    fn a_first_design_takes_the_finest_theta_h_that_fits() {
        let device = utia();
        let candidates = || {
            CandidateLattice::new(
                (0..16).map(|i| (i * i) as f64 * 0.2).collect(),
                (0..50).map(|i| 1.5 * (1 + i) as f64).collect(),
                (0..7).map(|i| 30.0 * i as f64).collect(),
                45.0,
                &device,
            )
        };
        let count = |chosen: &[bool]| chosen.iter().filter(|&&c| c).count();
        let mut roomy = candidates();
        roomy.choose_initial(800);
        assert_eq!(count(&roomy.chosen[0]), 16, "{}", roomy.design_text());
        assert!(count(&roomy.chosen[1]) < 50, "{}", roomy.design_text());
        assert!(roomy.chosen_product().len() <= 800);
        let mut tight = candidates();
        tight.choose_initial(100);
        let every_second: Vec<bool> = (0..16).map(|i| i % 2 == 0 || i == 15).collect();
        assert_eq!(tight.chosen[0], every_second, "{}", tight.design_text());
        assert!(tight.chosen_product().len() <= 100);
    }

    /// Among the designs with the finest theta_h that fits, one whose halves of phi_d each
    /// hold a plane between their ends comes before a larger one that keeps each half its
    /// ends only (0, 90 and 180 deg): at these budgets the largest design alone keeps three
    /// phi_d planes.
    #[test]
    fn a_first_design_bends_each_half_of_phi_d_before_it_takes_more_theta_d() {
        let device = utia();
        for max_samples in [260, 350, 500] {
            let mut lattice = CandidateLattice::new(
                (0..16).map(|i| (i * i) as f64 * 0.2).collect(),
                (0..25).map(|i| 3.0 * (1 + i) as f64).collect(),
                (0..7).map(|i| 30.0 * i as f64).collect(),
                45.0,
                &device,
            );
            lattice.choose_initial(max_samples);
            let phi_d = &lattice.chosen[2];
            assert!(
                phi_d[1..3].iter().any(|&c| c) && phi_d[4..6].iter().any(|&c| c),
                "{max_samples}: {}",
                lattice.design_text()
            );
        }
        assert!(each_half_bends(
            &[true, false, true, true, false, true, true],
            Some(3)
        ));
        assert!(!each_half_bends(
            &[true, false, false, true, false, true, true],
            Some(3)
        ));
        assert!(each_half_bends(&[true, true], None));
        assert!(!each_half_bends(&[true, false, true], None));
    }

    /// The grid for a peak the instrument does not resolve has 28 theta_h nodes, most of
    /// them within the resolution: the first design takes every second one (15, at most
    /// [`FIRST_THETA_H_NODES`]), not all 28 with fewer theta_d planes.
    #[test]
    fn a_first_design_takes_every_second_theta_h_of_an_unresolved_peak() {
        let device = utia();
        let mut lattice = CandidateLattice::new(
            (0..28).map(|i| (i * i) as f64 * 0.07).collect(),
            (0..30).map(|i| 3.0 * (1 + i) as f64).collect(),
            (0..7).map(|i| 30.0 * i as f64).collect(),
            45.0,
            &device,
        );
        lattice.choose_initial(600);
        assert_eq!(lattice.chosen[0], every(28, 2), "{}", lattice.design_text());
        assert!(lattice.chosen_product().len() <= 600);
    }

    /// Each half of phi_d holds both its ends whatever the stride: with every other node
    /// (0, 60, 120, 180 deg) the first design adds 90 deg; over a quarter (0 to 90 deg) 90 is
    /// the last node anyway.
    #[test]
    fn a_first_design_measures_phi_d_where_the_halves_meet() {
        let device = utia();
        let candidates = |phi_d: Vec<f64>| {
            CandidateLattice::new(
                vec![0.0, 1.0, 4.0, 10.0, 20.0, 40.0],
                (0..20).map(|i| 3.0 + 3.0 * i as f64).collect(),
                phi_d,
                45.0,
                &device,
            )
        };
        for max_samples in [150, 300, 600] {
            let mut half_turn = candidates((0..7).map(|i| 30.0 * i as f64).collect());
            half_turn.choose_initial(max_samples);
            let phi_d = &half_turn.chosen[2];
            assert!(phi_d[0] && phi_d[3] && phi_d[6], "{max_samples}: {phi_d:?}");
            let mut quarter = candidates(vec![0.0, 30.0, 60.0, 90.0]);
            quarter.choose_initial(max_samples);
            assert!(quarter.chosen[2][0] && quarter.chosen[2][3]);
        }
    }
}
