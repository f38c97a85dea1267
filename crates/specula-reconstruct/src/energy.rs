//! Energy conservation of a reconstructed table: its directional albedo, the fraction of the
//! light arriving from one direction that it reflects, `rho(wi) = integral f cos theta_o
//! dwo` ([`MerlBrdf::directional_albedo`]), must stay at most 1 at every incidence.
//!
//! A deblurred table can break it where it is extrapolated: towards grazing incidence, beyond
//! what the device reaches, a lobe continued from the measured theta_d rows can reflect more
//! than arrives (a satin sample's table reached 1.43 at 85 deg, where the device measured
//! nothing). Such a table is scaled down where the excess is, in two steps, so that what the
//! samples measured is the last thing lowered:
//!
//! 1. **Beyond the samples' reach first.** Only the cells with a direction beyond the samples'
//!    reach are scaled. At an incidence `t` the albedo is the sum of the part `F(t)` of the
//!    cells within the reach, which stay, and the part `S(t)` of those beyond; each cell beyond
//!    takes `g(t) = (1 - F(t)) / S(t)` at the incidence of each of its two directions (the
//!    smaller of the two, so that the table stays reciprocal), which brings `t` to 1 in one
//!    round when nothing else moves. This holds whenever the cells within the reach reflect at
//!    most 1 by themselves, as those of any physical material do. On a neural fit of a white
//!    paint whose grazing lobe reflects 2.3 times what arrives at 85 deg, scaling every cell
//!    seen from beyond 67 deg (the second step alone) lowered the measured cells up to 2.3
//!    times and took the table's relative RMSE within 75 deg from 0.019 to 0.19.
//! 2. **Then every cell**, when the cells within the reach alone reflect more than 1 (the
//!    samples themselves do: a calibration off by that much, or a truth that breaks the law):
//!    each cell by `1 / rho` at the steeper of its two directions' incidences,
//!    `max(theta_i, theta_o)` (rho linear between the checked incidences, the last beyond
//!    it; cells whose incidence reflects at most 1 keep their value). Scaling by a symmetric
//!    function of the two directions keeps the table reciprocal, and the cells of the
//!    incidences that do conserve energy are not touched.
//!
//! A cell lowered for one incidence also lowers the albedo of the other incidence it is seen
//! from, so each step is repeated until every incidence holds ([`MAX_ROUNDS`]).

use specula_core::merl::{Bin, MerlBrdf};
use specula_core::{HalfDiff, Rgb};

/// Incidences at which the albedo is checked and held to 1, degrees.
pub const INCIDENCES_DEG: [f64; 18] = [
    0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0, 55.0, 60.0, 65.0, 70.0, 75.0,
    80.0, 85.0,
];

/// Rounds of scaling at most: a cell's factor also lowers the other incidence it is seen
/// from, so one round may leave a little excess.
const MAX_ROUNDS: usize = 30;

/// The largest directional albedo accepted after scaling: 1 and the quadrature's error
/// ([`MerlBrdf::directional_albedo`] on a table, about 1e-3).
pub const HELD_ALBEDO: f64 = 1.001;

/// How a table was scaled to conserve energy.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnergyScale {
    /// The largest directional albedo before, over channels and [`INCIDENCES_DEG`].
    pub albedo_before: f64,
    /// The incidence where it was, degrees.
    pub incidence_deg: f64,
    /// The largest directional albedo after.
    pub albedo_after: f64,
    /// The smallest factor any cell was scaled by.
    pub smallest_factor: f64,
    /// The steepest incidence, degrees, whose cells kept their values: cells seen from
    /// beyond it were scaled.
    pub kept_up_to_deg: f64,
    /// The largest directional albedo of the cells within the samples' reach alone, the
    /// others taken as zero: above 1 (and [`HELD_ALBEDO`]) the measured cells were lowered
    /// too (see the module documentation).
    pub within_reach_albedo: f64,
}

impl std::fmt::Display for EnergyScale {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "directional albedo {:.3} at {:.0} deg incidence brought to {:.3}: cells seen from beyond {:.1} deg scaled, by down to {:.3}",
            self.albedo_before,
            self.incidence_deg,
            self.albedo_after,
            self.kept_up_to_deg,
            self.smallest_factor
        )?;
        if self.within_reach_albedo > HELD_ALBEDO {
            write!(
                f,
                "; the cells within the samples' reach alone reflect up to {:.3}, more than arrives, so they were lowered too (a calibration off by that much, or a material that breaks the law)",
                self.within_reach_albedo
            )
        } else {
            write!(
                f,
                "; the cells within the samples' reach kept (alone they reflect up to {:.3})",
                self.within_reach_albedo
            )
        }
    }
}

