//! A deblurred table is checked against the samples it was made from before anyone trusts
//! it, and where it fails, the data's own un-deblurred values take its place.
//!
//! Deblurring divides out the instrument's response, and a response blurs: a spike narrower
//! than the light's disk changes what the instrument records hardly at all, so a table can
//! match the samples in its fit and still hold a feature the samples never saw. Two checks
//! catch what the fit cannot:
//!
//! 1. **Consistency** ([`crate::consistency`]): the table, blurred by the response, must
//!    reproduce every sample within its uncertainty. The uncertainty of a prediction is
//!    `u = sqrt(u_pos^2 + u_rep^2 + (r S)^2)`: the device's angular positioning through the
//!    local slope ([`crate::consistency::positioning_uncertainty`], of the fitted lobe's
//!    table, which invents nothing), the table's binning of the fitted lobe under the
//!    response (`|P_lobe table - M_lobe|`: what a table of MERL bins loses of a sharp peak
//!    however right it is) and a relative floor `r` = [`RELATIVE_FLOOR`] for the binning of
//!    the material's departure from the lobe. The normalised chi-square is reported; a region
//!    fails when its reproduction error exceeds [`FAIL_FACTOR`] times the one its
//!    uncertainties explain (`sqrt(sum u^2 / sum S^2)`): weighted by the signal, so that a
//!    few samples of tiny uncertainty on a dark flank cannot decide alone.
//! 2. **Energy**: the table's directional albedo ([`MerlBrdf::directional_albedo`]) must stay
//!    at most 1 (plus the quadrature's [`ALBEDO_TOLERANCE`]) at every incidence; an invented
//!    spike breaks it first.
//!
//! Where either fails, the table is reconstructed again without the response (the samples
//! as measured, blur and all) and its cells below the failing region's upper theta_h take
//! the deblurred ones' place when they reproduce the samples of every region there better
//! (lower reproduction error). The summary says so: a bound at the instrument's resolution,
//! not a resolved peak.
//!
//! Where they do not, and the fitted lobe's peak is too narrow for the captures to tell its
//! width from zero ([`width_detection_limit_deg`]), the data cannot decide the peak's
//! height: such a peak changes the captures hardly at all (the blur's null space), and the
//! lobe's family chose its width. Whether that choice is worth keeping is decided where the
//! captures do see the shape, on the flank (beyond the peak region, within the blur's
//! reach): when the deblurred table reproduces the flank's samples, the lobe describes the
//! material as far as the instrument resolves it, and its peak, the continuation of that
//! shape, stays (the summary says the check failed and the peak is not a measurement),
//! unless the peak region misses its own samples by more than [`REFUTED_FACTOR`] times what
//! its uncertainties explain: such a peak is refuted by the samples, not merely unconfirmed.
//! When the flank fails too, or the peak is refuted, its peak is bounded instead. The
//! un-deblurred value is then a lower bound of the peak (the blur spreads it over the
//! resolution) and the deblurred one the height the lobe's shape would give. Below the peak
//! region's upper theta_h the table holds their geometric mean, which is off by at most
//! half the bounds' log ratio wherever the truth lies between them (the log-error minimax
//! of the interval), and the summary gives the bounds at the highest cell. Elsewhere the
//! deblurred table stays and the summary says which check it failed.
//!
//! A deblurred table that passes both checks can still hold a peak nothing in the data asks
//! for: on a near-diffuse fabric the lobe family fits a spike of half width 0.04 deg on top
//! of the body, which the captures cannot see and which puts 13 % into the first theta_h
//! bins. When the un-deblurred table, blurred by the response, reproduces every region's
//! samples within what their uncertainties explain (not merely within [`FAIL_FACTOR`] times
//! it), the deblurring adds only what the instrument cannot see, and the un-deblurred values
//! take its place below the peak region's upper theta_h, whatever the fitted lobe's width:
//! on a neural fit of a polyurethane foam the lobe's spike was 0.28 deg wide, just above
//! what the captures can tell from zero ([`width_detection_limit_deg`]), and kept it made
//! the table's relative RMSE 0.00066 against 0.00045 with the un-deblurred values (the
//! summary then also names the width). On a sharp peak they cannot: blurred once more, the
//! measured peak falls well below its samples.
//!
//! One more check needs no samples: at theta_h 0 every phi_d names one configuration
//! ([`NormalSpread`]), and the halves of phi_d are reconstructed apart
//! ([`crate::phi_d_halves`]). When the kept table varies there by more than
//! [`NORMAL_SPREAD_LIMIT`], one half holds a peak that the other half's samples, at the same
//! configurations, do not: on a flat-topped silk the first half's lobe put three times the
//! material's value at the normal while the second half's held it. The half whose
//! un-deblurred values bring the spread within the limit takes them ([`NormalFallback`]), up
//! to the upper theta_h of the region whose samples the table failed (the peak region's when
//! none did), or through the flank when that reproduces the samples better: a lobe that
//! invents a peak at the normal can hold its tails beyond the peak region (a neural fit of a
//! measured silk, measured on other planes than the default design takes, put 606 times the
//! other half's value there: 0.038 relative RMSE with the peak region replaced, 0.031 through
//! the flank). When neither half's alone do, both halves' lobes are off at the normal, each
//! its own way (on a neural fit of a measured material the deblurred table held five times
//! the truth's peak in one half and varied 4.2 times over phi_d there, while the un-deblurred
//! table varied 1.02 times), and both halves take them if that restores the identity; where
//! even that does not, the table stays and the summary says the identity fails. Two more
//! cases keep the table as it is, and the summary says why: a peak the checks bounded, whose
//! height is undecided between its bounds and so is its spread over phi_d (the fallback would
//! put the lower bound in its place: neural fits of measured paints vary 1.6 to 13 times over
//! phi_d at the normal themselves, and on two of them the lower bound took a table from 0.62
//! and 0.51 relative RMSE to 0.83 and 0.91); and a fallback that reproduces the samples worse
//! than the table it would replace, since then the samples see what it would remove (on a
//! third, 24.9 % against 7.7 %; kept, its table scores 0.94 relative RMSE against 0.98).
//!
//! Whatever table is kept, its directional albedo is then held to 1
//! ([`energy::conserve_energy`]): a fallback removes an invented spike, but a lobe continued
//! towards grazing incidence, where the device does not reach, can still reflect more than
//! arrives, and such a table is scaled down where it does, beyond the samples' reach first.

use crate::consistency::{self, Consistency, Instrument, NormalSpread, NORMAL_SPREAD_LIMIT};
use crate::energy::{self, max_albedo, EnergyScale};
use crate::lobe::{Lobe, LobeOnGrid, BLUR_THETA_H_DEG};
use crate::phi_d_halves::in_second;
use crate::response_nodes::FIT_RESPONSE_NODES;
use crate::sample::reach_deg;
use crate::uncertainty::REACH_MARGIN_DEG;
use specula_core::capture::{CaptureNode, CaptureResponse};
use specula_core::merl::{Bin, MerlBrdf};
use specula_core::{Rgb, Sample};

/// A region fails when its reproduction error exceeds this many times the one its
/// uncertainties explain.
pub const FAIL_FACTOR: f64 = 3.0;

/// A peak region whose reproduction error exceeds this many times the one its uncertainties
/// explain is refuted by its samples: an unresolved peak is then bounded even where the lobe
/// reproduces the flank (see the module documentation). Twice [`FAIL_FACTOR`]: on the
/// clear coat and the metal whose kept peaks were right the peak missed by 3.5 times, on a
/// phenolic whose kept peak was twice the paper's way's error by 9.3 times.
pub const REFUTED_FACTOR: f64 = 2.0 * FAIL_FACTOR;

