//! Samples `.csv` parser (and format sniffing), then binning: no panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use specula_core::Brdf;
use specula_core::HalfDiff;
use specula_formats::convert::FileFormat;
use specula_formats::samples_csv::SampleSet;

fuzz_target!(|data: &[u8]| {
    let _ = FileFormat::sniff(data, data.len() as u64);
    if let Ok(set) = SampleSet::from_csv("fuzz", data) {
        let _ = set.eval_half_diff(HalfDiff::from_degrees(1.0, 0.0, 40.0, 90.0));
        let mut out = Vec::new();
        set.write_to(&mut out).expect("writing to memory");
    }
});
