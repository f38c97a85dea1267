//! `specula info`: what a MERL file holds.

use anyhow::Result;
use specula_core::merl::{theta_h_centre_deg, Bin, MerlBrdf, CELLS};
use std::path::PathBuf;

/// Describe a MERL .binary file: its dimensions, how many cells are measured and missing,
/// the per-channel minimum, maximum and mean of f_r (1/sr) over the measured cells, and
/// where the peak (the largest channel mean) lies.
#[derive(clap::Args)]
pub struct Args {
    /// The MERL .binary file.
    pub file: PathBuf,
}

pub fn run(args: Args) -> Result<()> {
    let table = MerlBrdf::read(&args.file)?;
    let measured = table.measured_count();
    println!("file: {}", args.file.display());
    println!("dimensions: 90 x 90 x 180 (theta_h x theta_d x phi_d)");
    println!("measured: {measured}");
    println!("missing: {}", CELLS - measured);
    if measured == 0 {
        return Ok(());
    }
    let mut min = [f64::INFINITY; 3];
    let mut max = [f64::NEG_INFINITY; 3];
    let mut sum = [0.0; 3];
    let mut peak = (f64::NEG_INFINITY, 0);
    for index in 0..CELLS {
        let Some(v) = table.cell(index) else { continue };
        for c in 0..3 {
            min[c] = min[c].min(v[c]);
            max[c] = max[c].max(v[c]);
            sum[c] += v[c];
        }
        let mean = v.element_sum() / 3.0;
        if mean > peak.0 {
            peak = (mean, index);
        }
    }
    for (c, name) in ["red", "green", "blue"].iter().enumerate() {
        println!(
            "{name}: min={:.6e} max={:.6e} mean={:.6e} (1/sr)",
            min[c],
            max[c],
            sum[c] / measured as f64
        );
    }
    let bin = Bin::from_index(peak.1);
    println!(
        "peak: {:.6e} 1/sr (channel mean) at theta_h={:.4} theta_d={:.1} phi_d={:.1} deg (bin {}, {}, {})",
        peak.0,
        theta_h_centre_deg(bin.theta_h_i),
        bin.theta_d_i as f64 + 0.5,
        bin.phi_d_i as f64 + 0.5,
        bin.theta_h_i,
        bin.theta_d_i,
        bin.phi_d_i
    );
    Ok(())
}