/// The relative floor of a prediction's uncertainty (see the module documentation).
pub const RELATIVE_FLOOR: f64 = 0.01;

/// The largest directional albedo accepted as energy conserving: 1 plus the quadrature's
/// error on a table ([`MerlBrdf::directional_albedo`]).
pub const ALBEDO_TOLERANCE: f64 = 1.02;

/// What the checks found of a deblurred table (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct Safeguard {
    /// The figures of the table returned.
    pub consistency: Consistency,
    /// The deblurred table's figures, when part of it was replaced.
    pub deblurred: Option<Consistency>,
    /// Cells with theta_h below this (degrees) hold the un-deblurred reconstruction.
    pub fallback_below_deg: Option<f64>,
    /// Cells with theta_h below this (degrees) hold the geometric mean of the deblurred and
    /// the un-deblurred values: the peak's height is bounded, not measured (see the module
    /// documentation).
    pub bounded_below_deg: Option<f64>,
    /// Why the fallback was taken, in words.
    pub reason: Option<String>,
    /// The largest directional albedo of the table returned, over the channels and
    /// [`energy::INCIDENCES_DEG`].
    pub max_albedo: f64,
    /// How the table was scaled to conserve energy ([`energy::conserve_energy`]), if it was.
    pub energy: Option<EnergyScale>,
    /// What the identity at the normal did to the table (see the module documentation).
    pub at_normal: AtNormal,
}

/// What the identity at the normal did to a deblurred table (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub enum AtNormal {
    /// Nothing: the table holds the identity, or no half's un-deblurred values restore it.
    Untouched,
    /// A half of phi_d (or both) took the un-deblurred values to restore it.
    Restored(NormalFallback),
    /// The table breaks it and stays as it is, though the un-deblurred values would restore
    /// it: why, in words.
    Kept(String),
}

impl AtNormal {
    /// The halves that took the un-deblurred values, if any did.
    pub fn restored(&self) -> Option<&NormalFallback> {
        match self {
            AtNormal::Restored(fallback) => Some(fallback),
            AtNormal::Untouched | AtNormal::Kept(_) => None,
        }
    }
}

/// The halves of phi_d whose cells below `below_deg` in theta_h hold the un-deblurred values
/// because the deblurred table broke the identity at the normal ([`NormalSpread`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalFallback {
    /// Which half, or both.
    pub halves: Halves,
    /// Cells with theta_h below this (degrees) were replaced in that half.
    pub below_deg: f64,
    /// The deblurred table's spread, which the fallback removed.
    pub before: NormalSpread,
    /// The spread of the table returned.
    pub after: NormalSpread,
}

/// One half of phi_d or both ([`crate::phi_d_halves`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Halves {
    /// `[0, 90)` deg.
    First,
    /// `[90, 180)` deg.
    Second,
    /// Both.
    Both,
}

impl Halves {
    /// Whether cell `index` lies in these halves.
    fn hold(self, index: usize) -> bool {
        match self {
            Halves::First => !in_second(index),
            Halves::Second => in_second(index),
            Halves::Both => true,
        }
    }
}

impl std::fmt::Display for Halves {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Halves::First => "0-90",
            Halves::Second => "90-180",
            Halves::Both => "0-180",
        })
    }
}

impl std::fmt::Display for NormalFallback {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let half = self.halves;
        write!(
            f,
            "theta_h below {:.2} deg of phi_d {half} deg holds the un-deblurred values: the deblurred table varied {:.3}x over phi_d at theta_h 0 (theta_d {:.1} deg), where every phi_d is one configuration; now {:.3}x",
            self.below_deg, self.before.ratio, self.before.theta_d_deg, self.after.ratio
        )
    }
}

impl Safeguard {
    /// Below which theta_h (degrees) the samples do not decide the deblurred table, as the
    /// uncertainty's deblurring term takes it ([`crate::uncertainty`]): the peak region,
    /// where a blurred table reproduces the samples whatever lies within the resolution;
    /// beyond it each region whose samples the deblurred table fails ([`region_failure`]:
    /// the flank up to [`crate::lobe::BLUR_THETA_H_DEG`], the body everywhere); and every
    /// cell the safeguard replaced.
    pub fn undecided_below_deg(&self) -> f64 {
        let checked = self.deblurred.as_ref().unwrap_or(&self.consistency);
        let fails = |name: &str| region_failure(checked, name).is_some();
        let checked_below = if fails("body") {
            f64::INFINITY
        } else if fails("flank") {
            crate::lobe::BLUR_THETA_H_DEG
        } else {
            checked.peak_limit_deg
        };
        [
            self.fallback_below_deg,
            self.bounded_below_deg,
            self.at_normal.restored().map(|n| n.below_deg),
        ]
        .into_iter()
        .flatten()
        .fold(checked_below, f64::max)
    }

    /// True when the deblurred table failed a check or was not asked for by the data
    /// (whether or not it was replaced).
    pub fn failed(&self) -> bool {
        self.reason.is_some() || self.at_normal.restored().is_some()
    }

    /// The summary's lines: the consistency per region, the albedo and any fallback.
    pub fn lines(&self) -> Vec<String> {
        let mut lines = self.consistency.lines();
        lines.push(format!("max_directional_albedo={:.4}", self.max_albedo));
        if let Some(scale) = &self.energy {
            lines.push(format!("energy_conserved={scale}"));
        }
        lines.push(match (self.fallback_below_deg, self.bounded_below_deg, &self.reason) {
            (Some(limit), _, Some(reason)) => format!(
                "deblur_fallback=theta_h below {limit:.2} deg holds the un-deblurred values ({reason})"
            ),
            (None, Some(limit), Some(reason)) => format!(
                "deblur_fallback=theta_h below {limit:.2} deg holds the geometric mean of the deblurred and the un-deblurred values, a bounded peak ({reason})"
            ),
            (None, None, Some(reason)) => format!("deblur_fallback=none, check failed: {reason}"),
            _ if self.at_normal.restored().is_some() => {
                "deblur_fallback=none beyond one half of phi_d: the samples' checks passed, the identity at the normal did not".into()
            }
            _ => "deblur_fallback=none, checks passed".into(),
        });
        match &self.at_normal {
            AtNormal::Restored(normal) => lines.push(format!("deblur_fallback_normal={normal}")),
            AtNormal::Kept(why) => lines.push(format!("deblur_fallback_normal=none: {why}")),
            AtNormal::Untouched => {}
        }
        if let Some(d) = &self.deblurred {
            lines.extend(d.lines().into_iter().map(|l| format!("deblurred_{l}")));
        }
        lines
    }
}

/// Checks the `deblurred` table (made through `response` from `samples`, with its fitted
/// `lobe`) and falls back per region to the `plain` table (made without the response, which
/// every path of the checks compares with) where it fails,
/// and per half of phi_d where it breaks the identity at the normal (see the module
/// documentation), then holds the kept table's directional albedo to 1
/// ([`energy::conserve_energy`]): the table to keep, what the checks found and, when its
/// cells were replaced, the deblurred table itself.
pub(crate) fn safeguarded<R: CaptureResponse + ?Sized>(
    samples: &[Sample],
    deblurred: MerlBrdf,
    lobe: Option<&Lobe>,
    response: &R,
    plain: &MerlBrdf,
) -> (MerlBrdf, Safeguard, Option<MerlBrdf>) {
    let nodes = response.capture_nodes(FIT_RESPONSE_NODES);
    let checks = Checks {
        samples,
        u: prediction_uncertainty(samples, lobe, &deblurred, &nodes),
        instrument: Instrument {
            nodes: &nodes,
            resolution_deg: Some(response.resolution_deg()),
        },
    };
    let undetected = Undetected::of(lobe, response.resolution_deg());
    let (kept, guard, replaced) = checked(&checks, deblurred, undetected, plain);
    let (kept, mut guard, replaced) = if guard.consistency.normal_spread.ratio > NORMAL_SPREAD_LIMIT
    {
        normal_restored(&checks, kept, guard, replaced, plain)
    } else {
        (kept, guard, replaced)
    };
    // The checks measured the kept table's albedo at the same incidences: only a table that
    // breaks 1 is integrated again.
    if guard.max_albedo <= energy::HELD_ALBEDO {
        return (kept, guard, replaced);
    }
    let reach = reach_deg(samples) + REACH_MARGIN_DEG;
    let (kept, scale) = energy::conserve_energy(kept, reach);
    if let Some(scale) = &scale {
        guard.max_albedo = scale.albedo_after;
    }
    guard.energy = scale;
    (kept, guard, replaced)
}

