//! `specula reconstruct`: measured samples into a full MERL table with its provenance.

use anyhow::{bail, Context, Result};
use specula_accuracy::merl_prior::basis_for;
use specula_formats::samples_csv::SampleSet;
use specula_reconstruct::provenance::sidecar_path;
use specula_reconstruct::uncertainty::{self, UncertaintyInputs};
use specula_reconstruct::{run_reconstruct, Method, ReconstructRequest, RunReconstructError};
use specula_session::workflow::{session_main_samples, DeblurRecord};
use std::path::PathBuf;

/// Reconstruct a full MERL table from sparse samples (paper 5.3).
#[derive(clap::Args)]
pub(crate) struct Args {
    /// Samples CSV with the header theta_h,phi_h,theta_d,phi_d,r,g,b (degrees, 1/sr), one
    /// row per measured sample.
    #[arg(
        long = "samples-csv",
        required_unless_present = "session",
        conflicts_with = "session"
    )]
    pub samples: Option<PathBuf>,
    /// A measurement session journal (.sqlite, from `specula measure`) to reconstruct from:
    /// the measured samples of its main stage.
    #[arg(long)]
    pub session: Option<PathBuf>,
    /// Reconstruction method: lobe, prior, log or linear (the paper's baseline). lobe is the
    /// default, the best measured on real RGL measurements (`specula evaluate --help`).
    /// prior blends a data-driven prior (the MERL-100 fits) into lobe's model as far as the
    /// material's own samples trust it, so the cells the device cannot reach follow it
    /// (provenance code 3); it derives its basis first (about 20 s) and measured no better
    /// than lobe on real data. log and linear stay for comparison.
    #[arg(long, default_value = "lobe")]
    pub method: Method,
    /// With --session: do not fit the lobe through the instrument's response that the
    /// session's calibration holds (the BRDF as measured, blurred by the light's disk).
    #[arg(long, requires = "session")]
    pub no_deblur: bool,
    /// The MERL .binary file to write.
    #[arg(long, value_parser = crate::output::OUTPUT_FILE)]
    pub out: PathBuf,
}

/// Share of the table's cells extrapolated (not between samples) above which the result is
/// mostly made up rather than measured, and a warning says so. The paper's full plan on the
/// UTIA device extrapolates 52 % (761,018 cells: the grazing ones beyond its 75 deg reach,
/// `specula measure --truth silver-925`, then `specula info`); one sample, 99.99 %.
const MOSTLY_EXTRAPOLATED: f64 = 0.9;

pub(crate) fn run(args: Args) -> Result<()> {
    let request = ReconstructRequest {
        method: args.method,
        deblur: !args.no_deblur,
        out: Some(args.out.clone()),
    };
    request.validate()?;
    let (input, samples, response) = match (&args.samples, &args.session) {
        (Some(path), _) => (path, SampleSet::read(path)?.samples().to_vec(), None),
        (None, Some(path)) => {
            let (samples, response) = session_main_samples(path)?;
            (path, samples, response)
        }
        (None, None) => bail!("give --samples-csv or --session"),
    };
    let spinner = crate::progress::spinner("reconstructing");
    let prior = basis_for(args.method)?;
    let through = response.as_ref().map(|fit| &fit.response);
    // Written below with the uncertainty, all three together.
    let unwritten = ReconstructRequest {
        out: None,
        ..request.clone()
    };
    let result = run_reconstruct(&unwritten, &samples, through, prior.as_deref());
    let r = match result {
        Err(RunReconstructError::Reconstruct(e)) => Err(e).context(input.display().to_string())?,
        other => other?,
    };
    let inputs = UncertaintyInputs {
        samples: &samples,
        method: args.method,
        prior: prior.as_deref(),
    };
    let u = uncertainty::estimate(&inputs, &r).context(input.display().to_string())?;
    spinner.finish_and_clear();
    let sidecar = sidecar_path(&args.out);
    let u_sidecar = uncertainty::sidecar_path(&args.out);
    specula_core::atomic_file::write_together(&[
        (&args.out, &r.brdf.to_bytes()),
        (&sidecar, &r.provenance.to_npy()),
        (&u_sidecar, &u.absolute(&r.brdf).to_bytes()),
    ])?;
    let [nh, nd, np] = r.lattice_shape;
    outln!("samples: {} on a lattice of {nh} theta_h x {nd} theta_d x {np} phi_d ({} nodes measured, {} extrapolated)", samples.len(), r.measured_nodes, r.filled_nodes);
    if let Some(lobe) = r.lobe {
        outln!(
            "lobe: alpha {:.5}, gamma {:.3}, kd ({:.4}, {:.4}, {:.4})",
            lobe.shape.alpha,
            lobe.shape.gamma,
            lobe.diffuse.x,
            lobe.diffuse.y,
            lobe.diffuse.z
        );
    }
    if let (Some(fit), Some(_)) = (&response, r.resolution_deg) {
        let deblurred = DeblurRecord::new(fit, &r).describe();
        outln!("fitted through the instrument's response: {deblurred}");
    }
    for line in r.safeguard.iter().flat_map(|s| s.lines()) {
        outln!("{line}");
    }
    outln!("cells: {}", r.provenance.summary());
    let share = r.provenance.extrapolated_share();
    if share > MOSTLY_EXTRAPOLATED {
        eprintln!(
            "warning: {:.2} % of the table's cells are extrapolated from {} samples: most of it is made up, not measured",
            100.0 * share,
            samples.len()
        );
    }
    for line in u.lines() {
        outln!("{line}");
    }
    outln!(
        "wrote {}, {} and {} (method {})",
        args.out.display(),
        sidecar.display(),
        u_sidecar.display(),
        args.method
    );
    Ok(())
}
