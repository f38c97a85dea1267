//! Calibrates the uncertainty's scales ([`specula_reconstruct::uncertainty::Scales`]) on
//! measured truths: for each `TABLE=TRUTH` (a table `specula measure --truth TRUTH --out
//! TABLE` wrote, with its session beside it), the cell coverage at k = 2 over a grid of the
//! reconstruction and deblurring scales.
//!
//!   cargo run --release -p specula-cli --example uncertainty_calibration -- T.binary=TRUTH ...

use specula_accuracy::coverage::cell_coverage;
use specula_core::merl::MerlBrdf;
use specula_core::tabulate::tabulate;
use specula_reconstruct::provenance::Provenance;
use specula_reconstruct::uncertainty::{Scales, Terms, UncertaintyInputs};
use specula_reconstruct::Method;
use specula_session::measured_uncertainty::session_main_noise;
use specula_session::workflow::session_main_samples;
use std::path::PathBuf;

const RECONSTRUCTION: [f64; 7] = [0.0, 0.03, 0.06, 0.12, 0.25, 0.5, 1.0];
const DEBLUR: [f64; 6] = [0.0, 0.1, 0.25, 0.5, 1.0, 2.0];

fn main() -> anyhow::Result<()> {
    for pair in std::env::args().skip(1) {
        let (table_path, truth_name) = pair
            .split_once('=')
            .ok_or_else(|| anyhow::anyhow!("{pair}: expected TABLE=TRUTH"))?;
        let table_path = PathBuf::from(table_path);
        let session = table_path.with_extension("session.sqlite");
        let table = MerlBrdf::read(&table_path)?;
        let provenance = Provenance::beside(&table_path)?
            .ok_or_else(|| anyhow::anyhow!("no provenance beside {}", table_path.display()))?;
        let (samples, response) = session_main_samples(&session)?;
        let noise = session_main_noise(&session)?;
        let inputs = UncertaintyInputs {
            samples: &samples,
            noise_rel: Some(&noise),
            method: Method::Lobe,
        };
        let terms = Terms::of(&inputs, &table, response.is_some())?;
        let phi_h_rad = specula_core::GridSpec::paper().phi_h_deg.to_radians();
        let truth = tabulate(specula_formats::load_brdf(truth_name)?.as_ref(), phi_h_rad);
        println!("{} {truth_name}", table_path.display());
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
