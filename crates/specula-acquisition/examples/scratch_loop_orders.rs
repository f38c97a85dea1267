use specula_acquisition::device::Device;
use specula_acquisition::ordering::{order_with, transition_time_s, OrderingOptions};
use specula_acquisition::plan::Plan;
use specula_core::sampling::{Family, SamplingFunction};
fn main() {
    let device = Device::utia();
    let th = SamplingFunction::new(Family::Exponential, 4.78).unwrap().positions_deg(30);
    let td: Vec<f64> = (0..30).map(|i| 3.0 * i as f64).collect();
    let pd: Vec<f64> = (0..7).map(|i| 15.0 * i as f64).collect();
    let plan = Plan::from_grid(&th, &td, &pd, 45.0, &device);
    for (n, r) in [(5, 1), (10, 1), (10, 3), (20, 3), (30, 5)] {
        let t = std::time::Instant::now();
        let o = order_with(&plan, &OrderingOptions { neighbours: n, rounds: r });
        let s = o.summary(&device);
        println!("k={n} rounds={r}: move {:.3} h settle {:.3} h motion {:.3} h in {:.2?}", s.move_s/3600.0, s.settle_s/3600.0, transition_time_s(&o)/3600.0, t.elapsed());
    }
}
