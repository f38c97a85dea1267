//! The device time the main samples took, against the time they were planned to take.
//!
//! A batch is priced before it is measured: the moves by the time model, the captures by the
//! exposures predicted from the probe ([`crate::estimate::price_captures`]). Near a peak the
//! capturer's own prediction, corrected by the sample before, can miss and take a second or
//! third capture, and a batch's first move starts where the last batch ended, not at the park
//! position it was priced from: measured runs take about 5 % longer than priced. So before
//! each decision the samples so far are priced again as they were taken, from the journal
//! alone (each move from the position before it, every capture the record holds, priced by the
//! same time model), and the next batch's price is scaled by the ratio. The journal holds
//! the same rows and captures however often a run was stopped and resumed, so the decisions
//! stay those of an uninterrupted run.

use crate::journal::{CaptureRecord, PlannedRow};
use specula_acquisition::device::Device;
use specula_acquisition::hdr::Exposure;
use specula_acquisition::timing::{predicted_capture_times_s, TimeModel};
use std::collections::BTreeMap;

/// The time the main stage's samples took and the time they were priced at, seconds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Pace {
    /// The measured rows priced as they were taken.
    pub taken_s: f64,
    /// The same rows' predicted time, as planned.
    pub planned_s: f64,
}

impl Pace {
    /// The main rows of `plan` that were taken (`captures` by seq, as the journal holds
    /// them), priced as taken and as planned. The first move starts at the park position, as
    /// the first design was priced.
    pub(crate) fn of(
        plan: &[PlannedRow],
        captures: &BTreeMap<u32, Vec<CaptureRecord>>,
        device: &Device,
    ) -> Self {
        let time = TimeModel::from_device(device);
        let mut from = device.park_axes();
        let (mut moves_s, mut planned_s) = (0.0, 0.0);
        let mut exposures: Vec<Exposure> = Vec::new();
        for row in plan {
            let Some(taken) = captures.get(&row.seq) else {
                continue;
            };
            moves_s += time.transition_s(&from, &row.axes);
            from = row.axes;
            planned_s += row.predicted_s;
            exposures.extend(taken.iter().map(|c| Exposure {
                light_level: c.light_level,
                exposure_s: c.exposure_s,
            }));
        }
        let captures_s: f64 = predicted_capture_times_s(&exposures, &device.capture)
            .iter()
            .sum();
        Self {
            taken_s: moves_s + captures_s,
            planned_s,
        }
    }

    /// How much longer the samples took than planned: `taken / planned` (1 with nothing
    /// measured yet).
    pub(crate) fn ratio(&self) -> f64 {
        if self.planned_s > 0.0 && self.taken_s > 0.0 {
            self.taken_s / self.planned_s
        } else {
            1.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ideal::simulated_instrument;
    use specula_acquisition::plan::Plan;
    use specula_core::HalfDiff;
    use std::sync::Arc;

    /// The simulated device's own clock over moves, light changes and captures is what the
    /// journal's rows and captures are priced at, whatever the predictions said.
    #[test]
    fn the_samples_priced_as_taken_take_what_the_device_s_clock_took() {
        let device = Device::utia();
        let truth = Arc::new(specula_core::materials::preset("chrome").unwrap());
        let mut instrument = simulated_instrument(device.clone(), truth, 1, true);
        let hds: Vec<HalfDiff> = [(0.5, 10.0, 90.0), (20.0, 40.0, 0.0), (3.0, 60.0, 45.0)]
            .iter()
            .map(|&(h, d, p)| HalfDiff::from_degrees(h, 45.0, d, p))
            .collect();
        let plan = Plan::from_half_diffs(&hds, &device);
        // Each sample's captures: several at changing light levels, one, two at one level.
        let taken: [&[(f64, f64)]; 3] = [
            &[(0.01, 1.0), (0.001, 0.1), (0.004, 0.1)],
            &[(0.2, 1.0)],
            &[(0.05, 0.5), (0.02, 0.5)],
        ];
        instrument.home().unwrap();
        instrument.set_light(0.0).unwrap();
        let start_s = instrument.simulated_clock_s().unwrap();
        let (mut rows, mut records) = (Vec::new(), BTreeMap::new());
        for (seq, ((sample, axes), captures)) in plan.measured().zip(taken).enumerate() {
            instrument.move_to(&axes).unwrap();
            for &(exposure_s, light_level) in captures {
                instrument.set_light(light_level).unwrap();
                instrument.capture(exposure_s, false).unwrap();
            }
            rows.push(PlannedRow {
                seq: seq as u32,
                hd: sample.hd,
                axes,
                predicted_s: 1.0,
            });
            records.insert(seq as u32, taken_captures(captures));
        }
        assert_eq!(rows.len(), 3);
        let device_s = instrument.simulated_clock_s().unwrap() - start_s;
        let pace = Pace::of(&rows, &records, &device);
        assert!(
            (pace.taken_s - device_s).abs() < 1e-9,
            "{pace:?} {device_s}"
        );
        assert_eq!(pace.planned_s, 3.0);
        assert!((pace.ratio() - device_s / 3.0).abs() < 1e-9);
        // A row not measured yet counts neither way.
        records.remove(&2);
        assert_eq!(Pace::of(&rows, &records, &device).planned_s, 2.0);
    }

    fn taken_captures(captures: &[(f64, f64)]) -> Vec<CaptureRecord> {
        captures
            .iter()
            .map(|&(exposure_s, light_level)| CaptureRecord {
                exposure_s,
                light_level,
                mean_raw: [100.0; 3],
                saturated_fraction: [0.0; 3],
                pixel_count: 1,
                used: true,
                unix_s: 0.0,
            })
            .collect()
    }
}
