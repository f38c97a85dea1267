//! A measurement plan: samples in half-difference angles turned into device positions, with
//! the samples the device cannot take marked and the time of each step (paper 5.3).
//!
//! The paper's plan is 30 theta_h positions of the exponential sampling function with the
//! material's k-hat, theta_d = 0, 3, ..., 87 deg, phi_d = 0, 15, ..., 90 deg and
//! phi_h = 45 deg: 6300 combinations, of which the UTIA device reached 4073. A sample is
//! - `limit` when no position of the axes within their ranges gives its pair of directions
//!   (theta_v > 75 deg, a direction below the surface);
//! - `occluded` when every reachable position is blocked (see [`crate::occlusion`]);
//! - `ok` otherwise; it then has one chosen position and the list of its free alternatives.
//!
//! A plan keeps its samples in execution order: the measurable ones in the order they are
//! taken, then the excluded ones in their original order.

use crate::device::Device;
use crate::kinematics::{solutions, AxisPositions};
use crate::occlusion::{blockage_within_accuracy, Blockage};
use crate::timing::{StepTime, TimeModel};
use glam::DVec3;
use specula_core::geometry::Spherical;
use specula_core::HalfDiff;
use std::collections::BTreeMap;
use std::io::Write;

/// Whether the device can take a sample, with what each case has.
#[derive(Debug, Clone, PartialEq)]
pub enum Status {
    /// Reachable and unobstructed.
    Ok {
        /// The position used.
        axes: AxisPositions,
        /// Every free position; `axes` is one of them.
        alternatives: Vec<AxisPositions>,
    },
    /// Out of the axes' ranges for every position.
    Limit,
    /// Reachable, but blocked at every reachable position.
    Occluded {
        /// What blocks the first reachable position.
        blockage: Blockage,
    },
}

impl Status {
    /// `ok`, `limit` or `occluded`, as in the plan CSV.
    pub fn name(&self) -> &'static str {
        match self {
            Status::Ok { .. } => "ok",
            Status::Limit => "limit",
            Status::Occluded { .. } => "occluded",
        }
    }

    /// Whether the device can take the sample.
    pub fn is_ok(&self) -> bool {
        matches!(self, Status::Ok { .. })
    }
}

/// One sample of a plan.
#[derive(Debug, Clone, PartialEq)]
pub struct PlannedSample {
    /// Position in the list the plan was made from (for a grid: theta_h outermost, phi_d
    /// innermost).
    pub index: usize,
    /// The sample in half-difference angles, radians.
    pub hd: HalfDiff,
    /// Direction to the light, sample frame.
    pub wi: DVec3,
    /// Direction to the camera, sample frame.
    pub wo: DVec3,
    /// Whether the device can take it, with its positions or what blocks it.
    pub status: Status,
    /// This sample's step: the move from the previous measured sample (the park position for
    /// the first), settling and the capture, seconds; 0 for an excluded sample.
    pub time_s: f64,
    /// This sample's capture, seconds: the device's bracket until
    /// [`Plan::set_capture_times_s`] prices another HDR scheme.
    pub capture_s: f64,
}

impl PlannedSample {
    /// The position used, for an `ok` sample.
    pub fn axes(&self) -> Option<AxisPositions> {
        match &self.status {
            Status::Ok { axes, .. } => Some(*axes),
            _ => None,
        }
    }

    /// Every free position of an `ok` sample (none for an excluded one).
    pub fn alternatives(&self) -> &[AxisPositions] {
        match &self.status {
            Status::Ok { alternatives, .. } => alternatives,
            _ => &[],
        }
    }

    /// For an `occluded` sample, what blocks its first reachable position.
    pub fn blockage(&self) -> Option<Blockage> {
        match &self.status {
            Status::Occluded { blockage } => Some(*blockage),
            _ => None,
        }
    }
}

/// Samples in execution order with their device positions and step times.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// Every sample of the plan: the measurable ones in execution order, then the excluded ones.
    pub samples: Vec<PlannedSample>,
    /// The time model the step times come from.
    pub time_model: TimeModel,
}