/// The largest directional albedo of `table` over its channels at each of [`INCIDENCES_DEG`].
pub fn albedo_per_incidence(table: &MerlBrdf) -> [f64; INCIDENCES_DEG.len()] {
    INCIDENCES_DEG.map(|t| {
        let a = table.directional_albedo(t);
        a.x.max(a.y).max(a.z)
    })
}

/// The largest directional albedo of `table` over channels and [`INCIDENCES_DEG`].
pub fn max_albedo(table: &MerlBrdf) -> f64 {
    worst_albedo(table).1
}

/// The incidence (degrees, of [`INCIDENCES_DEG`]) at which `table`'s directional albedo is
/// largest over its channels, and that albedo.
pub fn worst_albedo(table: &MerlBrdf) -> (f64, f64) {
    let (worst, albedo) = argmax(&albedo_per_incidence(table));
    (INCIDENCES_DEG[worst], albedo)
}

/// `table` with its directional albedo held to at most 1, the cells with a direction beyond
/// `reach_deg` (degrees from the normal) lowered first (see the module documentation), and
/// how it was scaled; the table unchanged and `None` when it already conserves energy.
pub fn conserve_energy(table: MerlBrdf, reach_deg: f64) -> (MerlBrdf, Option<EnergyScale>) {
    let albedo = albedo_per_incidence(&table);
    let (worst, albedo_before) = argmax(&albedo);
    if albedo_before <= HELD_ALBEDO {
        return (table, None);
    }
    let cells = cell_incidences();
    let mut factors = vec![1.0_f64; cells.len()];
    let beyond: Vec<bool> = cells.iter().map(|c| c.steeper_deg > reach_deg).collect();
    let within = within_reach_albedo(&table, &beyond);
    let (table, albedo) = beyond_reach_first(table, albedo, &cells, &beyond, &within, &mut factors);
    let (table, albedo) = every_cell(table, albedo, &cells, &mut factors);
    let kept_up_to_deg = cells
        .iter()
        .zip(&factors)
        .filter(|(_, &f)| f < 1.0)
        .map(|(c, _)| c.steeper_deg)
        .fold(90.0, f64::min);
    let scale = EnergyScale {
        albedo_before,
        incidence_deg: INCIDENCES_DEG[worst],
        albedo_after: argmax(&albedo).1,
        smallest_factor: factors.iter().copied().fold(1.0, f64::min),
        kept_up_to_deg,
        within_reach_albedo: argmax(&within).1,
    };
    (table, Some(scale))
}

/// The incidences of a cell's two directions at its bin centre (phi_h 0), degrees.
#[derive(Debug, Clone, Copy)]
struct CellIncidence {
    steeper_deg: f64,
    shallower_deg: f64,
}

/// Each cell's [`CellIncidence`].
fn cell_incidences() -> Vec<CellIncidence> {
    (0..specula_core::merl::CELLS)
        .map(|index| {
            let [h, d, p] = Bin::from_index(index).centre_deg();
            let (wi, wo) = HalfDiff::from_degrees(h, 0.0, d, p).to_directions();
            let deg = |z: f64| z.clamp(-1.0, 1.0).acos().to_degrees();
            CellIncidence {
                steeper_deg: deg(wi.z.min(wo.z)),
                shallower_deg: deg(wi.z.max(wo.z)),
            }
        })
        .collect()
}

/// The albedo per incidence of `table`'s cells within the reach alone (`F` of the module
/// documentation), the cells `beyond` it taken as zero.
fn within_reach_albedo(table: &MerlBrdf, beyond: &[bool]) -> [f64; INCIDENCES_DEG.len()] {
    albedo_per_incidence(&MerlBrdf::from_fn("within the reach", |index| {
        let value = table.cell(index);
        if beyond[index] {
            value.map(|_| Rgb::ZERO)
        } else {
            value
        }
    }))
}

/// Step 1 of the module documentation: `table` with the cells `beyond` the reach lowered
/// until every incidence holds, and its albedo per incidence, given the albedo of the cells
/// `within` the reach alone; unchanged when those reflect more than [`HELD_ALBEDO`]. Each
/// cell's factor is multiplied into `factors`.
fn beyond_reach_first(
    table: MerlBrdf,
    albedo: [f64; INCIDENCES_DEG.len()],
    cells: &[CellIncidence],
    beyond: &[bool],
    within: &[f64; INCIDENCES_DEG.len()],
    factors: &mut [f64],
) -> (MerlBrdf, [f64; INCIDENCES_DEG.len()]) {
    if argmax(within).1 > HELD_ALBEDO {
        return (table, albedo);
    }
    scaled_in_rounds(table, albedo, factors, |albedo| {
        // g(t) of the module documentation: the share of the cells beyond that brings t to 1.
        let share: Vec<f64> = albedo
            .iter()
            .zip(within)
            .map(|(&all, &within)| {
                if all <= HELD_ALBEDO || all <= within {
                    1.0
                } else {
                    ((1.0 - within) / (all - within)).clamp(0.0, 1.0)
                }
            })
            .collect();
        cells
            .iter()
            .zip(beyond)
            .map(|(c, &beyond)| {
                if beyond {
                    interpolated(&share, c.steeper_deg).min(interpolated(&share, c.shallower_deg))
                } else {
                    1.0
                }
            })
            .collect()
    })
}

