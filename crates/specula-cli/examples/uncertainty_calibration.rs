//! Calibrates the uncertainty's scales ([`specula_reconstruct::uncertainty::Scales`]) on
//! measured truths: for each `TABLE=TRUTH` (a table `specula measure --truth TRUTH --out
//! TABLE` wrote, with its session beside it), the cell coverage at k = 2 over a grid of the
//! reconstruction and deblurring scales.
//!
//!   cargo run --release -p specula-cli --example uncertainty_calibration -- T.binary=TRUTH ...
//!
//! Per table, the median of each term over the measured and interpolated cells within
//! 75 deg at the calibrated scales; `COV=1` adds the cell coverage at those scales or at
//! `COV_RECONSTRUCTION` and `COV_DEBLUR` (a line `COV TABLE FRACTION`), `GRID=1` the coverage grid (at
//! `GRID_CORE`'s core term), `BANDS=1` the coverage and the terms'
//! medians by theta_h band, `SCATTER=1` how far the samples lie from the truth in their noise.
//! `WRITE=1` rewrites
//! `T.uncertainty.binary` with the estimate of this build (as `specula measure` would write
//! it from the same session). `BATCHES=389,536,635` times what the sequential main stage
//! does after each batch of that many samples (the table without the response, then its
//! uncertainty), on the first samples of the session.

use specula_accuracy::coverage::cell_coverage;
use specula_core::merl::MerlBrdf;
use specula_core::statistics::normal_scale_of_absolute;
use specula_core::tabulate::tabulate;
use specula_reconstruct::phi_d_halves::reconstruct_halves;
use specula_reconstruct::provenance::Provenance;
use specula_reconstruct::uncertainty::{sidecar_path, CellTerms, Scales, Terms, UncertaintyInputs};
use specula_reconstruct::Method;
use specula_session::workflow::session_main_samples;
use std::path::PathBuf;

const RECONSTRUCTION: [f64; 8] = [0.25, 0.5, 0.6, 0.7, 0.8, 1.0, 1.5, 2.0];
const DEBLUR: [f64; 6] = [0.0, 1.0, 2.0, 3.0, 4.0, 6.0];

fn main() -> anyhow::Result<()> {
    for pair in std::env::args().skip(1) {
        let (table_path, truth_name) = pair
            .split_once('=')
            .ok_or_else(|| anyhow::anyhow!("{pair}: expected TABLE=TRUTH"))?;
        let table_path = PathBuf::from(table_path);
        let session = table_path.with_extension("session.sqlite");
        let (samples, response) = session_main_samples(&session)?;
        let through = response.as_ref().map(|fit| &fit.response);
        let reconstruction = reconstruct_halves(&samples, Method::Lobe, "t", through, None)?;
        let table = reconstruction.brdf.clone();
        let provenance = reconstruction.provenance.clone();
        let phi_h_rad = specula_core::GridSpec::paper().phi_h_deg.to_radians();
        let truth = tabulate(specula_formats::load_brdf(truth_name)?.as_ref(), phi_h_rad);
        let inputs = UncertaintyInputs {
            samples: &samples,
            method: Method::Lobe,
            prior: None,
        };
        let started = std::time::Instant::now();
        let terms = Terms::of(&inputs, &reconstruction)?;
        let default = terms.combined(&table, &provenance, Scales::default());
        let spent = started.elapsed();
        let written = default.absolute(&table).to_bytes().len();
        println!(
            "uncertainty terms and cells: {:.1} s ({written} bytes)",
            spent.as_secs_f64()
        );
        if let Ok(batches) = std::env::var("BATCHES") {
            time_batches(&samples, &batches)?;
        }
        if std::env::var_os("WRITE").is_some() {
            default.absolute(&table).write(&sidecar_path(&table_path))?;
        }
        println!("{} {truth_name}", table_path.display());
        term_medians(&table, &terms, &provenance);
        for line in default.lines() {
            println!("{line}");
        }
        if std::env::var_os("COV").is_some() {
            let scales = scales_from_env("COV", Scales::default())?;
            let u = terms.combined(&table, &provenance, scales);
            let c = cell_coverage(&table, &u.absolute(&table), &provenance, &truth, 75.0);
            println!(
                "COV {} {:.4}",
                table_path.display(),
                c.both.fraction().unwrap_or(f64::NAN)
            );
        }
        if std::env::var_os("SCATTER").is_some() {
            noise_scatter(&samples, truth_name)?;
        }
        if std::env::var_os("BANDS").is_some() {
            bands(&table, &terms, &provenance, &truth)?;
        }
        if std::env::var_os("GRID").is_none() {
            continue;
        }
        let grid_scales = scales_from_env("GRID", Scales::default())?;
        print!("recon\\deblur");
        for d in DEBLUR {
            print!(" {d:>7}");
        }
        println!();
        for r in RECONSTRUCTION {
            print!("{r:>12}");
            for d in DEBLUR {
                let u = terms.combined(
                    &table,
                    &provenance,
                    Scales {
                        reconstruction: r,
                        deblur: d,
                        ..grid_scales
                    },
                );
                let c = cell_coverage(&table, &u.absolute(&table), &provenance, &truth, 75.0);
                print!(" {:>7.4}", c.both.fraction().unwrap_or(f64::NAN));
            }
            println!();
        }
    }
    Ok(())
}

