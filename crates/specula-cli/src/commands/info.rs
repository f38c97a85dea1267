//! `specula info`: what a BRDF source holds.

use crate::output::plain;
use anyhow::Result;
use specula_accuracy::{within_elevation, USED_ELEVATION_DEG};
use specula_core::merl::{Bin, MerlBrdf, CELLS};
use specula_core::statistics::{ChannelStats, Peak};
use specula_core::tabulate::tabulate;
use specula_formats::convert::Loaded;
use specula_formats::samples_csv::SampleSet;
use specula_formats::utia::{self, UtiaBrdf};
use specula_reconstruct::provenance::{sidecar_path, Provenance};
use std::path::Path;

/// Describe any BRDF source Specula loads: its format, its grid, how many cells (nodes,
/// samples) hold a measured value, the per-channel minimum, maximum and mean of f_r (1/sr)
/// over them, and the peak (the largest mean of R, G and B) among them, saying which cells
/// it was looked for in.
///
/// A MERL table written by `specula reconstruct` or `measure` has a provenance sidecar
/// (OUT.provenance.npy): its peak is the peak among the cells a sample fell in, not among
/// the interpolated or extrapolated ones. A continuous source (a preset, a material .toml,
/// a model:name fit, an RGL .bsdf) is evaluated at the MERL bin centres at phi_h = 45 deg.
///
/// Example: specula info chrome.binary; specula info sgd:chrome-steel
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The BRDF: a MERL .binary, UTIA .bin, RGL .bsdf or samples .csv file, a material
    /// .toml, a preset name or a model:name fit.
    pub brdf: String,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let loaded = Loaded::resolve(&args.brdf)?;
    outln!("source: {}", args.brdf);
    match loaded {
        Loaded::Merl(table) => {
            outln!("format: MERL .binary");
            let sidecar = sidecar_path(Path::new(&args.brdf));
            let provenance = Provenance::beside(Path::new(&args.brdf))?;
            let origin = match &provenance {
                Some(_) => format!(
                    "the cells a sample fell in, per {} (interpolated and extrapolated cells left out)",
                    sidecar.display()
                ),
                None => "the cells the file holds a value for".to_string(),
            };
            describe_merl(&table, provenance.as_ref(), &origin);
        }
        Loaded::Utia(table) => describe_utia(&table),
        Loaded::Samples(set) => describe_samples(&set),
        Loaded::Rgl(bsdf) => {
            outln!("format: RGL .bsdf (a tabulated, interpolated BRDF)");
            evaluated(&*bsdf);
        }
        Loaded::Other(brdf) => {
            outln!("format: {} (a continuous BRDF)", brdf.name());
            evaluated(brdf.as_ref());
        }
    }
    Ok(())
}

/// A continuous source, evaluated at the MERL bin centres.
fn evaluated(brdf: &dyn specula_core::Brdf) {
    let phi_h_rad = specula_core::GridSpec::paper().phi_h_deg.to_radians();
    let table = tabulate(brdf, phi_h_rad);
    describe_merl(
        &table,
        None,
        "the MERL bin centres it is evaluated at (phi_h 45 deg)",
    );
}

/// The per-channel minimum, maximum and mean of the statistics, one line per channel.
fn print_channels(stats: &ChannelStats) {
    let Some(mean) = stats.mean() else {
        return;
    };
    for (c, name) in ["red", "green", "blue"].iter().enumerate() {
        outln!(
            "{name}: min {} max {} mean {} (1/sr)",
            plain(stats.min[c]),
            plain(stats.max[c]),
            plain(mean[c])
        );
    }
}

