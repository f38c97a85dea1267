//! `specula placement`: the paper's theta_h placement against ours and the oracle.

use super::analyze::DatabaseArgs;
use anyhow::Result;
use specula_core::GridSpec;
use specula_sampling::column::Interpolation;
use specula_sampling::placement_study::{study_slice, summarize, write_csv, MaterialPlacement};
use specula_sampling::slice::DENSE_NODES;
use std::path::PathBuf;

/// Compare ways of placing n theta_h samples over a database: how well each rebuilds the
/// characteristic slice (phi_d = 90 deg, all theta_d) from one set of theta_h positions.
///
/// Every method but the oracle sees only the probe (the column at theta_d = 40 deg, paper 5.2):
/// square root (MERL's mapping, eq. 1), the paper's exponential with k-hat fitted to the
/// probe (eq. 3), the optimal placement of the probe's own samples by dynamic programming, and
/// ours (the same on a dense log-domain model of the probe, which may place samples between
/// the probe's); each is used for every theta_d. The oracle places each column's samples
/// optimally knowing the truth: the lower bound. The error is the mean absolute error over
/// the slice's columns theta_d = 0, 3, ..., 87 deg (1/sr, mean of RGB).
///
/// The truth is the slice of each BRDF at 268 square-root-spaced theta_h nodes (the probe's
/// 90 and two between each pair); a MERL file gives its 90 bins. Prints one table per
/// interpolation domain (linear, as the paper; and log, interpolating ln f): mean error over
/// the materials, its ratio to the oracle's, and the geometric mean, median and worst of the
/// per-material ratios to the oracle.
///
/// Example: specula placement --builtin
#[derive(clap::Args)]
pub(crate) struct Args {
    #[command(flatten)]
    pub database: DatabaseArgs,
    /// Number of theta_h samples of the sparse measurement. Range: a whole number from 2 to
    /// 360.
    #[arg(long, default_value_t = GridSpec::paper().theta_h_samples, value_parser = crate::range::THETA_H_SAMPLES)]
    pub theta_h_samples: usize,
    /// Also print the table for interpolation in the log domain (ln f), which doubles the time.
    #[arg(long)]
    pub log: bool,
    /// Also write every material's errors as CSV
    /// (material,k_hat,domain,square_root,paper,probe_samples,ours,oracle).
    #[arg(long, value_parser = crate::output::OUTPUT_FILE)]
    pub out: Option<PathBuf>,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let domains: &[Interpolation] = if args.log {
        &Interpolation::ALL
    } else {
        &[Interpolation::Linear]
    };
    let rows = args.database.map("placing", DENSE_NODES, |slice| {
        domains
            .iter()
            .map(|&domain| study_slice(slice, args.theta_h_samples, domain))
            .collect::<Result<Vec<_>, _>>()
            .map_err(anyhow::Error::from)
    })?;
    let materials = rows.len();
    for (d, domain) in domains.iter().enumerate() {
        let per_domain: Vec<MaterialPlacement> = rows.iter().map(|r| r[d].clone()).collect();
        let table = summarize(&per_domain);
        outln!(
            "\n{} theta_h samples, {} interpolation, {materials} materials ({} rebuilt exactly by the oracle, left out of the ratios):\n",
            args.theta_h_samples,
            domain.name(),
            table[0].exact_materials
        );
        outln!("| placement | mean error (1/sr) | ratio of means to oracle | geometric mean ratio | median ratio | worst ratio |");
        outln!("|---|---|---|---|---|---|");
        for row in table {
            outln!(
                "| {} | {:.4e} | {:.2} | {:.2} | {:.2} | {:.2} |",
                row.method.label(),
                row.mean_error,
                row.ratio_of_means,
                row.geometric_mean_ratio,
                row.median_ratio,
                row.worst_ratio
            );
        }
    }
    if let Some(path) = &args.out {
        write_csv(path, domains, &rows)?;
        outln!("\nwrote {}", path.display());
    }
    Ok(())
}
