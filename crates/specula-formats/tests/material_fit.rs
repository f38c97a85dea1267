//! `specula fit`'s library against truths it was not built from: analytic presets, whose
//! parameters the fit must recover from their tabulated values alone, and which model it
//! exports for a dielectric and for a metal.

use specula_core::compare::ErrorFigures;
use specula_core::materials::clearcoat::ClearCoat;
use specula_core::materials::conductor::RoughConductor;
use specula_core::materials::{preset, Base, Distribution, Material};
use specula_core::scattering::fresnel::conductor_rgb;
use specula_core::tabulate::tabulate;
use specula_core::Rgb;
use specula_formats::material_fit::{
    fit_material, fit_models, ExportReason, FitChoice, FitModel, MaterialFit,
};
use specula_formats::renderer_export::gltf_document;

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

/// The exported fit of `truth` with both models fitted, as `specula fit` exports it.
fn exported(truth: &Material) -> (Vec<MaterialFit>, ExportReason) {
    let fits = fit_models(&tabulate(truth, 0.0), FitChoice::Both.models(), 75.0, "t").unwrap();
    let reason = ExportReason::of(&fits);
    for fit in &fits {
        println!(
            "{:?}: {:?} {:?}",
            fit.model, fit.material.base, fit.error_within
        );
    }
    println!("exported {:?}: {reason}", fits[0].model);
    (fits, reason)
}

/// The glTF `metallicFactor` of a fit's export.
fn gltf_metallic(fit: &MaterialFit) -> f64 {
    let document: serde_json::Value =
        serde_json::from_str(&gltf_document(&fit.material).unwrap()).unwrap();
    document["materials"][0]["pbrMetallicRoughness"]["metallicFactor"]
        .as_f64()
        .unwrap()
}

#[test]
fn a_dielectric_film_is_exported_as_a_dielectric() {
    // A glossy black wrap film: a dielectric coat (index 1.5) over an almost black base, whose
    // reflection is a dielectric's Fresnel, which a conductor with k near 0 fits as well.
    let film = Material::new(
        "film",
        Base::ClearCoat(ClearCoat::new(
            Distribution::Ggx,
            0.05,
            1.5,
            Rgb::splat(0.01),
        )),
    );
    let (fits, reason) = exported(&film);
    assert_eq!(fits[0].model, FitModel::Coat, "{reason}");
    assert!(!fits[0].is_metal_like());
    assert_eq!(gltf_metallic(&fits[0]), 0.0);
    assert!(
        fits[0].material.name.contains("coat fit"),
        "{}",
        fits[0].material.name
    );
    let conductor = fits
        .iter()
        .find(|f| f.model == FitModel::Conductor)
        .unwrap();
    assert!(!conductor.is_metal_like(), "{:?}", conductor.material.base);
}

#[test]
fn a_metal_is_exported_as_a_conductor() {
    let (fits, reason) = exported(&preset("silver-925").unwrap());
    assert_eq!(fits[0].model, FitModel::Conductor, "{reason}");
    assert_eq!(reason, ExportReason::LowerError);
    assert!(fits[0].is_metal_like());
    assert_eq!(gltf_metallic(&fits[0]), 1.0);
    assert!(
        fits[0].material.name.contains("conductor fit"),
        "{}",
        fits[0].material.name
    );
}

#[test]
fn a_conductor_with_k_near_zero_goes_after_the_coat() {
    let fit = |model, base, log_rmse| {
        let figures = ErrorFigures {
            cells: 1000,
            relative_rmse: log_rmse,
            log_rmse,
            slice_mae: 0.0,
        };
        MaterialFit {
            model,
            material: Material::new("m", base),
            error_all: figures,
            error_within: figures,
            cells: 1000,
        }
    };
    let conductor = |k| {
        Base::Conductor(RoughConductor::new(
            Distribution::Ggx,
            0.1,
            Rgb::splat(1.5),
            Rgb::splat(k),
        ))
    };
    let coat = Base::ClearCoat(ClearCoat::new(Distribution::Ggx, 0.1, 1.5, Rgb::splat(0.1)));
    // A dielectric-like conductor fitted better: the coat is exported, and says why.
    let fits = [
        fit(FitModel::Conductor, conductor(0.05), 0.1),
        fit(FitModel::Coat, coat.clone(), 0.2),
    ];
    assert_eq!(
        ExportReason::of(&fits),
        ExportReason::NotMetalLike { k_max: 0.05 }
    );
    let reordered = [fits[1].clone(), fits[0].clone()];
    assert_eq!(
        ExportReason::of(&reordered),
        ExportReason::NotMetalLike { k_max: 0.05 }
    );
    // A metal's k: the lower error decides.
    let fits = [
        fit(FitModel::Conductor, conductor(3.0), 0.1),
        fit(FitModel::Coat, coat, 0.2),
    ];
    assert_eq!(ExportReason::of(&fits), ExportReason::LowerError);
    assert_eq!(ExportReason::of(&fits[..1]), ExportReason::OnlyModel);
}