/// The samples a table is checked against, their predictions' standard uncertainties and the
/// instrument that predicts them.
struct Checks<'a> {
    samples: &'a [Sample],
    u: Vec<Rgb>,
    instrument: Instrument<'a>,
}

impl Checks<'_> {
    /// How well `table` reproduces the samples ([`Consistency::check`]).
    fn of(&self, table: &MerlBrdf) -> Consistency {
        Consistency::check(self.samples, &self.u, table, self.instrument)
    }
}

/// [`safeguarded`] before the identity at the normal and the energy: the checks against the
/// samples and the fallback.
fn checked(
    checks: &Checks<'_>,
    deblurred: MerlBrdf,
    undetected: Option<Undetected>,
    plain: &MerlBrdf,
) -> (MerlBrdf, Safeguard, Option<MerlBrdf>) {
    let check = checks.of(&deblurred);
    let albedo = max_albedo(&deblurred);
    let Some((limit_deg, reason)) = failure(&check, albedo) else {
        if reproduces_within_uncertainty(&checks.of(plain)) {
            let (kept, guard) = unasked(checks, &deblurred, check, plain, undetected);
            return (kept, guard, Some(deblurred));
        }
        let passed = Safeguard {
            consistency: check,
            deblurred: None,
            fallback_below_deg: None,
            bounded_below_deg: None,
            reason: None,
            max_albedo: albedo,
            energy: None,
            at_normal: AtNormal::Untouched,
        };
        return (deblurred, passed, None);
    };
    let merged = replaced_below(&deblurred, plain, limit_deg);
    let merged_check = checks.of(&merged);
    let merged_albedo = max_albedo(&merged);
    if !fits_better(&merged_check, &check, limit_deg) {
        let flank_failed = region_failure(&check, "flank").is_some();
        let refuted = check
            .region("peak")
            .is_some_and(|r| r.misses_by(REFUTED_FACTOR));
        if let Some(undetected) = undetected.filter(|_| flank_failed || refuted) {
            let limit_deg = check.peak_limit_deg;
            let bounds = PeakBounds::of(&deblurred, plain, limit_deg);
            let bounded = geometric_mean_below(&deblurred, plain, limit_deg);
            let bounded_check = checks.of(&bounded);
            let guard = Safeguard {
                max_albedo: max_albedo(&bounded),
                energy: None,
                at_normal: AtNormal::Untouched,
                consistency: bounded_check,
                deblurred: Some(check),
                fallback_below_deg: None,
                bounded_below_deg: Some(limit_deg),
                reason: Some(format!(
                    "{reason}; the un-deblurred values reproduce the samples no better, and {undetected}: {bounds}"
                )),
            };
            return (bounded, guard, Some(deblurred));
        }
        let why_kept = match undetected {
            Some(undetected) => format!("{undetected}, but the lobe reproduces the flank they resolve, so its peak stays as that shape's continuation"),
            None => "so the deblurred ones stay".into(),
        };
        let kept = Safeguard {
            consistency: check,
            deblurred: None,
            fallback_below_deg: None,
            bounded_below_deg: None,
            reason: Some(format!(
                "{reason}; the un-deblurred values reproduce the samples no better; {why_kept}"
            )),
            max_albedo: albedo,
            energy: None,
            at_normal: AtNormal::Untouched,
        };
        return (deblurred, kept, None);
    }
    let replaced = Safeguard {
        consistency: merged_check,
        deblurred: Some(check),
        fallback_below_deg: Some(limit_deg),
        bounded_below_deg: None,
        reason: Some(reason),
        max_albedo: merged_albedo,
        energy: None,
        at_normal: AtNormal::Untouched,
    };
    (merged, replaced, Some(deblurred))
}

/// The standard uncertainty of each sample's prediction (see the module documentation):
/// positioning and the lobe table's binning from the fitted `lobe` when there is one, else
/// the positioning through `table` itself; and the relative floor.
fn prediction_uncertainty(
    samples: &[Sample],
    lobe: Option<&Lobe>,
    table: &MerlBrdf,
    nodes: &[CaptureNode],
) -> Vec<Rgb> {
    let floor = |s: &Sample| s.value.abs() * RELATIVE_FLOOR;
    let Some(lobe) = lobe else {
        let positioning = consistency::positioning_uncertainty(samples, table, nodes);
        return samples
            .iter()
            .zip(positioning)
            .map(|(s, p)| quadrature_sum(&[p, floor(s)]))
            .collect();
    };
    let on_grid = LobeOnGrid::new(*lobe);
    let lobe_table = MerlBrdf::from_fn("lobe", |index| Some(on_grid.at(index)));
    let positioning = consistency::positioning_uncertainty(samples, &lobe_table, nodes);
    let representation =
        consistency::LobeCaptures::of(samples, lobe, &lobe_table, nodes).representation_error();
    samples
        .iter()
        .zip(positioning)
        .zip(representation)
        .map(|((s, p), r)| quadrature_sum(&[p, r.abs(), floor(s)]))
        .collect()
}

/// The narrowest peak half width (degrees, in theta_h) the captures can tell from an
/// infinitely narrow one, through a response of `resolution_deg`: half widths add in
/// quadrature under a blur, `sqrt(R^2 + w^2)`, so a peak of half width `w` widens what the
/// device records by more than its angular positioning accuracy `a`
/// ([`consistency::POSITIONING_ACCURACY_DEG`]) only when `w > sqrt(2 a R + a^2)`: 0.26 deg
/// for the default device's 1.09 deg resolution and 0.03 deg accuracy. A narrower fitted
/// width is the lobe family's choice, not the data's.
pub fn width_detection_limit_deg(resolution_deg: f64) -> f64 {
    let a = consistency::POSITIONING_ACCURACY_DEG;
    (2.0 * a * resolution_deg + a * a).sqrt()
}

/// A fitted lobe's peak narrower than the captures can tell from zero
/// ([`width_detection_limit_deg`]).
#[derive(Debug, Clone, Copy)]
struct Undetected {
    half_width_deg: f64,
    limit_deg: f64,
}

impl Undetected {
    /// Of the fitted `lobe` through a response of `resolution_deg`; `None` when its peak is
    /// wide enough to be told from zero.
    fn of(lobe: Option<&Lobe>, resolution_deg: f64) -> Option<Self> {
        let limit_deg = width_detection_limit_deg(resolution_deg);
        lobe.map(|l| l.shape.half_width_deg())
            .filter(|&w| w < limit_deg)
            .map(|half_width_deg| Self {
                half_width_deg,
                limit_deg,
            })
    }
}

impl std::fmt::Display for Undetected {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the lobe's half width {:.3} deg is below the {:.3} deg the captures can tell from zero",
            self.half_width_deg, self.limit_deg
        )
    }
}

