//! `specula probe`: the dense theta_h column of paper 5.2 from any BRDF.

use crate::output::plain;
use crate::range;
use anyhow::Result;
use specula_core::ProbeSpec;
use specula_sampling::probe::Probe;
use std::path::PathBuf;

/// Take the probe of paper 5.2: one dense theta_h column of a BRDF.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The BRDF: a preset name, a material .toml, a MERL .binary or a model:name fit
    /// (e.g. sgd:chrome-steel).
    pub brdf: String,
    /// theta_d of the column, degrees. Range: degrees from 0 to 89.5.
    #[arg(long, default_value_t = ProbeSpec::paper().theta_d_deg, value_parser = range::THETA_D_DEG)]
    pub theta_d: f64,
    /// phi_d of the column, degrees (90: the characteristic slice of paper 5.1). Range: degrees
    /// from 0 to 180.
    #[arg(long, default_value_t = ProbeSpec::paper().phi_d_deg, value_parser = range::PHI_D_DEG)]
    pub phi_d: f64,
    /// phi_h, degrees: the sample's orientation (chosen to avoid scratches, paper 4.3). Range:
    /// degrees from -360 to 360.
    #[arg(long, default_value_t = ProbeSpec::paper().phi_h_deg, allow_negative_numbers = true, value_parser = range::AZIMUTH_DEG)]
    pub phi_h: f64,
    /// Number of theta_h samples of the probe (the paper uses up to 90). Range: a whole number from
    /// 2 to 10000.
    #[arg(long, default_value_t = ProbeSpec::paper().samples, value_parser = range::PROBE_SAMPLES)]
    pub probe_samples: usize,
    /// Where to write the probe (CSV).
    #[arg(long)]
    pub out: PathBuf,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let brdf = specula_formats::load_brdf(&args.brdf)?;
    let settings = ProbeSpec {
        theta_d_deg: args.theta_d,
        phi_d_deg: args.phi_d,
        phi_h_deg: args.phi_h,
        samples: args.probe_samples,
    };
    let probe = Probe::take(brdf.as_ref(), &settings)?;
    probe.write_csv(&args.out)?;
    let (peak_at, peak) = probe.column().peak();
    outln!(
        "wrote {} samples of {} to {} (theta_d {} deg, phi_d {} deg, phi_h {} deg); peak {} 1/sr (mean of RGB) at theta_h {} deg",
        probe.len(),
        brdf.name(),
        args.out.display(),
        args.theta_d,
        args.phi_d,
        args.phi_h,
        plain(peak),
        plain(peak_at)
    );
    Ok(())
}