/// Step 2 of the module documentation: every cell by `1 / rho` at its steeper incidence,
/// until every incidence holds. Each cell's factor is multiplied into `factors`.
fn every_cell(
    table: MerlBrdf,
    albedo: [f64; INCIDENCES_DEG.len()],
    cells: &[CellIncidence],
    factors: &mut [f64],
) -> (MerlBrdf, [f64; INCIDENCES_DEG.len()]) {
    scaled_in_rounds(table, albedo, factors, |albedo| {
        cells
            .iter()
            .map(|c| (1.0 / interpolated(albedo, c.steeper_deg)).min(1.0))
            .collect()
    })
}

/// `table` scaled round after round, each cell by its factor of `round_factors(albedo)`, the
/// albedo per incidence before the round, until every incidence holds or [`MAX_ROUNDS`] have
/// passed.
fn scaled_in_rounds(
    mut table: MerlBrdf,
    mut albedo: [f64; INCIDENCES_DEG.len()],
    factors: &mut [f64],
    round_factors: impl Fn(&[f64; INCIDENCES_DEG.len()]) -> Vec<f64>,
) -> (MerlBrdf, [f64; INCIDENCES_DEG.len()]) {
    for _ in 0..MAX_ROUNDS {
        if argmax(&albedo).1 <= HELD_ALBEDO {
            break;
        }
        let round = round_factors(&albedo);
        for (f, r) in factors.iter_mut().zip(&round) {
            *f *= r;
        }
        table = MerlBrdf::from_fn(specula_core::Brdf::name(&table), |index| {
            table.cell(index).map(|v| v * round[index])
        });
        albedo = albedo_per_incidence(&table);
    }
    (table, albedo)
}

/// `values` given at [`INCIDENCES_DEG`] at `theta_deg`: linear between them, the last
/// beyond it.
fn interpolated(values: &[f64], theta_deg: f64) -> f64 {
    let step = INCIDENCES_DEG[1] - INCIDENCES_DEG[0];
    let at = (theta_deg / step).clamp(0.0, (INCIDENCES_DEG.len() - 1) as f64);
    let lower = at.floor() as usize;
    let upper = (lower + 1).min(INCIDENCES_DEG.len() - 1);
    let t = at - lower as f64;
    values[lower] * (1.0 - t) + values[upper] * t
}

