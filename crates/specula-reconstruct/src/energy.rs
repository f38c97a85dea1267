//! Energy conservation of a reconstructed table: its directional albedo, the fraction of the
//! light arriving from one direction that it reflects, `rho(wi) = integral f cos theta_o
//! dwo` ([`MerlBrdf::directional_albedo`]), must stay at most 1 at every incidence.
//!
//! A deblurred table can break it where it is extrapolated: towards grazing incidence, beyond
//! what the device reaches, a lobe continued from the measured theta_d rows can reflect more
//! than arrives (a satin sample's table reached 1.43 at 85 deg, where the device measured
//! nothing). Such a table is scaled down where the excess is: each cell by `1 / rho` at the
//! steeper of its two directions' incidences, `max(theta_i, theta_o)` (rho linear between the
//! checked incidences, the last beyond it; cells whose incidence reflects at most 1 keep
//! their value). Scaling by a symmetric function of the two directions keeps the table
//! reciprocal, and the cells of the incidences that do conserve energy, the measured ones
//! first, are not touched. A cell lowered for one incidence also lowers the albedo of the
//! other incidences it is seen from, so the scaling is repeated until every incidence holds
//! ([`MAX_ROUNDS`]).

use specula_core::merl::{Bin, MerlBrdf};
use specula_core::HalfDiff;

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
        )
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

/// `table` with its directional albedo held to at most 1 (see the module documentation), and
/// how it was scaled; the table unchanged and `None` when it already conserves energy.
pub fn conserve_energy(table: MerlBrdf) -> (MerlBrdf, Option<EnergyScale>) {
    let mut albedo = albedo_per_incidence(&table);
    let (worst, albedo_before) = argmax(&albedo);
    if albedo_before <= HELD_ALBEDO {
        return (table, None);
    }
    let incidence = cell_incidences_deg();
    let mut factors = vec![1.0_f64; incidence.len()];
    let mut scaled = table;
    for _ in 0..MAX_ROUNDS {
        if argmax(&albedo).1 <= HELD_ALBEDO {
            break;
        }
        let round: Vec<f64> = incidence.iter().map(|&t| factor_at(&albedo, t)).collect();
        for (f, r) in factors.iter_mut().zip(&round) {
            *f *= r;
        }
        scaled = MerlBrdf::from_fn(specula_core::Brdf::name(&scaled), |index| {
            scaled.cell(index).map(|v| v * round[index])
        });
        albedo = albedo_per_incidence(&scaled);
    }
    let kept_up_to_deg = incidence
        .iter()
        .zip(&factors)
        .filter(|(_, &f)| f < 1.0)
        .map(|(&t, _)| t)
        .fold(90.0, f64::min);
    let scale = EnergyScale {
        albedo_before,
        incidence_deg: INCIDENCES_DEG[worst],
        albedo_after: argmax(&albedo).1,
        smallest_factor: factors.iter().copied().fold(1.0, f64::min),
        kept_up_to_deg,
    };
    (scaled, Some(scale))
}

/// Each cell's `max(theta_i, theta_o)` at its bin centre (phi_h 0), degrees.
fn cell_incidences_deg() -> Vec<f64> {
    (0..specula_core::merl::CELLS)
        .map(|index| {
            let [h, d, p] = Bin::from_index(index).centre_deg();
            let (wi, wo) = HalfDiff::from_degrees(h, 0.0, d, p).to_directions();
            wi.z.min(wo.z).clamp(-1.0, 1.0).acos().to_degrees()
        })
        .collect()
}

/// A cell's factor for one round: `1 / rho` at its incidence `theta_deg` (linear between
/// [`INCIDENCES_DEG`], the last beyond it), at most 1.
fn factor_at(albedo: &[f64; INCIDENCES_DEG.len()], theta_deg: f64) -> f64 {
    let step = INCIDENCES_DEG[1] - INCIDENCES_DEG[0];
    let at = (theta_deg / step).clamp(0.0, (INCIDENCES_DEG.len() - 1) as f64);
    let lower = at.floor() as usize;
    let upper = (lower + 1).min(INCIDENCES_DEG.len() - 1);
    let t = at - lower as f64;
    let rho = albedo[lower] * (1.0 - t) + albedo[upper] * t;
    (1.0 / rho).min(1.0)
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
        let (kept, none) = conserve_energy(chrome.clone());
        assert!(none.is_none());
        assert_eq!(kept.cell(1000), chrome.cell(1000));
        let bright = MerlBrdf::from_fn("bright", |i| chrome.cell(i).map(|v| v * 3.0));
        let before = max_albedo(&bright);
        assert!(before > 1.5, "{before}");
        let (held, scale) = conserve_energy(bright);
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
        let incidence = cell_incidences_deg();
        let grazing = MerlBrdf::from_fn("grazing", |i| {
            let boost = if incidence[i] > 80.0 { 20.0 } else { 1.0 };
            chrome.cell(i).map(|v| v * boost)
        });
        let before = albedo_per_incidence(&grazing);
        assert!(before[INCIDENCES_DEG.len() - 1] > 1.0, "{before:?}");
        assert!(before[..15].iter().all(|&a| a < 1.0), "{before:?}");
        let (held, scale) = conserve_energy(grazing.clone());
        let scale = scale.expect("scaled");
        assert!(max_albedo(&held) <= HELD_ALBEDO, "{scale}");
        assert!(scale.kept_up_to_deg > 75.0, "{scale}");
        for i in (0..specula_core::merl::CELLS).step_by(97) {
            if incidence[i] <= 75.0 {
                assert_eq!(held.cell(i), grazing.cell(i), "cell {i}");
            }
        }
    }
}