/// Counts and times of a plan.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanSummary {
    /// Samples in the plan.
    pub total: usize,
    /// Samples with status `ok`.
    pub measurable: usize,
    /// Samples out of the axes' ranges (status `limit`).
    pub limit: usize,
    /// Samples blocked at every reachable position (status `occluded`).
    pub occluded: usize,
    /// Occluded samples by what blocks them (see [`Blockage::describe`]).
    pub occluded_by: BTreeMap<String, usize>,
    /// Sum of the axis moves, seconds.
    pub move_s: f64,
    /// Sum of the settle times, seconds.
    pub settle_s: f64,
    /// Sum of the captures, seconds.
    pub capture_s: f64,
}

impl PlanSummary {
    /// Everything: moves, settling and captures, seconds.
    pub fn duration_s(&self) -> f64 {
        self.move_s + self.settle_s + self.capture_s
    }
}

impl Plan {
    /// The grid `theta_h x theta_d x phi_d` at one `phi_h` (degrees), theta_h outermost and
    /// phi_d innermost: the paper's nested-loop order.
    pub fn from_grid(
        theta_h_deg: &[f64],
        theta_d_deg: &[f64],
        phi_d_deg: &[f64],
        phi_h_deg: f64,
        device: &Device,
    ) -> Plan {
        let mut hds = Vec::with_capacity(theta_h_deg.len() * theta_d_deg.len() * phi_d_deg.len());
        for &th in theta_h_deg {
            for &td in theta_d_deg {
                for &pd in phi_d_deg {
                    hds.push(HalfDiff::from_degrees(th, phi_h_deg, td, pd));
                }
            }
        }
        Plan::from_half_diffs(&hds, device)
    }

    /// Any list of samples, taken in the given order. Each `ok` sample uses the free position
    /// that is quickest to reach from the previous one (as a careful operator would).
    pub fn from_half_diffs(hds: &[HalfDiff], device: &Device) -> Plan {
        let time_model = TimeModel::from_device(device);
        let mut previous = time_model.park;
        let mut measured = Vec::new();
        let mut excluded = Vec::new();
        for (index, &hd) in hds.iter().enumerate() {
            let sample = plan_sample(index, hd, device, &time_model, &previous);
            if let Status::Ok { axes, .. } = sample.status {
                previous = axes;
                measured.push(sample);
            } else {
                excluded.push(sample);
            }
        }
        measured.extend(excluded);
        let mut plan = Plan {
            samples: measured,
            time_model,
        };
        plan.retime();
        plan
    }

    /// The measurable samples in execution order, each with its position.
    pub fn measured(&self) -> impl Iterator<Item = (&PlannedSample, AxisPositions)> {
        self.samples
            .iter()
            .filter_map(|s| s.axes().map(|axes| (s, axes)))
    }

    /// The step of each measured sample from the one before (the park position first), with
    /// the sample's own capture time.
    pub fn steps(&self) -> Vec<StepTime> {
        let mut previous = self.time_model.park;
        self.measured()
            .map(|(sample, axes)| {
                let step = StepTime {
                    capture_s: sample.capture_s,
                    ..self.time_model.step(&previous, &axes)
                };
                previous = axes;
                step
            })
            .collect()
    }

    /// Recomputes every `time_s` from the execution order.
    pub fn retime(&mut self) {
        let steps = self.steps();
        let mut steps = steps.iter();
        for sample in &mut self.samples {
            sample.time_s = match sample.axes() {
                Some(_) => steps.next().map_or(0.0, StepTime::total_s),
                None => 0.0,
            };
        }
    }

    /// Prices the capture of each measured sample, in execution order (seconds, e.g. from
    /// [`crate::timing::predicted_capture_times_s`]), and retimes the plan. Extra times are
    /// ignored; samples without one keep theirs.
    pub fn set_capture_times_s(&mut self, capture_s: &[f64]) {
        let measured = self.samples.iter_mut().filter(|s| s.status.is_ok());
        for (sample, &t) in measured.zip(capture_s) {
            sample.capture_s = t;
        }
        self.retime();
    }

