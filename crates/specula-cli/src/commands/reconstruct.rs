//! `specula reconstruct`: measured samples into a full MERL table with its provenance.

use anyhow::{bail, Context, Result};
use specula_core::Sample;
use specula_formats::samples_csv::SampleSet;
use specula_reconstruct::phi_d_halves::reconstruct_halves;
use specula_reconstruct::provenance::sidecar_path;
use specula_reconstruct::uncertainty::{self, UncertaintyInputs};
use specula_reconstruct::Method;
use specula_session::measured_uncertainty::session_main_noise;
use specula_session::workflow::session_main_samples;
use std::path::{Path, PathBuf};

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
    specula_core::request::check_merl_out(&args.out)?;
    let (input, samples, response, noise) = match (&args.samples, &args.session) {
        (Some(path), _) => (path, read_samples(path)?, None, None),
        (None, Some(path)) => {
            let (samples, response) = session_main_samples(path)?;
            let noise = session_main_noise(path)?;
            (
                path,
                samples,
                response.filter(|_| !args.no_deblur),
                Some(noise),
            )
        }
        (None, None) => bail!("give --samples-csv or --session"),
    };
    let name = args.out.file_stem().map_or_else(
        || "reconstruction".into(),
        |s| s.to_string_lossy().into_owned(),
    );
    let spinner = crate::progress::spinner("reconstructing");
    let result =
        reconstruct_halves(&samples, args.method, &name, response.as_ref()).and_then(|r| {
            let inputs = UncertaintyInputs {
                samples: &samples,
                noise_rel: noise.as_deref(),
                method: args.method,
            };
            let u = uncertainty::estimate(&inputs, &r)?;
            Ok((r, u))
        });
    spinner.finish_and_clear();
    let (r, u) = result.with_context(|| input.display().to_string())?;
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
    if let Some(resolution) = r.resolution_deg {
        let width = r.lobe.map(|l| l.shape.half_width_deg());
        outln!(
            "fitted through the instrument's response: resolution {resolution:.3} deg in theta_h; {}",
            match width {
                Some(w) if w < resolution => format!(
                    "the peak's half width {w:.3} deg is below it: a bound, not a measurement"
                ),
                Some(w) => format!("the peak's half width {w:.3} deg is resolved"),
                None => "no lobe".into(),
            }
        );
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

/// The samples of a CSV file.
fn read_samples(path: &Path) -> Result<Vec<Sample>> {
    Ok(SampleSet::read(path)?.samples().to_vec())
}