/// How far the samples lie from the truth at their nominal directions, in their own noise
/// ([`specula_core::Sample::noise_rel`]) and in all: a scale of about 1 says the noise
/// explains the scatter (the blur, the positioning and a calibration's bias add to it).
fn noise_scatter(samples: &[specula_core::Sample], truth_name: &str) -> anyhow::Result<()> {
    let truth = specula_formats::load_brdf(truth_name)?;
    let (mut in_noise, mut in_all) = (Vec::new(), Vec::new());
    for s in samples {
        let (Some(noise), Some(t)) = (s.noise_rel, truth.eval_half_diff(s.hd)) else {
            continue;
        };
        for c in 0..3 {
            let d = (s.value[c] / t[c]).ln().abs();
            if d.is_finite() {
                in_noise.push(d / noise[c]);
                in_all.push(d);
            }
        }
    }
    println!(
        "SCATTER {} values: |ln(sample / truth)| has the scale of {:.3} of their noise, {:.6} in all",
        in_all.len(),
        normal_scale_of_absolute(&mut in_noise),
        normal_scale_of_absolute(&mut in_all)
    );
    Ok(())
}

/// Times the reconstruction without the response and the uncertainty estimate of the first
/// `n` samples for each `n` of the comma-separated `batches`.
fn time_batches(samples: &[specula_core::Sample], batches: &str) -> anyhow::Result<()> {
    for n in batches.split(',') {
        let n: usize = n.trim().parse()?;
        let samples = &samples[..n.min(samples.len())];
        let started = std::time::Instant::now();
        let none = None::<&dyn specula_core::capture::CaptureResponse>;
        let table = reconstruct_halves(samples, Method::Lobe, "batch", none, None)?;
        let reconstructed = started.elapsed();
        let inputs = UncertaintyInputs {
            samples,
            method: Method::Lobe,
            prior: None,
        };
        specula_reconstruct::uncertainty::estimate(&inputs, &table)?;
        println!(
            "batch of {n} samples: table {:.2} s, uncertainty {:.2} s",
            reconstructed.as_secs_f64(),
            (started.elapsed() - reconstructed).as_secs_f64()
        );
    }
    Ok(())
}

/// The median of each term over the measured and interpolated cells and channels within
/// 75 deg, at the calibrated scales.
fn term_medians(table: &MerlBrdf, terms: &Terms, provenance: &Provenance) {
    use specula_core::merl::{Bin, CELLS};
    let cells: Vec<CellTerms> = (0..CELLS)
        .filter(|&i| !provenance.cells[i].is_extrapolated())
        .filter(|&i| specula_accuracy::within_elevation(Bin::from_index(i).centre(0.0), 75.0))
        .filter_map(|i| terms.cell_terms(i, table, provenance, Scales::default()))
        .flatten()
        .collect();
    let median_of = |term: fn(&CellTerms) -> f64| {
        let mut values: Vec<f64> = cells.iter().map(term).collect();
        100.0 * specula_core::statistics::median(&mut values)
    };
    println!(
        "term medians (%): noise {:.3}, calibration {:.3}, reconstruction {:.3}, extrapolation {:.3}, core {:.3}, deblurring {:.3}, combined {:.3}",
        median_of(|t| t.noise),
        median_of(|t| t.calibration),
        median_of(|t| t.reconstruction),
        median_of(|t| t.extrapolation),
        median_of(|t| t.core),
        median_of(|t| t.deblurring),
        median_of(CellTerms::combined),
    );
}