/// The index and value of the largest entry.
fn argmax(values: &[f64]) -> (usize, f64) {
    values
        .iter()
        .copied()
        .enumerate()
        .fold((0, f64::NEG_INFINITY), |best, (i, v)| {
            if v > best.1 {
                (i, v)
            } else {
                best
            }
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::materials::preset;
    use specula_core::tabulate::tabulate;

    #[test]
    fn a_table_that_reflects_more_than_arrives_is_scaled_to_one_and_one_that_does_not_is_kept() {
        // Chrome's table conserves energy and comes back as it was. The same table three
        // times as bright reflects up to about twice what arrives: after scaling, every
        // checked incidence is within 1, no cell lowered by more than five times.
        let chrome = tabulate(&preset("chrome").unwrap(), 0.0);
        let (kept, none) = conserve_energy(chrome.clone(), 75.0);
        assert!(none.is_none());
        assert_eq!(kept.cell(1000), chrome.cell(1000));
        let bright = MerlBrdf::from_fn("bright", |i| chrome.cell(i).map(|v| v * 3.0));
        let before = max_albedo(&bright);
        assert!(before > 1.5, "{before}");
        let (held, scale) = conserve_energy(bright, 75.0);
        let scale = scale.expect("scaled");
        assert!(max_albedo(&held) <= HELD_ALBEDO, "{scale}");
        assert!((scale.albedo_after - max_albedo(&held)).abs() < 1e-12);
        assert!(
            scale.smallest_factor > 0.2 && scale.smallest_factor < 1.0 / 1.5,
            "{scale}"
        );
    }

    #[test]
    fn an_excess_at_grazing_is_taken_from_the_grazing_cells_alone() {
        // Chrome with every cell seen from beyond 80 deg made twenty times brighter: the
        // albedo breaks 1 at 85 deg only. After scaling every incidence holds, and the cells
        // seen from within 75 deg on both sides keep their values exactly.
        let chrome = tabulate(&preset("chrome").unwrap(), 0.0);
        let incidence: Vec<f64> = cell_incidences().iter().map(|c| c.steeper_deg).collect();
        let grazing = MerlBrdf::from_fn("grazing", |i| {
            let boost = if incidence[i] > 80.0 { 20.0 } else { 1.0 };
            chrome.cell(i).map(|v| v * boost)
        });
        let before = albedo_per_incidence(&grazing);
        assert!(before[INCIDENCES_DEG.len() - 1] > 1.0, "{before:?}");
        assert!(before[..15].iter().all(|&a| a < 1.0), "{before:?}");
        let (held, scale) = conserve_energy(grazing.clone(), 75.0);
        let scale = scale.expect("scaled");
        assert!(max_albedo(&held) <= HELD_ALBEDO, "{scale}");
        assert!(scale.kept_up_to_deg > 75.0, "{scale}");
        for i in (0..specula_core::merl::CELLS).step_by(97) {
            if incidence[i] <= 75.0 {
                assert_eq!(held.cell(i), grazing.cell(i), "cell {i}");
            }
        }
    }

    /// A Lambertian table of albedo `albedo` whose cells with a direction beyond `reach_deg`
    /// are `boost` times as bright, and each cell's steeper incidence.
    fn lambertian_with_bright_grazing(
        albedo: f64,
        reach_deg: f64,
        boost: f64,
    ) -> (MerlBrdf, Vec<f64>) {
        let steeper: Vec<f64> = cell_incidences().iter().map(|c| c.steeper_deg).collect();
        let value = albedo / std::f64::consts::PI;
        let table = MerlBrdf::from_fn("lambertian", |i| {
            let boost = if steeper[i] > reach_deg { boost } else { 1.0 };
            Some(Rgb::splat(value * boost))
        });
        (table, steeper)
    }

    #[test]
    fn the_cells_beyond_the_reach_take_the_excess_of_an_incidence_within_it() {
        // A white Lambertian (albedo 0.8) whose cells with a direction beyond 76 deg are ten
        // times as bright: at 70 deg incidence the 6 % of the projected hemisphere beyond 76
        // deg (cos^2 76 deg) adds 0.47 to the 0.75 the rest reflects, 1.2 in all. The cells
        // within the reach reflect at most 0.8 by themselves, so they keep their values
        // exactly and every incidence holds. Scaling every cell by the albedo at its steeper
        // incidence (a reach of 90 deg: nothing beyond it) lowers cells within 76 deg too.
        let reach = 76.0;
        let (table, steeper) = lambertian_with_bright_grazing(0.8, reach, 10.0);
        let before = albedo_per_incidence(&table);
        assert!(before[14] > 1.1, "70 deg: {}", before[14]);
        let (held, scale) = conserve_energy(table.clone(), reach);
        let scale = scale.expect("scaled");
        assert!(max_albedo(&held) <= HELD_ALBEDO, "{scale}");
        assert!(scale.kept_up_to_deg > reach, "{scale}");
        assert!(scale.within_reach_albedo < 0.81, "{scale}");
        assert!(
            scale.to_string().contains("within the samples' reach kept"),
            "{scale}"
        );
        let within: Vec<usize> = (0..specula_core::merl::CELLS)
            .filter(|&i| steeper[i] <= reach)
            .collect();
        assert!(within.iter().all(|&i| held.cell(i) == table.cell(i)));
        let (everywhere, scale) = conserve_energy(table.clone(), 90.0);
        let scale = scale.expect("scaled");
        assert!(max_albedo(&everywhere) <= HELD_ALBEDO, "{scale}");
        assert!(scale.kept_up_to_deg < reach, "{scale}");
        let lowered = within
            .iter()
            .filter(|&&i| everywhere.cell(i).unwrap().x < table.cell(i).unwrap().x)
            .count();
        assert!(
            lowered > within.len() / 100,
            "{lowered} of {}",
            within.len()
        );
    }

    #[test]
    fn cells_within_the_reach_that_reflect_more_than_arrives_are_lowered_as_well() {
        // A Lambertian of albedo 1.3 breaks the law within the reach by itself: nothing
        // beyond it can take the excess, so every cell is scaled and every incidence holds,
        // the cells within the reach by up to 1 / 1.3.
        let reach = 76.0;
        let (table, steeper) = lambertian_with_bright_grazing(1.3, reach, 1.0);
        let (held, scale) = conserve_energy(table.clone(), reach);
        let scale = scale.expect("scaled");
        assert!(max_albedo(&held) <= HELD_ALBEDO, "{scale}");
        let i = (0..specula_core::merl::CELLS)
            .find(|&i| steeper[i] < 30.0)
            .unwrap();
        assert!(scale.within_reach_albedo > 1.2, "{scale}");
        assert!(scale.to_string().contains("lowered too"), "{scale}");
        let ratio = held.cell(i).unwrap().x / table.cell(i).unwrap().x;
        assert!(ratio < 0.8 && ratio > 0.7, "{ratio}");
    }
}
