//! Bad files of every format, loaded the way every command loads a BRDF (`load_brdf`): a
//! one-line error that names the file and says what is wrong, never a panic.

mod common;

use common::measured;
use specula_core::merl::CELLS;
use specula_core::MerlBrdf;
use specula_formats::load_brdf;
use specula_formats::utia::{self, UtiaBrdf};
use std::path::Path;

/// Writes `bytes` as `name` in `dir`, loads it, and checks the error mentions the file and `problem`.
fn expect_error(dir: &Path, name: &str, bytes: &[u8], problem: &str) {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    let message = match load_brdf(path.to_str().unwrap()) {
        Ok(_) => panic!("{name}: loaded, expected an error about {problem:?}"),
        Err(e) => format!("{e:#}"),
    };
    assert!(
        message.starts_with(&path.display().to_string()),
        "{message}"
    );
    assert!(message.contains(problem), "{name}: {message}");
    assert!(!message.contains('\n'), "{message}");
}

/// Where a field's record sits in an RGL tensor header: (start of its shape, start of its offset).
fn field_record(bytes: &[u8], wanted: &str) -> (usize, usize) {
    let count = u32::from_le_bytes(bytes[14..18].try_into().unwrap());
    let mut at = 18;
    for _ in 0..count {
        let len = u16::from_le_bytes([bytes[at], bytes[at + 1]]) as usize;
        let name = std::str::from_utf8(&bytes[at + 2..at + 2 + len])
            .unwrap()
            .to_string();
        at += 2 + len;
        let rank = u16::from_le_bytes([bytes[at], bytes[at + 1]]) as usize;
        let offset_at = at + 3;
        let shape_at = at + 11;
        if name == wanted {
            return (shape_at, offset_at);
        }
        at = shape_at + 8 * rank;
    }
    panic!("no field {wanted}");
}

#[test]
fn bad_rgl_files() {
    let dir = tempfile::tempdir().unwrap();
    let Some(path) = measured("rgl_bsdf/satin_rosaline_rgb.bsdf") else {
        return;
    };
    let good = std::fs::read(path).unwrap();
    expect_error(
        dir.path(),
        "truncated.bsdf",
        &good[..good.len() / 2],
        "truncated: field",
    );
    expect_error(dir.path(), "header.bsdf", &good[..40], "truncated header");
    let mut magic = good.clone();
    magic[..6].copy_from_slice(b"tensor");
    magic[0] = b'X';
    expect_error(dir.path(), "magic.bsdf", &magic, "not a tensor file");

    let (shape_at, _) = field_record(&good, "rgb");
    let mut shape = good.clone();
    shape[shape_at + 16..shape_at + 24].copy_from_slice(&2u64.to_le_bytes());
    expect_error(
        dir.path(),
        "shape.bsdf",
        &shape,
        "field 'rgb' has shape [1, 8, 2, 32, 32]",
    );

    let (shape_at, _) = field_record(&good, "phi_i");
    let mut aniso = good.clone();
    aniso[shape_at..shape_at + 8].copy_from_slice(&2u64.to_le_bytes());
    expect_error(dir.path(), "aniso.bsdf", &aniso, "anisotropic material");

    let (_, offset_at) = field_record(&good, "ndf");
    let data = u64::from_le_bytes(good[offset_at..offset_at + 8].try_into().unwrap()) as usize;
    let mut nan = good.clone();
    nan[data + 40..data + 44].copy_from_slice(&f32::NAN.to_le_bytes());
    expect_error(
        dir.path(),
        "nan.bsdf",
        &nan,
        "field 'ndf' holds a non-finite value (NaN) at element 10",
    );

    let (_, offset_at) = field_record(&good, "sigma");
    let data = u64::from_le_bytes(good[offset_at..offset_at + 8].try_into().unwrap()) as usize;
    let mut zero = good.clone();
    zero[data..data + 4].copy_from_slice(&0f32.to_le_bytes());
    expect_error(
        dir.path(),
        "sigma.bsdf",
        &zero,
        "field 'sigma' holds values that are not positive",
    );
}

#[test]
fn bad_merl_files() {
    let dir = tempfile::tempdir().unwrap();
    let good = MerlBrdf::empty("x").to_bytes();
    expect_error(
        dir.path(),
        "truncated.binary",
        &good[..good.len() - 8],
        "truncated payload",
    );
    let mut dims = good.clone();
    dims[8..12].copy_from_slice(&360i32.to_le_bytes());
    expect_error(dir.path(), "dims.binary", &dims, "dimensions 90 x 90 x 360");
    let mut nan = good.clone();
    let at = 12 + 8 * (2 * CELLS + 5);
    nan[at..at + 8].copy_from_slice(&f64::INFINITY.to_le_bytes());
    expect_error(
        dir.path(),
        "nan.binary",
        &nan,
        "non-finite value inf in the blue channel",
    );
}

#[test]
fn bad_utia_files() {
    let dir = tempfile::tempdir().unwrap();
    let good = UtiaBrdf::empty("x").to_bytes();
    expect_error(
        dir.path(),
        "truncated.bin",
        &good[..1000],
        "truncated: 1000 bytes",
    );
    let dense = vec![0u8; 3 * 44 * 180 * 44 * 180 / 64 * 8];
    expect_error(
        dir.path(),
        "dense.bin",
        &dense,
        "a UTIA BRDF file has 1990656",
    );
    let mut long = good.clone();
    long.extend_from_slice(&[0; 8]);
    expect_error(dir.path(), "long.bin", &long, "over-long");
    let mut nan = good.clone();
    nan[8 * 17..8 * 18].copy_from_slice(&f64::NAN.to_le_bytes());
    expect_error(
        dir.path(),
        "nan.bin",
        &nan,
        "non-finite value NaN in the red channel",
    );
    assert_eq!(good.len(), utia::FILE_BYTES);
}

#[test]
fn bad_samples_files() {
    let dir = tempfile::tempdir().unwrap();
    let header = "theta_h,phi_h,theta_d,phi_d,r,g,b\n";
    expect_error(
        dir.path(),
        "header.csv",
        b"theta,phi,r,g,b\n1,2,3,4,5\n",
        "header is 'theta,phi,r,g,b'",
    );
    let truncated = format!("{header}1,45,40,90,0.5,0.5,0.5\n2,45,40,9");
    expect_error(dir.path(), "truncated.csv", truncated.as_bytes(), "row 3:");
    let wide = format!("{header}1,45,40,90,0.5,0.5,0.5,7\n");
    expect_error(dir.path(), "wide.csv", wide.as_bytes(), "row 2:");
    let nan = format!("{header}1,45,40,90,0.5,nan,0.5\n");
    expect_error(
        dir.path(),
        "nan.csv",
        nan.as_bytes(),
        "row 2: g is not finite",
    );
    expect_error(dir.path(), "empty.csv", header.as_bytes(), "no samples");
}

#[test]
fn bad_fit_names_and_missing_files() {
    let err = format!("{:#}", load_brdf("nbrdf-rgl:gold").err().unwrap());
    assert!(
        err.contains("nbrdf-rgl:gold") && err.contains("51"),
        "{err}"
    );
    let err = format!("{:#}", load_brdf("/no/such/file.bsdf").err().unwrap());
    assert!(err.contains("/no/such/file.bsdf"), "{err}");
}