/// The `deblurred` table (which passed its `check`) with the un-deblurred `plain` values
/// below the peak region's upper theta_h, where nothing in the data asks for its
/// `undetected` peak (see the module documentation), and what the checks found.
fn unasked(
    checks: &Checks<'_>,
    deblurred: &MerlBrdf,
    check: Consistency,
    plain: &MerlBrdf,
    undetected: Option<Undetected>,
) -> (MerlBrdf, Safeguard) {
    let limit_deg = check.peak_limit_deg;
    let merged = replaced_below(deblurred, plain, limit_deg);
    let guard = Safeguard {
        consistency: checks.of(&merged),
        deblurred: Some(check),
        fallback_below_deg: Some(limit_deg),
        bounded_below_deg: None,
        reason: Some(format!(
            "not asked for by the data: the un-deblurred values reproduce every region within what its uncertainties explain{}",
            undetected.map_or_else(String::new, |u| format!(", and {u}"))
        )),
        max_albedo: max_albedo(&merged),
        energy: None,
        at_normal: AtNormal::Untouched,
    };
    (merged, guard)
}

/// The `kept` table (with its `guard` and the deblurred table it `replaced`, if any), which
/// breaks the identity at the normal, with the un-deblurred `plain` values in the half of
/// phi_d where they restore it (see the module documentation); as it was when neither
/// half's do, when its peak is bounded, or when the values as measured would reproduce the
/// samples worse ([`AtNormal::Kept`] says which). They replace the cells below the upper theta_h
/// of the region the samples' checks failed in ([`failure`]: the flank's when the flank
/// failed), else below the peak region's, or below the flank's when that reproduces the
/// samples better.
fn normal_restored(
    checks: &Checks<'_>,
    kept: MerlBrdf,
    guard: Safeguard,
    replaced: Option<MerlBrdf>,
    plain: &MerlBrdf,
) -> (MerlBrdf, Safeguard, Option<MerlBrdf>) {
    let failed_below_deg = failure(&guard.consistency, guard.max_albedo)
        .map_or(guard.consistency.peak_limit_deg, |(limit_deg, _)| limit_deg);
    let restored_below = |halves: Halves, below_deg: f64| {
        let table = combined_where(
            &kept,
            plain,
            |index| halves.hold(index) && Bin::from_index(index).centre_deg()[0] < below_deg,
            |_, p| p,
        );
        Restoration {
            halves,
            below_deg,
            after: NormalSpread::of(&table),
            table,
            consistency: None,
        }
    };
    let reproduction = |c: &Consistency| c.region("all").map_or(0.0, |r| r.relative_error);
    // A lobe that invented a peak at the normal can hold its tails through the flank: the
    // flank's limit is taken when that table restores the identity too and reproduces the
    // samples better.
    let restored_by = |halves: Halves| {
        let near = restored_below(halves, failed_below_deg);
        if !near.within() || failed_below_deg >= BLUR_THETA_H_DEG {
            return near;
        }
        let far = restored_below(halves, BLUR_THETA_H_DEG);
        if !far.within() {
            return near;
        }
        let (near, far) = (near.checked(checks), far.checked(checks));
        let [near_error, far_error] =
            [&near, &far].map(|r| r.consistency.as_ref().map_or(0.0, reproduction));
        if far_error < near_error {
            far
        } else {
            near
        }
    };
    // One half when either restores the identity (the one that restores it more), both
    // when neither does alone.
    let restored = [Halves::First, Halves::Second]
        .map(restored_by)
        .into_iter()
        .min_by(|a, b| a.after.ratio.total_cmp(&b.after.ratio))
        .filter(Restoration::within)
        .or_else(|| Some(restored_by(Halves::Both)).filter(Restoration::within));
    let Some(Restoration {
        halves,
        below_deg,
        after,
        table,
        consistency,
    }) = restored
    else {
        return (kept, guard, replaced);
    };
    if let Some(limit_deg) = guard.bounded_below_deg {
        return kept_as_is(kept, guard, replaced, format!(
            "the peak below theta_h {limit_deg:.2} deg is bounded, not measured: its height over phi_d at the normal lies between its bounds, which the un-deblurred values would replace by the lower one"
        ));
    }
    let consistency = consistency.unwrap_or_else(|| checks.of(&table));
    let (restored_error, kept_error) =
        (reproduction(&consistency), reproduction(&guard.consistency));
    if restored_error > kept_error {
        return kept_as_is(kept, guard, replaced, format!(
            "the un-deblurred values would restore it but reproduce the samples worse (reproduction error {:.2} % against {:.2} %)",
            100.0 * restored_error,
            100.0 * kept_error
        ));
    }
    let guard = Safeguard {
        max_albedo: max_albedo(&table),
        deblurred: guard.deblurred.or(Some(guard.consistency.clone())),
        at_normal: AtNormal::Restored(NormalFallback {
            halves,
            below_deg,
            before: guard.consistency.normal_spread,
            after,
        }),
        consistency,
        ..guard
    };
    (table, guard, replaced.or(Some(kept)))
}

/// A table whose cells of `halves` below `below_deg` in theta_h hold the un-deblurred values,
/// its spread over phi_d at the normal and, once checked, how it reproduces the samples.
struct Restoration {
    halves: Halves,
    below_deg: f64,
    after: NormalSpread,
    table: MerlBrdf,
    consistency: Option<Consistency>,
}

impl Restoration {
    /// Whether it holds the identity at the normal ([`NORMAL_SPREAD_LIMIT`]).
    fn within(&self) -> bool {
        self.after.ratio <= NORMAL_SPREAD_LIMIT
    }

    /// The same with its check against the samples, made once.
    fn checked(self, checks: &Checks<'_>) -> Self {
        let consistency = Some(checks.of(&self.table));
        Self {
            consistency,
            ..self
        }
    }
}

/// The `kept` table as it is, its `guard` saying `why` the identity's fallback was not taken.
fn kept_as_is(
    kept: MerlBrdf,
    guard: Safeguard,
    replaced: Option<MerlBrdf>,
    why: String,
) -> (MerlBrdf, Safeguard, Option<MerlBrdf>) {
    let guard = Safeguard {
        at_normal: AtNormal::Kept(why),
        ..guard
    };
    (kept, guard, replaced)
}

/// Whether a table reproduces every region's samples within what their uncertainties
/// explain (the reproduction error at most the expected one; not [`FAIL_FACTOR`] times it).
fn reproduces_within_uncertainty(check: &Consistency) -> bool {
    check.regions.iter().all(|r| !r.misses_by(1.0))
}

/// `sqrt(sum of squares)` per channel.
fn quadrature_sum(terms: &[Rgb]) -> Rgb {
    let sum = terms.iter().fold(Rgb::ZERO, |acc, t| acc + *t * *t);
    Rgb::new(sum.x.sqrt(), sum.y.sqrt(), sum.z.sqrt())
}

/// The theta_h below which the table is replaced and why, if any check fails: the peak
/// region's limit when only the peak fails (or the albedo), the flank's when the flank does.
fn failure(check: &Consistency, max_albedo: f64) -> Option<(f64, String)> {
    let failed = |name: &str| region_failure(check, name);
    let mut reasons: Vec<String> = Vec::new();
    let mut limit = None;
    if let Some(r) = failed("peak") {
        reasons.push(r);
        limit = Some(check.peak_limit_deg);
    }
    if max_albedo > ALBEDO_TOLERANCE {
        reasons.push(format!("directional albedo {max_albedo:.3} above 1"));
        limit = limit.or(Some(check.peak_limit_deg));
    }
    if let Some(r) = failed("flank") {
        reasons.push(r);
        limit = Some(crate::lobe::BLUR_THETA_H_DEG);
    }
    limit.map(|l| (l, reasons.join("; ")))
}

