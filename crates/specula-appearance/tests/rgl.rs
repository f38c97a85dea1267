//! The figures of the real RGL measurements in `../shared/data/measured/rgl_bsdf` (skipped
//! with a message when the folder is absent): what is known of the materials without the
//! BRDF (a white matte paper, metallic effect car paints, a solid paint) must show.

use specula_appearance::{appearance, Options};
use std::path::Path;

fn rgl(name: &str) -> Option<specula_formats::BrdfSource> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/data/measured/rgl_bsdf")
        .join(format!("{name}_rgb.bsdf"));
    if !path.is_file() {
        eprintln!("skipping: {} is absent", path.display());
        return None;
    }
    Some(specula_formats::load_brdf(&path.to_string_lossy()).expect("a readable RGL file"))
}

#[test]
fn white_paper_is_matte_light_and_nearly_neutral() {
    let Some(paper) = rgl("paper_white") else {
        return;
    };
    let f = appearance(paper.as_ref(), &Options::default());
    println!("paper_white: {f:?}");
    assert!(f.gloss[1] < 5.0, "60 deg gloss {}", f.gloss[1]);
    assert!(
        f.doi < 5.0 && f.haze > 90.0,
        "DOI {} haze {}",
        f.doi,
        f.haze
    );
    let lab_45 = f.colour[2].expect("measured");
    assert!(
        lab_45[0] > 85.0 && lab_45[1].abs() < 10.0 && lab_45[2].abs() < 10.0,
        "{lab_45:?}"
    );
    assert!(f.flop_index.unwrap() < 2.0);
}

#[test]
fn effect_car_paints_flop_and_a_solid_paint_does_not() {
    for name in ["cc_ibiza_sunset", "cc_iris_purple_gem"] {
        let Some(paint) = rgl(name) else { return };
        let f = appearance(paint.as_ref(), &Options::default());
        let flop = f.flop_index.unwrap();
        assert!(flop > 10.0, "{name}: flop index {flop}");
        assert!(f.warnings.is_empty(), "{name}: {:?}", f.warnings);
    }
    let Some(solid) = rgl("colodur_napoli_4f") else {
        return;
    };
    let f = appearance(solid.as_ref(), &Options::default());
    assert!(f.flop_index.unwrap() < 3.0, "flop index {:?}", f.flop_index);
}
