//! RGL `.bsdf` (tensor file) parser, then evaluation of whatever parsed: no panic, no NaN.
#![no_main]

use libfuzzer_sys::fuzz_target;
use specula_core::{Brdf, Spherical};
use specula_formats::rgl::RglBsdf;

fuzz_target!(|data: &[u8]| {
    if let Ok(brdf) = RglBsdf::from_bytes("fuzz", data) {
        for (ti, pi, to, po) in [
            (0.0, 0.0, 30.0, 10.0),
            (45.0, 90.0, 45.0, 270.0),
            (89.0, 5.0, 1.0, 0.0),
        ] {
            let wi = Spherical::from_degrees(ti, pi).to_vector();
            let wo = Spherical::from_degrees(to, po).to_vector();
            let value = brdf
                .eval(wi, wo)
                .expect("RGL files are measured everywhere");
            assert!(!value.is_nan(), "NaN f_r");
        }
    }
});
