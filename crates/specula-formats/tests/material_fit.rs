//! `specula fit`'s library against truths it was not built from: analytic presets, whose
//! parameters the fit must recover from their tabulated values alone.

use specula_core::materials::{preset, Base};
use specula_core::scattering::fresnel::conductor_rgb;
use specula_core::tabulate::tabulate;
use specula_formats::material_fit::{fit_material, FitModel};

#[test]
fn coat_fit_recovers_the_green_paint() {
    let paint = preset("green-paint").unwrap();
    let Base::ClearCoat(truth) = &paint.base else {
        panic!("the paint is a coat")
    };
    let fit = fit_material(&tabulate(&paint, 0.0), FitModel::Coat, 75.0, "paint").unwrap();
    let Base::ClearCoat(coat) = &fit.material.base else {
        panic!("a coat fit gives a coat")
    };
    println!("{coat:?} {:?}", fit.error_within);
    assert!((coat.alpha() / truth.alpha() - 1.0).abs() < 1e-3);
    assert!((coat.ior / truth.ior - 1.0).abs() < 1e-3);
    assert!((coat.base_color - truth.base_color).abs().max_element() < 1e-3);
    assert!(fit.error_within.log_rmse < 1e-4 && fit.error_within.relative_rmse < 1e-3);
}

#[test]
fn conductor_fit_recovers_silver() {
    // eta and k are nearly degenerate in reflectance (many pairs give nearly the same Fresnel
    // curve), so the fit is held to the curve itself and to the roughness.
    let silver = preset("silver-925").unwrap();
    let Base::Conductor(truth) = &silver.base else {
        panic!("silver is a conductor")
    };
    let fit = fit_material(&tabulate(&silver, 0.0), FitModel::Conductor, 75.0, "s").unwrap();
    let Base::Conductor(metal) = &fit.material.base else {
        panic!("a conductor fit gives a conductor")
    };
    println!("{metal:?} {:?}", fit.error_within);
    assert!((metal.alpha() / truth.alpha() - 1.0).abs() < 1e-3);
    for cos in [1.0, 0.8, 0.5, 0.3] {
        let fitted = conductor_rgb(cos, metal.eta, metal.k);
        let expected = conductor_rgb(cos, truth.eta, truth.k);
        assert!(
            (fitted - expected).abs().max_element() < 1e-4,
            "{cos}: {fitted} {expected}"
        );
    }
    assert!(fit.error_within.log_rmse < 1e-4 && fit.error_within.relative_rmse < 1e-3);
}