/// The scales `{PREFIX}_RECONSTRUCTION`, `{PREFIX}_DEBLUR` and `{PREFIX}_CORE` where they are set, else
/// `calibrated`'s; an error names a variable that is not a number.
fn scales_from_env(prefix: &str, calibrated: Scales) -> anyhow::Result<Scales> {
    let scale = |name: &str, default: f64| -> anyhow::Result<f64> {
        let variable = format!("{prefix}_{name}");
        match std::env::var(&variable) {
            Ok(v) => v
                .parse()
                .map_err(|_| anyhow::anyhow!("{variable}={v}: expected a number")),
            Err(_) => Ok(default),
        }
    };
    Ok(Scales {
        reconstruction: scale("RECONSTRUCTION", calibrated.reconstruction)?,
        deblur: scale("DEBLUR", calibrated.deblur)?,
        core: scale("CORE", calibrated.core)?,
    })
}

/// Coverage and the terms' medians by theta_h band at the scales `BANDS_RECONSTRUCTION` and
/// `BANDS_DEBLUR` (the calibrated ones unless given): where the uncertainty falls short or
/// runs long, and which term sets it.
fn bands(
    table: &MerlBrdf,
    terms: &Terms,
    provenance: &Provenance,
    truth: &MerlBrdf,
) -> anyhow::Result<()> {
    use specula_core::merl::Bin;
    let scales = scales_from_env("BANDS", Scales::default())?;
    println!("by theta_h band at {scales:?}:");
    let u = terms.combined(table, provenance, scales);
    let abs = u.absolute(table);
    for (lo, hi) in [
        (0.0, 2.0),
        (2.0, 8.0),
        (8.0, 20.0),
        (20.0, 40.0),
        (40.0, 90.0),
    ] {
        let (mut n, mut ok, mut above, mut ratio) = (0, 0, 0, Vec::new());
        let mut by_source: [Vec<f64>; 4] = Default::default();
        for i in 0..specula_core::merl::CELLS {
            let th = Bin::from_index(i).centre_deg()[0];
            if th < lo || th >= hi || provenance.cells[i].is_extrapolated() {
                continue;
            }
            if !specula_accuracy::within_elevation(Bin::from_index(i).centre(0.0), 75.0) {
                continue;
            }
            let (Some(v), Some(uu), Some(t)) = (table.cell(i), abs.cell(i), truth.cell(i)) else {
                continue;
            };
            if let Some(cell) = terms.cell_terms(i, table, provenance, scales) {
                for t in cell {
                    by_source[0].push(t.noise.hypot(t.calibration));
                    by_source[1].push(t.reconstruction);
                    by_source[2].push(t.extrapolation);
                    by_source[3].push(t.deblurring);
                }
            }
            for c in 0..3 {
                n += 1;
                let e = (v[c] - t[c]).abs();
                if e <= 2.0 * uu[c] {
                    ok += 1
                } else if v[c] > t[c] {
                    above += 1
                }
                ratio.push(e / t[c].max(1e-12));
            }
        }
        ratio.sort_by(f64::total_cmp);
        let q = |p: f64| {
            ratio
                .get(((ratio.len() as f64 - 1.0) * p) as usize)
                .copied()
                .unwrap_or(0.0)
        };
        let med = |v: &mut Vec<f64>| 100.0 * specula_core::statistics::median(v);
        println!(
            "  terms med % noise+cal {:.2} recon {:.2} extrap {:.2} deblur {:.2}",
            med(&mut by_source[0]),
            med(&mut by_source[1]),
            med(&mut by_source[2]),
            med(&mut by_source[3])
        );
        println!("theta_h {lo}-{hi}: {n} values, covered {:.3}, above {above}, rel err median {:.3} p90 {:.3}", ok as f64 / n.max(1) as f64, q(0.5), q(0.9));
    }
    Ok(())
}