    /// Counts by status and the time, split into moves, settling and captures.
    pub fn summary(&self, device: &Device) -> PlanSummary {
        let count = |is: fn(&Status) -> bool| self.samples.iter().filter(|s| is(&s.status)).count();
        let mut occluded_by = BTreeMap::new();
        for b in self.samples.iter().filter_map(|s| s.blockage()) {
            *occluded_by.entry(b.describe(device)).or_insert(0) += 1;
        }
        let steps = self.steps();
        PlanSummary {
            total: self.samples.len(),
            measurable: count(Status::is_ok),
            limit: count(|s| matches!(s, Status::Limit)),
            occluded: count(|s| matches!(s, Status::Occluded { .. })),
            occluded_by,
            move_s: steps.iter().map(|s| s.move_s).sum(),
            settle_s: steps.iter().map(|s| s.settle_s).sum(),
            capture_s: steps.iter().map(|s| s.capture_s).sum(),
        }
    }

    /// Writes the plan as CSV in execution order: `index,theta_h,phi_h,theta_d,phi_d,theta_i,
    /// phi_i,theta_o,phi_o,status` (degrees), then the axis angles `turntable_deg,camera_deg,
    /// light_azimuth_deg,light_elevation_deg` (empty when excluded) and `time_s`.
    pub fn write_csv<W: Write>(&self, writer: W) -> csv::Result<()> {
        let mut out = csv::Writer::from_writer(writer);
        out.write_record([
            "index",
            "theta_h",
            "phi_h",
            "theta_d",
            "phi_d",
            "theta_i",
            "phi_i",
            "theta_o",
            "phi_o",
            "status",
            "turntable_deg",
            "camera_deg",
            "light_azimuth_deg",
            "light_elevation_deg",
            "time_s",
        ])?;
        for s in &self.samples {
            let i = Spherical::from_vector(s.wi);
            let o = Spherical::from_vector(s.wo);
            let angles = [
                s.hd.theta_h,
                s.hd.phi_h,
                s.hd.theta_d,
                s.hd.phi_d,
                i.theta_rad,
                i.phi_rad,
                o.theta_rad,
                o.phi_rad,
            ];
            let mut record: Vec<String> = vec![s.index.to_string()];
            record.extend(angles.iter().map(|a| format!("{:.6}", a.to_degrees())));
            record.push(s.status.name().to_string());
            match s.axes() {
                Some(axes) => record.extend(axes.to_degrees().iter().map(|a| format!("{a:.4}"))),
                None => record.extend(std::iter::repeat_n(String::new(), 4)),
            }
            record.push(format!("{:.3}", s.time_s));
            out.write_record(&record)?;
        }
        out.flush()?;
        Ok(())
    }
}