/// Why the region `name` fails ([`FAIL_FACTOR`]), in words; `None` when it passes or has
/// no samples.
fn region_failure(check: &Consistency, name: &str) -> Option<String> {
    check
        .region(name)
        .filter(|r| r.misses_by(FAIL_FACTOR))
        .map(|r| {
            format!(
                "{name} reproduction error {:.2} % above {FAIL_FACTOR} x the {:.2} % its uncertainties explain",
                100.0 * r.relative_error,
                100.0 * r.expected_error
            )
        })
}

/// True when `merged` reproduces the samples of every region below `limit_deg` better
/// (lower reproduction error) than `deblurred`.
fn fits_better(merged: &Consistency, deblurred: &Consistency, limit_deg: f64) -> bool {
    ["peak", "flank"]
        .iter()
        .filter(|name| **name == "peak" || limit_deg > deblurred.peak_limit_deg)
        .all(|name| match (merged.region(name), deblurred.region(name)) {
            (Some(m), Some(d)) => m.relative_error < d.relative_error,
            _ => true,
        })
}

/// `deblurred` with every cell whose theta_h centre lies below `limit_deg` taken from `plain`.
fn replaced_below(deblurred: &MerlBrdf, plain: &MerlBrdf, limit_deg: f64) -> MerlBrdf {
    combined_below(deblurred, plain, limit_deg, |_, p| p)
}

/// `deblurred` with every cell whose theta_h centre lies below `limit_deg` holding the
/// geometric mean of its value and `plain`'s, per channel (a cell either lacks: `plain`'s).
fn geometric_mean_below(deblurred: &MerlBrdf, plain: &MerlBrdf, limit_deg: f64) -> MerlBrdf {
    combined_below(deblurred, plain, limit_deg, |d, p| {
        Rgb::from_array(std::array::from_fn(|c| {
            (d[c].max(0.0) * p[c].max(0.0)).sqrt()
        }))
    })
}

/// `deblurred` with every cell whose theta_h centre lies below `limit_deg` made by
/// `combine(deblurred cell, plain cell)`; `plain`'s cell where `deblurred` has none.
fn combined_below(
    deblurred: &MerlBrdf,
    plain: &MerlBrdf,
    limit_deg: f64,
    combine: impl Fn(Rgb, Rgb) -> Rgb + Sync,
) -> MerlBrdf {
    let below = |index| Bin::from_index(index).centre_deg()[0] < limit_deg;
    combined_where(deblurred, plain, below, combine)
}

/// `deblurred` with every cell that `replace` names made by `combine(deblurred cell, plain
/// cell)`; `plain`'s cell where `deblurred` has none.
fn combined_where(
    deblurred: &MerlBrdf,
    plain: &MerlBrdf,
    replace: impl Fn(usize) -> bool + Sync,
    combine: impl Fn(Rgb, Rgb) -> Rgb + Sync,
) -> MerlBrdf {
    MerlBrdf::from_fn(specula_core::Brdf::name(deblurred), |index| {
        if !replace(index) {
            return deblurred.cell(index);
        }
        match (deblurred.cell(index), plain.cell(index)) {
            (Some(d), Some(p)) => Some(combine(d, p)),
            (_, p) => p,
        }
    })
}

/// The bounds are reported at a cell with theta_d below this (degrees), where light and
/// camera are within 75 deg of the normal at the peak.
const REPORTED_THETA_D_DEG: f64 = 75.0;

/// The two bounds of a peak the data cannot resolve, at the deblurred table's highest cell
/// below the limit (mean of the channels, 1/sr): the un-deblurred value (the peak spread
/// over the resolution) and the deblurred one (the lobe's shape).
struct PeakBounds {
    index: usize,
    plain: f64,
    deblurred: f64,
}

impl PeakBounds {
    fn of(deblurred: &MerlBrdf, plain: &MerlBrdf, limit_deg: f64) -> Self {
        let mean = |table: &MerlBrdf, index: usize| {
            table.cell(index).map_or(0.0, |v| (v.x + v.y + v.z) / 3.0)
        };
        let index = (0..specula_core::merl::CELLS)
            .filter(|&i| {
                let [theta_h_deg, theta_d_deg, _] = Bin::from_index(i).centre_deg();
                theta_h_deg < limit_deg && theta_d_deg < REPORTED_THETA_D_DEG
            })
            .max_by(|&a, &b| mean(deblurred, a).total_cmp(&mean(deblurred, b)))
            .unwrap_or(0);
        Self {
            index,
            plain: mean(plain, index),
            deblurred: mean(deblurred, index),
        }
    }
}

