//! `specula fit` end to end: the green paint fitted with the coat model, every export written
//! and read back by its own format's rules; a checked range refused as a usage error.

use std::process::Command;

fn specula() -> Command {
    Command::new(env!("CARGO_BIN_EXE_specula"))
}

#[test]
fn fit_writes_every_export() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name);
    let output = specula()
        .args(["fit", "green-paint", "--model", "coat", "--out"])
        .arg(path("fit.toml"))
        .arg("--mitsuba")
        .arg(path("fit.xml"))
        .arg("--pbrt")
        .arg(path("fit.pbrt"))
        .arg("--gltf")
        .arg(path("fit.gltf"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{stdout} {}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(
        stdout.starts_with("model,set,cells,relative_rmse,log_rmse,slice_mae"),
        "{stdout}"
    );
    let material = specula_core::materials::Material::from_toml_file(path("fit.toml")).unwrap();
    let specula_core::materials::Base::ClearCoat(coat) = &material.base else {
        panic!("a coat fit gives a coat")
    };
    assert!((coat.alpha() - 0.008).abs() < 1e-5, "{}", coat.alpha());
    let xml = std::fs::read_to_string(path("fit.xml")).unwrap();
    assert!(xml.contains(r#"<bsdf type="roughplastic""#), "{xml}");
    let pbrt = std::fs::read_to_string(path("fit.pbrt")).unwrap();
    assert!(pbrt.contains(r#"Material "coateddiffuse""#), "{pbrt}");
    let gltf: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path("fit.gltf")).unwrap()).unwrap();
    assert_eq!(gltf["asset"]["version"], "2.0");
    assert_eq!(gltf["extensionsUsed"][0], "KHR_materials_ior");
}

#[test]
fn fit_refuses_an_elevation_out_of_range() {
    let output = specula()
        .args(["fit", "green-paint", "--max-elevation", "0"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2));
}
