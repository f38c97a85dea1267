//! MERL `.binary` parser (`specula_core::merl::MerlBrdf::from_bytes`): no panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use specula_core::MerlBrdf;

fuzz_target!(|data: &[u8]| {
    let _ = MerlBrdf::from_bytes("fuzz", data);
});
