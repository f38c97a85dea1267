//! Specula's MERL lookup against an independent port of MERL's reference reader
//! (`tools/merl_reference_lookup.py`): the same direction pairs must land in the same cells.

use specula_core::merl::{MerlBrdf, CELLS};
use specula_core::{Brdf, Rgb, Spherical};

/// A table whose every cell holds its own flat index (in 1/sr, all channels).
fn index_table() -> MerlBrdf {
    let mut table = MerlBrdf::empty("index");
    for i in 0..CELLS {
        table.set_cell(i, Some(Rgb::splat(i as f64)));
    }
    table
}

#[test]
fn lookups_match_the_reference_reader() {
    let table = index_table();
    let text = include_str!("data/merl_reference_lookup.csv");
    let mut checked = 0;
    for line in text.lines().skip(1) {
        let fields: Vec<f64> = line.split(',').map(|f| f.parse().unwrap()).collect();
        let wi = Spherical::from_degrees(fields[0], fields[1]).to_vector();
        let wo = Spherical::from_degrees(fields[2], fields[3]).to_vector();
        let expected = fields[4] as usize;
        let value = table.eval(wi, wo).expect("every cell is measured");
        assert_eq!(value.x.round() as usize, expected, "directions {line}");
        checked += 1;
    }
    assert_eq!(checked, 3000);
}

#[test]
fn not_measured_cells_stay_not_measured_through_a_file() {
    let mut table = index_table();
    table.set_cell(12_345, None);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("holes.binary");
    table.write(&path).unwrap();
    let back = MerlBrdf::read(&path).unwrap();
    assert_eq!(back.cell(12_345), None);
    assert_eq!(back.measured_count(), CELLS - 1);
    let bytes = std::fs::read(&path).unwrap();
    let at = 12 + 8 * 12_345;
    assert!(f64::from_le_bytes(bytes[at..at + 8].try_into().unwrap()) < 0.0);
}

#[test]
fn reading_a_directory_or_a_missing_file_names_it() {
    let dir = tempfile::tempdir().unwrap();
    let err = MerlBrdf::read(dir.path()).unwrap_err().to_string();
    assert!(
        err.contains(&dir.path().display().to_string()) && err.contains("directory"),
        "{err}"
    );
    let missing = dir.path().join("nope.binary");
    let err = MerlBrdf::read(&missing).unwrap_err().to_string();
    assert!(err.contains("nope.binary"), "{err}");
    assert!(!err.contains('\n'));
}