/// Classifies one sample and, when it is measurable, picks its position nearest in time to
/// `previous`.
fn plan_sample(
    index: usize,
    hd: HalfDiff,
    device: &Device,
    time_model: &TimeModel,
    previous: &AxisPositions,
) -> PlannedSample {
    let (wi, wo) = hd.to_directions();
    let reachable = solutions(device, wi, wo);
    let blocked: Vec<Option<Blockage>> = reachable
        .iter()
        .map(|a| blockage_within_accuracy(device, a))
        .collect();
    let alternatives: Vec<AxisPositions> = reachable
        .iter()
        .zip(&blocked)
        .filter(|(_, b)| b.is_none())
        .map(|(a, _)| *a)
        .collect();
    let quickest = alternatives.iter().copied().min_by(|a, b| {
        time_model
            .transition_s(previous, a)
            .total_cmp(&time_model.transition_s(previous, b))
    });
    let status = match (quickest, blocked.first()) {
        (Some(axes), _) => Status::Ok { axes, alternatives },
        (None, Some(&Some(blockage))) => Status::Occluded { blockage },
        (None, _) => Status::Limit,
    };
    PlannedSample {
        index,
        hd,
        wi,
        wo,
        status,
        time_s: 0.0,
        capture_s: time_model.capture_s,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn device() -> Device {
        Device::utia()
    }

    #[test]
    fn statuses_follow_the_geometry() {
        let d = device();
        let hds = [
            HalfDiff::from_degrees(10.0, 45.0, 30.0, 90.0), // ordinary: ok
            HalfDiff::from_degrees(0.0, 45.0, 0.0, 0.0),    // retro at the zenith: occluded
            HalfDiff::from_degrees(60.0, 45.0, 60.0, 0.0),  // light below the horizon: limit
        ];
        let plan = Plan::from_half_diffs(&hds, &d);
        let by_index = |i: usize| plan.samples.iter().find(|s| s.index == i).unwrap();
        assert_eq!(by_index(0).status.name(), "ok");
        assert_eq!(by_index(1).status.name(), "occluded");
        assert_eq!(by_index(2).status, Status::Limit);
        assert!(by_index(1).blockage().is_some());
        // Measured first, then excluded in order.
        let order: Vec<usize> = plan.samples.iter().map(|s| s.index).collect();
        assert_eq!(order, vec![0, 1, 2]);
        let summary = plan.summary(&d);
        assert_eq!(
            (summary.measurable, summary.limit, summary.occluded),
            (1, 1, 1)
        );
        assert_eq!(summary.occluded_by.values().sum::<usize>(), 1);
    }

    #[test]
    fn chosen_positions_give_the_planned_directions() {
        let d = device();
        let plan = Plan::from_grid(
            &[0.5, 8.0, 30.0],
            &[0.0, 9.0, 45.0],
            &[0.0, 45.0, 90.0],
            45.0,
            &d,
        );
        assert_eq!(plan.samples.len(), 27);
        for (s, axes) in plan.measured() {
            assert!(s.alternatives().contains(&axes));
            assert!(d.within_limits(&axes));
            assert_eq!(blockage_within_accuracy(&d, &axes), None);
            let (wi, wo) = axes.directions();
            assert!((wi - s.wi).length() < 1e-9 && (wo - s.wo).length() < 1e-9);
            let hd = HalfDiff::from_directions(wi, wo);
            assert!((hd.theta_h - s.hd.theta_h).abs() < 1e-9);
            assert!((hd.theta_d - s.hd.theta_d).abs() < 1e-9);
        }
    }

    #[test]
    fn limits_match_the_elevations() {
        // With the default device, a sample is out of range exactly when the light or the
        // camera is beyond 75 deg (the arms' ranges); check against the directions.
        let d = device();
        let th: Vec<f64> = (0..10).map(|i| i as f64 * 9.0).collect();
        let td: Vec<f64> = (0..10).map(|i| i as f64 * 9.0 + 1.0).collect();
        let pd = [0.0, 30.0, 60.0, 90.0];
        let plan = Plan::from_grid(&th, &td, &pd, 45.0, &d);
        for s in &plan.samples {
            let max_deg = Spherical::from_vector(s.wi)
                .theta_rad
                .max(Spherical::from_vector(s.wo).theta_rad)
                .to_degrees();
            assert_eq!(s.status == Status::Limit, max_deg > 75.0 + 1e-7, "{s:?}");
        }
    }

    #[test]
    fn times_add_up() {
        let d = device();
        let plan = Plan::from_grid(&[1.0, 10.0], &[20.0, 40.0], &[0.0, 90.0], 45.0, &d);
        let summary = plan.summary(&d);
        let sum: f64 = plan.samples.iter().map(|s| s.time_s).sum();
        assert!((sum - summary.duration_s()).abs() < 1e-9);
        assert!(
            (summary.capture_s - summary.measurable as f64 * d.capture.duration_s()).abs() < 1e-9
        );
    }

    #[test]
    fn csv_has_the_documented_columns() {
        let d = device();
        let plan = Plan::from_grid(&[0.0, 10.0], &[0.0, 30.0], &[90.0], 45.0, &d);
        let mut bytes = Vec::new();
        plan.write_csv(&mut bytes).unwrap();
        let text = String::from_utf8(bytes).unwrap();
        let mut lines = text.lines();
        assert_eq!(
            lines.next().unwrap(),
            "index,theta_h,phi_h,theta_d,phi_d,theta_i,phi_i,theta_o,phi_o,status,\
             turntable_deg,camera_deg,light_azimuth_deg,light_elevation_deg,time_s"
        );
        let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
        assert_eq!(rows.len(), 4);
        for row in &rows {
            assert_eq!(row.len(), 15);
            let measured = row[9] == "ok";
            assert_eq!(!row[10].is_empty(), measured);
        }
        // theta_h = 10, theta_d = 30, phi_d = 90 is measurable; its theta_h column reads 10.
        let row = rows.iter().find(|r| r[0] == "3").unwrap();
        assert_eq!(row[9], "ok");
        assert_eq!(row[1].parse::<f64>().unwrap(), 10.0);
        assert_eq!(row[2].parse::<f64>().unwrap(), 45.0);
    }
}
