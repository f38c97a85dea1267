//! Figures read from a MERL table agree with the material it tabulates: every measured
//! result is a table, and a colour or gloss tolerance is only worth checking when the table
//! does not move the figures by more than the tolerance itself.

use specula_appearance::{appearance, Options};
use specula_core::materials::preset;
use specula_core::tabulate::tabulate;

/// Largest CIEDE2000 at any aspecular angle between a material and its table.
const MAX_DE00: f64 = 0.5;
/// Largest relative gloss difference at any geometry between a material and its table.
const MAX_GLOSS_RELATIVE: f64 = 0.01;

#[test]
fn a_tabulated_material_reads_the_figures_of_the_material() {
    for name in ["silver-925", "chrome", "green-paint"] {
        let material = preset(name).unwrap();
        let table = tabulate(&material, 0.0);
        let exact = appearance(&material, &Options::default());
        let tabled = appearance(&table, &Options::default());
        let differences = tabled.against(&exact);
        for (k, de00) in differences.delta_e00.iter().enumerate() {
            let de00 = de00.expect("every colour reading is measured");
            assert!(
                de00 <= MAX_DE00,
                "{name}: dE00 {de00:.3} at reading {k} (L* {:?} from the table, {:?} exact)",
                tabled.colour[k],
                exact.colour[k]
            );
        }
        for (k, (t, e)) in tabled.gloss.iter().zip(&exact.gloss).enumerate() {
            let relative = (t - e).abs() / e;
            assert!(
                relative <= MAX_GLOSS_RELATIVE,
                "{name}: gloss {t:.3} GU from the table, {e:.3} exact at geometry {k}"
            );
        }
    }
}
