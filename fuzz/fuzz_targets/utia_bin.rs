//! UTIA `.bin` parser, then interpolation of whatever parsed: no panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use specula_core::{Brdf, Spherical};
use specula_formats::utia::{UtiaBrdf, FILE_BYTES};

fuzz_target!(|data: &[u8]| {
    // Inputs shorter than a file are padded with their own bytes so that the fuzzer reaches
    // the value checks and the interpolation, not only the size check.
    let _ = UtiaBrdf::from_bytes("fuzz", data);
    if data.is_empty() {
        return;
    }
    let padded: Vec<u8> = data.iter().copied().cycle().take(FILE_BYTES).collect();
    if let Ok(table) = UtiaBrdf::from_bytes("fuzz", &padded) {
        let wi = Spherical::from_degrees(20.0, 359.9).to_vector();
        let wo = Spherical::from_degrees(74.9, 3.0).to_vector();
        let _ = table.eval(wi, wo);
        let _ = table.to_bytes();
    }
});
