//! Material TOML files: the documented schema, round trips of every built-in material, and
//! one-line errors that name the file and the problem.

use specula_core::materials::conductor::RoughConductor;
use specula_core::materials::scratch::ScratchLobe;
use specula_core::materials::{
    builtin_database, preset, preset_names, Base, Distribution, Material,
};
use specula_core::Rgb;
use std::path::Path;

const EXAMPLE: &str = r#"
name = "my-chrome"
[base]
kind = "conductor"          # or "clearcoat"
distribution = "ggx"        # or "beckmann"
alpha = 0.02
eta = [3.1, 3.2, 2.3]       # per channel R,G,B
k = [3.3, 3.3, 3.1]
[scratch]                   # optional
weight = 0.05
alpha_along = 0.002
alpha_across = 0.2
orientation_deg = 30.0
"#;

#[test]
fn the_documented_example_reads() {
    let material = Material::from_toml_str(EXAMPLE).unwrap();
    let conductor = RoughConductor::new(
        Distribution::Ggx,
        0.02,
        Rgb::new(3.1, 3.2, 2.3),
        Rgb::new(3.3, 3.3, 3.1),
    );
    let expected = Material::new("my-chrome", Base::Conductor(conductor))
        .with_scratch(ScratchLobe::new(Distribution::Ggx, 0.05, 0.002, 0.2, 30.0));
    assert_eq!(material, expected);
}

#[test]
fn a_clear_coat_reads_with_defaults() {
    let text =
        "name = \"paint\"\n[base]\nkind = \"clearcoat\"\nalpha = 0.01\ncolor = [0.1, 0.4, 0.1]\n";
    let material = Material::from_toml_str(text).unwrap();
    let Base::ClearCoat(coat) = &material.base else {
        panic!("expected a clear coat, got {material:?}");
    };
    assert_eq!((coat.ior, coat.distribution()), (1.5, Distribution::Ggx));
    assert!(material.scratch.is_none());
}

#[test]
fn every_builtin_material_round_trips() {
    let database = builtin_database();
    assert!(database.len() >= 50, "only {} materials", database.len());
    for material in &database {
        let text = material.to_toml_string();
        let back = Material::from_toml_str(&text).unwrap_or_else(|e| panic!("{text}\n{e}"));
        assert_eq!(&back, material, "{text}");
    }
    for name in preset_names() {
        assert!(
            database.iter().any(|m| m.name == name),
            "{name} missing from the database"
        );
    }
}

#[test]
fn names_are_unique_and_resolve() {
    let database = builtin_database();
    let mut names: Vec<&str> = database.iter().map(|m| m.name.as_str()).collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), database.len(), "duplicate names");
    for name in names {
        assert_eq!(preset(name).map(|m| m.name), Some(name.to_string()));
    }
    assert!(preset("unobtainium").is_none());
}

#[test]
fn files_round_trip_through_disk() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("green.toml");
    let original = preset("green-paint").unwrap();
    std::fs::write(&path, original.to_toml_string()).unwrap();
    assert_eq!(Material::from_toml_file(&path).unwrap(), original);
}

#[test]
fn material_embeds_in_other_documents() {
    #[derive(serde::Deserialize)]
    struct Simulation {
        material: Material,
    }
    let text = EXAMPLE
        .replace("[base]", "[material.base]")
        .replace("[scratch]", "[material.scratch]");
    let text = text.replace("name = \"my-chrome\"", "[material]\nname = \"my-chrome\"");
    let simulation: Simulation = toml::from_str(&text).unwrap();
    assert_eq!(
        simulation.material,
        Material::from_toml_str(EXAMPLE).unwrap()
    );
}

/// Writes `text` to a file and returns the error message of reading it.
fn error_of(text: &str) -> (String, String) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.toml");
    std::fs::write(&path, text).unwrap();
    let message = Material::from_toml_file(&path).unwrap_err().to_string();
    (message, path.display().to_string())
}

fn assert_error(text: &str, expected: &[&str]) {
    let (message, path) = error_of(text);
    assert!(!message.contains('\n'), "not one line: {message}");
    assert!(
        message.starts_with(&format!("{path}: ")),
        "no file name: {message}"
    );
    for part in expected {
        assert!(message.contains(part), "{message:?} lacks {part:?}");
    }
}

#[test]
fn bad_files_give_one_line_errors() {
    assert_error(
        &EXAMPLE.replace("\"conductor\"", "\"plastic\""),
        &["unknown variant `plastic`", "conductor", "clearcoat"],
    );
    assert_error(
        &EXAMPLE.replace("alpha = 0.02\n", ""),
        &["missing field `alpha`", "line"],
    );
    assert_error(
        &EXAMPLE.replace("alpha = 0.02", "alpha = -0.1"),
        &["base.alpha", "[0.001, 1]", "-0.1"],
    );
    assert_error(
        &EXAMPLE.replace("weight = 0.05", "weight = 1.5"),
        &["scratch.weight", "1.5"],
    );
    assert_error(
        &EXAMPLE.replace("k = [3.3, 3.3, 3.1]", "k = [3.3, -3.3, 3.1]"),
        &["base.k"],
    );
    // Errors inside [base] point at the table's line (its fields are buffered by the `kind` tag).
    assert_error(
        &EXAMPLE.replace("eta = [3.1, 3.2, 2.3]", "eta = [3.1, 3.2]"),
        &["line 3", "length 3"],
    );
    assert_error(
        &EXAMPLE.replace("distribution = \"ggx\"", "distribution = \"phong\""),
        &["unknown variant `phong`", "ggx", "beckmann"],
    );
    assert_error(
        &EXAMPLE.replace("alpha = 0.02", "alpah = 0.02"),
        &["unknown field `alpah`"],
    );
    assert_error("name = \"x\"\n[base\nkind = 1", &["line 2"]);
    assert_error(
        "name = \"p\"\n[base]\nkind = \"clearcoat\"\nalpha = 0.01\ncolor = [1.0, 0.5, 0.5]\n",
        &["base.color", "0.95"],
    );
    assert_error(
        &EXAMPLE.replace("name = \"my-chrome\"", "name = \" \""),
        &["name must be non-empty"],
    );
}

#[test]
fn a_missing_file_names_itself() {
    let path = Path::new("/nonexistent/specula/material.toml");
    let message = Material::from_toml_file(path).unwrap_err().to_string();
    assert!(
        message.starts_with("/nonexistent/specula/material.toml: cannot read"),
        "{message}"
    );
    assert!(!message.contains('\n'));
}

#[test]
fn absurd_values_and_sizes_are_refused_at_load() {
    // eta = 1e300 used to load and evaluate to NaN.
    assert_error(
        &EXAMPLE.replace("eta = [3.1, 3.2, 2.3]", "eta = [1e300, 3.2, 2.3]"),
        &["base.eta", "(0, 100]", "1e300"],
    );
    assert_error(
        &EXAMPLE.replace("k = [3.3, 3.3, 3.1]", "k = [3.3, 3.3, 1e300]"),
        &["base.k", "[0, 100]"],
    );
    assert_error(
        &EXAMPLE.replace("alpha = 0.02", "alpha = nan"),
        &["base.alpha", "NaN"],
    );
    // A 4 GiB file is refused by its size, not read.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("huge.toml");
    std::fs::File::create(&path)
        .unwrap()
        .set_len(4 << 30)
        .unwrap();
    let message = Material::from_toml_file(&path).unwrap_err().to_string();
    assert!(
        message.contains("huge.toml") && message.contains("4294967296 bytes"),
        "{message}"
    );
}