impl std::fmt::Display for PeakBounds {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let [h, d, p] = Bin::from_index(self.index).centre_deg();
        write!(
            f,
            "at theta_h {h:.2} deg, theta_d {d:.1} deg, phi_d {p:.1} deg the peak lies between {:.4e} and {:.4e} 1/sr and the table holds {:.4e}",
            self.plain.min(self.deblurred),
            self.plain.max(self.deblurred),
            (self.plain * self.deblurred).sqrt()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lobe::{Geometry, Shape};
    use specula_acquisition::device::Device;
    use specula_core::merl::{PHI_D_BINS, THETA_H_BINS};
    use specula_core::HalfDiff;

    fn lobe(alpha: f64) -> Lobe {
        Lobe {
            shape: Shape { alpha, gamma: 2.0 },
            diffuse: Rgb::splat(0.05),
            specular: Rgb::splat(0.8),
            grazing: Rgb::splat(0.2),
        }
    }

    fn tabulated(truth: &Lobe) -> MerlBrdf {
        MerlBrdf::from_fn("t", |index| {
            let [h, d, p] = Bin::from_index(index).centre_deg();
            Some(truth.eval(&Geometry::of(HalfDiff::from_degrees(h, 0.0, d, p))))
        })
    }

    /// `truth` measured through `response` at 40 theta_h from 0 to 40 deg (denser near the
    /// peak), theta_d 40, phi_d 90.
    fn along_theta_h(truth: &Lobe, response: &impl CaptureResponse) -> Vec<Sample> {
        let nodes = response.capture_nodes(FIT_RESPONSE_NODES);
        (0..40)
            .map(|k| {
                let h = (k as f64 * 1.5).powi(2) / 90.0;
                let hd = HalfDiff::from_degrees(h, 45.0, 40.0, 90.0);
                Sample::new(hd, truth.measured(&nodes, hd))
            })
            .collect()
    }

    #[test]
    fn an_invented_spike_falls_back_to_the_values_as_measured_and_the_truth_stays() {
        // GGX alpha 0.05 measured through the UTIA response along theta_h at theta_d 40,
        // phi_d 90. A "deblurred" table with a peak four times sharper (and the lobe fitted
        // to it) reproduces the peak's samples badly: the check fails there, and the
        // un-deblurred table (here the truth itself) takes the peak's cells. The truth as
        // the deblurred table passes and is kept as it is.
        let response = Device::utia().response();
        let truth = lobe(0.05);
        let samples = along_theta_h(&truth, &response);
        let spiky = lobe(0.0125);
        let (kept, guard, replaced) = safeguarded(
            &samples,
            tabulated(&spiky),
            Some(&spiky),
            &response,
            &tabulated(&truth),
        );
        assert!(guard.fallback_below_deg.is_some(), "{guard:?}");
        // The deblurred table replaced is kept for the uncertainty's deblurring term.
        assert!(replaced.is_some());
        let peak = Bin {
            theta_h_i: 0,
            theta_d_i: 40,
            phi_d_i: 90,
        }
        .index();
        assert_eq!(kept.cell(peak), tabulated(&truth).cell(peak));
        let failed = guard.deblurred.as_ref().unwrap().region("peak").unwrap();
        assert!(
            failed.relative_error > FAIL_FACTOR * failed.expected_error,
            "{failed:?}"
        );
        assert!(guard
            .lines()
            .iter()
            .any(|l| l.starts_with("deblur_fallback=theta_h below")));

        // The un-deblurred table, wider than the truth, blurred once more misses the peak's
        // samples: it cannot stand in for the deblurred one.
        let (_, guard, replaced) = safeguarded(
            &samples,
            tabulated(&truth),
            Some(&truth),
            &response,
            &tabulated(&lobe(0.1)),
        );
        assert_eq!(guard.fallback_below_deg, None, "{guard:?}");
        assert!(replaced.is_none());
        let peak = guard.consistency.region("peak").unwrap();
        assert!(
            peak.relative_error < FAIL_FACTOR * peak.expected_error,
            "{peak:?}"
        );
        assert!(guard.max_albedo < 1.0, "{}", guard.max_albedo);
    }
    #[test]
    fn an_unresolved_peak_that_no_table_explains_is_bounded_between_the_two() {
        // As above, but the un-deblurred table is a lobe far wider than the truth, so it
        // reproduces the samples no better than a ten-times-sharper "deblurred" one. The
        // deblurred lobe's half width (0.18 deg) is below what the captures can tell from
        // zero (0.26 deg): the
        // peak's cells hold the geometric mean of the two tables, the cells beyond the peak
        // region keep the deblurred values, and the summary says so. With a lobe whose width
        // the captures do tell (1.8 deg), the same tables are kept as deblurred.
        let response = Device::utia().response();
        let truth = lobe(0.05);
        let samples = along_theta_h(&truth, &response);
        let spiky = lobe(0.005);
        let wide = lobe(0.6);
        let limit_deg = width_detection_limit_deg(response.resolution_deg());
        assert!(spiky.shape.half_width_deg() < limit_deg, "{limit_deg}");
        assert!(truth.shape.half_width_deg() > response.resolution_deg());
        let (kept, guard, replaced) = safeguarded(
            &samples,
            tabulated(&spiky),
            Some(&spiky),
            &response,
            &tabulated(&wide),
        );
        let limit = guard.bounded_below_deg.expect("bounded");
        assert!(replaced.is_some());
        assert_eq!(guard.fallback_below_deg, None, "{guard:?}");
        let cell = |h: usize| {
            Bin {
                theta_h_i: h,
                theta_d_i: 40,
                phi_d_i: 90,
            }
            .index()
        };
        let (d, p) = (tabulated(&spiky), tabulated(&wide));
        let peak = cell(0);
        let expected = (d.cell(peak).unwrap().y * p.cell(peak).unwrap().y).sqrt();
        assert!((kept.cell(peak).unwrap().y - expected).abs() <= 1e-12 * expected);
        let truth_peak = tabulated(&truth).cell(peak).unwrap().y;
        assert!(p.cell(peak).unwrap().y < truth_peak && truth_peak < d.cell(peak).unwrap().y);
        let beyond = (0..THETA_H_BINS)
            .find(|&h| Bin::from_index(cell(h)).centre_deg()[0] > limit)
            .unwrap();
        assert_eq!(kept.cell(cell(beyond)), d.cell(cell(beyond)));
        assert!(
            guard.lines().iter().any(|l| l.contains("geometric mean")),
            "{guard:?}"
        );

        let (kept, guard, replaced) = safeguarded(
            &samples,
            tabulated(&spiky),
            Some(&truth),
            &response,
            &tabulated(&wide),
        );
        assert!(replaced.is_none());
        assert_eq!(guard.bounded_below_deg, None, "{guard:?}");
        assert_eq!(kept.cell(peak), d.cell(peak));
    }
    /// The truth of the two tests below, a lobe narrower than the captures can tell from zero
    /// (alpha 0.004, half width 0.15 deg), measured along theta_h; and what the checks make of
    /// a "deblurred" table that is the truth with the cells within 0.5 deg of the peak
    /// `scale` times as high (the flank's samples, which the blur reaches from beyond a
    /// degree, reproduced exactly), beside an un-deblurred table (a wide lobe) that does no
    /// better: the table kept, the checks and the table itself.
    fn overshooting_peak(scale: f64) -> (MerlBrdf, Safeguard, MerlBrdf) {
        let response = Device::utia().response();
        let truth = Lobe {
            specular: Rgb::splat(0.4),
            ..lobe(0.004)
        };
        assert!(
            truth.shape.half_width_deg() < width_detection_limit_deg(response.resolution_deg())
        );
        let samples = along_theta_h(&truth, &response);
        let exact = tabulated(&truth);
        let overshoot = MerlBrdf::from_fn("t", |index| {
            let near = Bin::from_index(index).centre_deg()[0] < 0.5;
            exact.cell(index).map(|v| if near { v * scale } else { v })
        });
        let (kept, guard, _) = safeguarded(
            &samples,
            overshoot.clone(),
            Some(&truth),
            &response,
            &tabulated(&lobe(0.6)),
        );
        (kept, guard, overshoot)
    }

    fn peak_cell() -> usize {
        Bin {
            theta_h_i: 0,
            theta_d_i: 40,
            phi_d_i: 90,
        }
        .index()
    }

    #[test]
    fn an_unresolved_peak_whose_lobe_reproduces_the_flank_stays_as_deblurred() {
        // 15 % higher: the peak's samples are reproduced badly (more than three times what
        // their uncertainties explain) but within twice the failure threshold, the flank's
        // exactly. The lobe describes the material where the
        // captures see its shape: the peak is not bounded, the deblurred table is returned as
        // it is (its albedo within 1), and the reason says why.
        let (kept, guard, overshoot) = overshooting_peak(1.15);
        let peak = guard.consistency.region("peak").unwrap();
        assert!(
            peak.relative_error > FAIL_FACTOR * peak.expected_error,
            "{peak:?}"
        );
        assert!(
            peak.relative_error < REFUTED_FACTOR * peak.expected_error,
            "{peak:?}"
        );
        assert!(
            region_failure(&guard.consistency, "flank").is_none(),
            "{guard:?}"
        );
        assert_eq!(guard.bounded_below_deg, None, "{guard:?}");
        assert_eq!(guard.fallback_below_deg, None, "{guard:?}");
        assert_eq!(guard.energy, None, "{guard:?}");
        assert_eq!(kept.cell(peak_cell()), overshoot.cell(peak_cell()));
        assert!(
            guard.lines().iter().any(|l| l.contains("continuation")),
            "{guard:?}"
        );
    }

    #[test]
    fn an_unresolved_peak_its_own_samples_refute_is_bounded_though_the_flank_passes() {
        // 40 % higher: the peak region misses its samples by more than twice the
        // failure threshold. The flank still passes, but the samples refute the peak: it is
        // bounded between the two tables.
        let (kept, guard, overshoot) = overshooting_peak(1.4);
        let checked = guard
            .deblurred
            .as_ref()
            .expect("the deblurred table's figures");
        let peak = checked.region("peak").unwrap();
        assert!(
            peak.relative_error > REFUTED_FACTOR * peak.expected_error,
            "{peak:?}"
        );
        assert!(region_failure(checked, "flank").is_none(), "{guard:?}");
        assert!(guard.bounded_below_deg.is_some(), "{guard:?}");
        assert!(kept.cell(peak_cell()).unwrap().y < overshoot.cell(peak_cell()).unwrap().y);
    }
    #[test]
    fn a_peak_at_the_detection_limit_widens_the_capture_by_the_positioning_accuracy() {
        // Half widths add in quadrature under the blur: at the limit the recorded width grows
        // by exactly the device's accuracy, and the default device's limit is 0.26 deg.
        for resolution_deg in [0.5, 1.0861, 2.0] {
            let w = width_detection_limit_deg(resolution_deg);
            let widening = (resolution_deg * resolution_deg + w * w).sqrt() - resolution_deg;
            assert!((widening - consistency::POSITIONING_ACCURACY_DEG).abs() < 1e-12);
        }
        let default = width_detection_limit_deg(Device::utia().response().resolution_deg());
        assert!((default - 0.257).abs() < 0.002, "{default}");
    }

    /// `flat` with a GGX spike of roughness `alpha` and specular weight `weight` on top.
    fn spiked(flat: Lobe, alpha: f64, weight: f64) -> Lobe {
        Lobe {
            shape: Shape { alpha, gamma: 2.0 },
            specular: Rgb::splat(weight),
            ..flat
        }
    }

    #[test]
    fn a_spike_the_captures_cannot_see_on_a_flat_material_is_not_kept() {
        // A matte material (the lobe's diffuse part alone) and a "deblurred" table that adds
        // a spike of half width below the detection limit on top: blurred, the spike changes
        // the captures by far less than their uncertainty, so both checks pass. The flat
        // table reproduces every region within its uncertainty too: nothing asks for the
        // spike, and the flat values take the peak's cells.
        let response = Device::utia().response();
        let flat = Lobe {
            specular: Rgb::ZERO,
            grazing: Rgb::ZERO,
            ..lobe(0.3)
        };
        let spiky = spiked(flat, 0.0005, 1e-7);
        let samples = along_theta_h(&flat, &response);
        let limit = width_detection_limit_deg(response.resolution_deg());
        assert!(spiky.shape.half_width_deg() < limit);
        let flat_table = tabulated(&flat);
        let body = flat_table.cell(peak_cell()).unwrap().y;
        // The spike as the deblurred table, checked against the flat table; the spike shows
        // in the table's peak cell.
        let guard_of = |spiky: &Lobe| {
            let table = tabulated(spiky);
            let spike = table.cell(peak_cell()).unwrap().y;
            assert!(spike > 1.1 * body, "{spike} {body}");
            safeguarded(&samples, table, Some(spiky), &response, &flat_table)
        };
        let (kept, guard, replaced) = guard_of(&spiky);
        let checked = guard
            .deblurred
            .as_ref()
            .expect("the deblurred table's figures");
        assert!(failure(checked, 0.0).is_none(), "{guard:?}");
        assert!(guard.fallback_below_deg.is_some(), "{guard:?}");
        assert!(replaced.is_some());
        assert_eq!(kept.cell(peak_cell()).unwrap().y, body);
        assert!(
            guard
                .lines()
                .iter()
                .any(|l| l.contains("not asked for by the data")),
            "{guard:?}"
        );

        // A spike the captures could tell from zero (its half width above the limit) but
        // too weak for them to see: the flat values take its place all the same.
        let visible_width = spiked(flat, 0.008, 1e-6);
        assert!(visible_width.shape.half_width_deg() > limit);
        let (kept, guard, _) = guard_of(&visible_width);
        assert!(guard.fallback_below_deg.is_some(), "{guard:?}");
        assert_eq!(kept.cell(peak_cell()).unwrap().y, body);

        // The same spike on a sharp material is needed: the flat table cannot stand in.
        let sharp = lobe(0.0005);
        let samples = along_theta_h(&sharp, &response);
        let (_, guard, _) = safeguarded(
            &samples,
            tabulated(&sharp),
            Some(&sharp),
            &response,
            &flat_table,
        );
        assert_eq!(guard.fallback_below_deg, None, "{guard:?}");
    }

    #[test]
    fn a_peak_one_half_of_phi_d_invents_at_the_normal_falls_back_in_that_half() {
        // A flat-topped material (a wide lobe) measured at theta_d 40, and a "deblurred" table
        // whose first half of phi_d holds a sharp peak on top from theta_d 60: the samples
        // cannot see it, so their checks pass, but at theta_h 0 the two halves name the same
        // configurations and differ several times over. The first half takes the
        // un-deblurred values; the second half stays.
        let response = Device::utia().response();
        let flat = flat_top();
        let invented = Lobe {
            specular: Rgb::splat(5.0),
            ..lobe(0.02)
        };
        let table = with_peaks([Some(&invented), None]);
        let nodes = response.capture_nodes(FIT_RESPONSE_NODES);
        let samples = column(40.0, 135.0, |hd| flat.measured(&nodes, hd));
        let before = NormalSpread::of(&table);
        assert!(before.ratio > 2.0 * NORMAL_SPREAD_LIMIT, "{before:?}");
        let (kept, guard, replaced) = safeguarded_over(&flat, &samples, table.clone(), &response);
        let at = |phi_d_i| peak_cell_at(70, phi_d_i);
        let AtNormal::Restored(fallback) = guard.at_normal else {
            panic!("the first half falls back: {:#?}", guard.lines());
        };
        assert_eq!(fallback.halves, Halves::First, "{fallback:?}");
        assert!(fallback.after.ratio < 1.01, "{fallback:?}");
        assert_eq!(guard.consistency.normal_spread, fallback.after);
        assert!(guard.failed());
        let replaced = replaced.expect("the deblurred table, for the uncertainty");
        assert_eq!(replaced.cell(at(45)), table.cell(at(45)));
        assert_eq!(kept.cell(at(45)), tabulated(&flat).cell(at(45)));
        assert_eq!(kept.cell(at(135)), table.cell(at(135)));
        assert!(guard
            .lines()
            .iter()
            .any(|l| l.starts_with("deblur_fallback_normal=theta_h below")));

        // The same peak in both halves is one material's: nothing to restore.
        let both = MerlBrdf::from_fn("b", |index| table.cell(index - index % PHI_D_BINS + 45));
        let (_, guard, _) = safeguarded_over(&flat, &samples, both, &response);
        assert_eq!(guard.at_normal.restored(), None, "{guard:?}");

        // Different peaks in the two halves: neither half's values as measured restore the
        // identity alone (each leaves the other's peak), both halves' do.
        let weaker = Lobe {
            specular: Rgb::splat(2.0),
            ..lobe(0.02)
        };
        let two = with_peaks([Some(&invented), Some(&weaker)]);
        let (kept, guard, _) = safeguarded_over(&flat, &samples, two, &response);
        let AtNormal::Restored(fallback) = guard.at_normal else {
            panic!("both halves fall back: {:#?}", guard.lines());
        };
        assert_eq!(fallback.halves, Halves::Both, "{fallback:?}");
        assert!(fallback.after.ratio < 1.01, "{fallback:?}");
        assert_eq!(kept.cell(at(45)), tabulated(&flat).cell(at(45)));
        assert_eq!(kept.cell(at(135)), tabulated(&flat).cell(at(135)));
    }

    /// A peak one half of phi_d invents at the normal, with tails beyond the peak region that
    /// its samples' checks let pass: the fallback takes that half's values as measured
    /// through the flank, which reproduces the samples better than the peak region alone.
    #[test]
    fn an_invented_peak_s_tails_fall_back_through_the_flank() {
        let response = Device::utia().response();
        let flat = flat_top();
        // Beckmann-like tails: at the normal the table varies 2.4 times over phi_d, and the
        // first half's flank samples, blurred by the light's disk, see 2.5 % of it: within
        // what the checks let pass.
        let invented = Lobe {
            shape: Shape {
                alpha: 0.024,
                gamma: 50.0,
            },
            diffuse: Rgb::ZERO,
            specular: Rgb::splat(0.0008),
            grazing: Rgb::ZERO,
        };
        let table = with_peaks([Some(&invented), None]);
        let nodes = response.capture_nodes(FIT_RESPONSE_NODES);
        // The first half's samples start beyond the peak region: none sees the peak itself.
        // They scatter by 1.5 %, above the 1 % their uncertainties explain, so that the values
        // as measured do not replace the peak region for want of a peak in the data.
        let samples: Vec<Sample> = column(70.0, 45.0, |hd| flat.measured(&nodes, hd))
            .into_iter()
            .filter(|s| s.hd.theta_h.to_degrees() > 2.4)
            .enumerate()
            .map(|(k, s)| Sample {
                value: s.value * if k % 2 == 0 { 1.015 } else { 0.985 },
                ..s
            })
            .collect();
        let (kept, guard, _) = safeguarded_over(&flat, &samples, table.clone(), &response);
        let AtNormal::Restored(fallback) = guard.at_normal else {
            panic!("the first half falls back: {:#?}", guard.lines());
        };
        assert_eq!(fallback.halves, Halves::First, "{fallback:?}");
        assert_eq!(fallback.below_deg, BLUR_THETA_H_DEG, "{fallback:?}");
        let tail = Bin::of_degrees(5.0, 70.0, 45.0).index();
        assert_ne!(table.cell(tail), tabulated(&flat).cell(tail));
        assert_eq!(kept.cell(tail), tabulated(&flat).cell(tail));
    }

    /// A flat-topped material: a wide lobe.
    fn flat_top() -> Lobe {
        Lobe {
            grazing: Rgb::ZERO,
            specular: Rgb::splat(0.3),
            ..lobe(0.4)
        }
    }

    /// [`safeguarded`] as the identity's tests call it: `table` deblurred over the `flat`
    /// lobe's fit, whose tabulation is the values as measured.
    fn safeguarded_over<R: CaptureResponse + ?Sized>(
        flat: &Lobe,
        samples: &[Sample],
        table: MerlBrdf,
        response: &R,
    ) -> (MerlBrdf, Safeguard, Option<MerlBrdf>) {
        safeguarded(samples, table, Some(flat), response, &tabulated(flat))
    }

    /// [`flat_top`] with, from theta_d 60 deg, each half of phi_d's peak on top (`[first,
    /// second]`, `None` for none): where the halves' peaks differ, the table breaks the
    /// identity at the normal.
    fn with_peaks(peaks: [Option<&Lobe>; 2]) -> MerlBrdf {
        let flat = flat_top();
        MerlBrdf::from_fn("t", |index| {
            let [h, d, p] = Bin::from_index(index).centre_deg();
            let g = Geometry::of(HalfDiff::from_degrees(h, 0.0, d, p));
            let peak = peaks[usize::from(in_second(index))].filter(|_| d >= 60.0);
            Some(flat.eval(&g) + peak.map_or(Rgb::ZERO, |peak| peak.eval(&g)))
        })
    }

    /// [`with_peaks`] with a sharp peak (alpha 0.02, albedo within 1) in the first half only.
    fn peak_in_the_first_half() -> (Lobe, MerlBrdf) {
        let peak = Lobe {
            specular: Rgb::splat(0.6),
            ..lobe(0.02)
        };
        let table = with_peaks([Some(&peak), None]);
        assert!(NormalSpread::of(&table).ratio > 2.0 * NORMAL_SPREAD_LIMIT);
        (flat_top(), table)
    }

    #[test]
    fn a_feature_at_the_normal_the_samples_see_is_not_restored_away() {
        // The samples measure the first half's peak (theta_d 70, phi_d 45) as the table holds
        // it: the flat values would restore the identity at the normal but miss those
        // samples, so the table stays and the summary says why.
        let response = Device::utia().response();
        let (flat, table) = peak_in_the_first_half();
        let nodes = response.capture_nodes(FIT_RESPONSE_NODES);
        let samples = column(70.0, 45.0, |hd| consistency::predicted(&table, &nodes, hd));
        let (kept, guard, replaced) = safeguarded_over(&flat, &samples, table.clone(), &response);
        assert_eq!(guard.at_normal.restored(), None, "{:#?}", guard.lines());
        assert_eq!(guard.energy, None, "{:#?}", guard.lines());
        assert!(replaced.is_none());
        assert_eq!(
            kept.cell(peak_cell_at(70, 45)),
            table.cell(peak_cell_at(70, 45))
        );
        assert!(
            guard
                .lines()
                .iter()
                .any(|l| l.starts_with("deblur_fallback_normal=none: the un-deblurred values would restore it but reproduce the samples worse")),
            "{:#?}",
            guard.lines()
        );
    }

    #[test]
    fn a_bounded_peak_keeps_its_spread_over_phi_d_at_the_normal() {
        // The same table, its peak bounded by the checks (its height undecided between its
        // bounds): the identity's fallback would put the lower bound in the first half, so the
        // table stays and the summary says why. The samples (theta_d 40, the second half)
        // do not see the first half's peak.
        let response = Device::utia().response();
        let (flat, table) = peak_in_the_first_half();
        let nodes = response.capture_nodes(FIT_RESPONSE_NODES);
        let samples = column(40.0, 135.0, |hd| flat.measured(&nodes, hd));
        let checks = Checks {
            samples: &samples,
            u: prediction_uncertainty(&samples, Some(&flat), &table, &nodes),
            instrument: Instrument {
                nodes: &nodes,
                resolution_deg: Some(response.resolution_deg()),
            },
        };
        let bounded = Safeguard {
            consistency: checks.of(&table),
            deblurred: None,
            fallback_below_deg: None,
            bounded_below_deg: Some(2.0),
            reason: Some("bounded".into()),
            max_albedo: max_albedo(&table),
            energy: None,
            at_normal: AtNormal::Untouched,
        };
        let plain = tabulated(&flat);
        let (kept, guard, _) =
            normal_restored(&checks, table.clone(), bounded.clone(), None, &plain);
        assert_eq!(guard.at_normal.restored(), None, "{:#?}", guard.lines());
        assert_eq!(
            kept.cell(peak_cell_at(70, 45)),
            table.cell(peak_cell_at(70, 45))
        );
        assert!(
            matches!(&guard.at_normal, AtNormal::Kept(why) if why.contains("is bounded")),
            "{:?}",
            guard.at_normal
        );

        // Not bounded, the first half takes the flat values, as for any invented peak.
        let unbounded = Safeguard {
            bounded_below_deg: None,
            ..bounded
        };
        let (kept, guard, _) = normal_restored(&checks, table, unbounded, None, &plain);
        assert_eq!(
            guard.at_normal.restored().map(|f| f.halves),
            Some(Halves::First)
        );
        assert_eq!(
            kept.cell(peak_cell_at(70, 45)),
            plain.cell(peak_cell_at(70, 45))
        );
    }

    /// Forty samples along theta_h (0 to 38 deg, closer near the peak) at `theta_d_deg`,
    /// `phi_d_deg` and phi_h 45 deg, each `capture` of its configuration.
    fn column(theta_d_deg: f64, phi_d_deg: f64, capture: impl Fn(HalfDiff) -> Rgb) -> Vec<Sample> {
        (0..40)
            .map(|k| {
                let h = (k as f64 * 1.5).powi(2) / 90.0;
                let hd = HalfDiff::from_degrees(h, 45.0, theta_d_deg, phi_d_deg);
                Sample::new(hd, capture(hd))
            })
            .collect()
    }

    /// The cell at theta_h 0 of theta_d bin `theta_d_i` and phi_d bin `phi_d_i`.
    fn peak_cell_at(theta_d_i: usize, phi_d_i: usize) -> usize {
        Bin {
            theta_h_i: 0,
            theta_d_i,
            phi_d_i,
        }
        .index()
    }
}
