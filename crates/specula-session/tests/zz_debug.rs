use specula_acquisition::device::Device;
use specula_acquisition::plan::Plan;
#[test]
fn dbg() {
    let plan = Plan::from_grid(&[0.5, 4.0, 20.0], &[10.0, 35.0, 60.0], &[30.0, 90.0], 45.0, &Device::utia());
    for (i, s) in plan.measured().enumerate() {
        let a = s.axes.unwrap();
        let (wi, wo) = a.directions();
        println!("{i} hd {:?} axes {:?} wi {wi} planned wi {} wo {wo} planned {}", s.hd, a.to_degrees(), s.wi, s.wo);
    }
}