fn describe_merl(table: &MerlBrdf, provenance: Option<&Provenance>, among: &str) {
    outln!("grid: 90 theta_h x 90 theta_d x 180 phi_d cells (MERL)");
    let chosen = |index: usize| provenance.is_none_or(|p| p.is_measured(index));
    let stats = ChannelStats::of(
        (0..CELLS)
            .filter(|&i| chosen(i))
            .filter_map(|i| table.cell(i).map(|v| (i, v))),
    );
    outln!("measured: {} of {CELLS} cells", table.measured_count());
    if let Some(p) = provenance {
        outln!("provenance: cells {}", p.summary());
    }
    print_channels(&stats);
    let used =
        |index: usize| within_elevation(Bin::from_index(index).centre(0.0), USED_ELEVATION_DEG);
    let peak_where = |keep: &dyn Fn(usize) -> bool| {
        ChannelStats::of(
            (0..CELLS)
                .filter(|&i| chosen(i) && keep(i))
                .filter_map(|i| table.cell(i).map(|v| (i, v))),
        )
        .peak
    };
    if let Some(peak) = peak_where(&used) {
        outln!(
            "peak within {USED_ELEVATION_DEG} deg: {}, among {among} with light and camera within {USED_ELEVATION_DEG} deg of the normal",
            merl_peak(&peak)
        );
    }
    if let Some(peak) = peak_where(&|i| !used(i)) {
        outln!(
            "peak of the grazing cells: {} (light or camera beyond {USED_ELEVATION_DEG} deg of the normal, the surface seen edge-on)",
            merl_peak(&peak)
        );
    }
}

/// A peak cell in words: its value and where it lies.
fn merl_peak(peak: &Peak) -> String {
    let bin = Bin::from_index(peak.index);
    let [theta_h_deg, theta_d_deg, phi_d_deg] = bin.centre_deg();
    format!(
        "{} 1/sr (mean of R, G, B) at theta_h {} deg, theta_d {theta_d_deg} deg, phi_d {phi_d_deg} deg (bin {}, {}, {})",
        plain(peak.mean),
        plain(theta_h_deg),
        bin.theta_h_i,
        bin.theta_d_i,
        bin.phi_d_i
    )
}

fn describe_utia(table: &UtiaBrdf) {
    outln!("format: UTIA .bin");
    outln!(
        "grid: {} x {} light directions x {} x {} camera directions (elevation 0 to 75 deg by 15, azimuth by 7.5)",
        utia::THETA_COUNT, utia::PHI_COUNT, utia::THETA_COUNT, utia::PHI_COUNT
    );
    outln!(
        "measured: {} of {} nodes",
        table.measured_count(),
        utia::NODES
    );
    let stats = ChannelStats::of((0..utia::NODES).filter_map(|i| table.node(i).map(|v| (i, v))));
    print_channels(&stats);
    if let Some(peak) = stats.peak {
        let [theta_i, phi_i, theta_v, phi_v] = utia::Node::from_index(peak.index).angles_deg();
        outln!(
            "peak: {} 1/sr (mean of R, G, B) at light theta {theta_i} phi {phi_i} deg, camera theta {theta_v} phi {phi_v} deg, among the measured nodes",
            plain(peak.mean),
        );
    }
}

fn describe_samples(set: &SampleSet) {
    outln!("format: samples .csv");
    outln!("grid: scattered samples (theta_h, phi_h, theta_d, phi_d)");
    let samples = set.samples();
    outln!("measured: {} samples", samples.len());
    let stats = ChannelStats::of(samples.iter().enumerate().map(|(i, s)| (i, s.value)));
    print_channels(&stats);
    if let Some(peak) = stats.peak {
        let (value, index) = (peak.mean, peak.index);
        let a = samples[index].hd;
        outln!(
            "peak: {} 1/sr (mean of R, G, B) at theta_h {} deg, phi_h {} deg, theta_d {} deg, phi_d {} deg (row {}), among the samples",
            plain(value),
            plain(a.theta_h.to_degrees()),
            plain(a.phi_h.to_degrees()),
            plain(a.theta_d.to_degrees()),
            plain(a.phi_d.to_degrees()),
            index + 2
        );
    }
}
