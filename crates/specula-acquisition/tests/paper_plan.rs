//! The paper's plan (section 5.3) on the default device: how many samples it reaches, how
//! long the paper's way of working takes and how much ordering saves.

use specula_acquisition::device::Device;
use specula_acquisition::ordering::{order, transition_time_s};
use specula_acquisition::plan::Plan;
use specula_core::sampling::{Family, SamplingFunction};

/// The paper's count of measured samples.
const PAPER_MEASURED: f64 = 4073.0;
/// The paper's measurement time, hours.
const PAPER_HOURS: f64 = 15.0;

fn paper_plan(k: f64, device: &Device) -> Plan {
    let theta_h = SamplingFunction::new(Family::Exponential, k)
        .unwrap()
        .positions_deg(30);
    let theta_d: Vec<f64> = (0..30).map(|i| 3.0 * i as f64).collect();
    let phi_d: Vec<f64> = (0..7).map(|i| 15.0 * i as f64).collect();
    Plan::from_grid(&theta_h, &theta_d, &phi_d, 45.0, device)
}

#[test]
fn paper_plan_counts_times_and_ordering() {
    let device = Device::utia();
    for k in [4.78, 5.64] {
        let plan = paper_plan(k, &device);
        let summary = plan.summary(&device);
        assert_eq!(summary.total, 6300);
        assert_eq!(summary.measurable + summary.limit + summary.occluded, 6300);
        let off = summary.measurable as f64 / PAPER_MEASURED - 1.0;
        assert!(
            off.abs() < 0.07,
            "k {k}: {} measurable ({off:+.3})",
            summary.measurable
        );

        // Every retro-reflection (theta_d = 0) within reach is occluded by the light head.
        for s in plan.samples.iter().filter(|s| s.hd.theta_d == 0.0) {
            assert!(!s.status.is_ok(), "{s:?}");
        }

        // The paper's way: fixed bracket, nested loops: about 15 h for 4073 samples.
        let hours_per_paper_count =
            summary.duration_s() / 3600.0 * PAPER_MEASURED / summary.measurable as f64;
        assert!(
            (hours_per_paper_count / PAPER_HOURS - 1.0).abs() < 0.05,
            "k {k}: {hours_per_paper_count} h for 4073 samples"
        );

        // Ordering: the same samples, at least 30 percent less motion (moves + settling).
        let ordered = order(&plan);
        let after = ordered.summary(&device);
        assert_eq!(after.measurable, summary.measurable);
        let (nested_s, ordered_s) = (transition_time_s(&plan), transition_time_s(&ordered));
        assert!(
            ordered_s < 0.7 * nested_s,
            "k {k}: motion {ordered_s} s vs nested {nested_s} s"
        );
    }
}
