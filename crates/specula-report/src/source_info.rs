//! What a BRDF source holds (`specula info`): its format, grid, measured cells, per-channel
//! statistics and peak. A MERL table's peak is given within the region people use (light
//! and camera within [`USED_ELEVATION_DEG`] of the normal) first, the grazing cells' peak
//! after it, named as such; then its largest directional albedo, which energy conservation
//! holds to 1.

use crate::error::{OrReport, ReportError};
use specula_accuracy::{within_elevation, USED_ELEVATION_DEG};
use specula_core::merl::{Bin, MerlBrdf, CELLS};
use specula_core::shown::plain;
use specula_core::statistics::{ChannelStats, Peak};
use specula_core::tabulate::tabulate;
use specula_formats::convert::Loaded;
use specula_formats::samples_csv::SampleSet;
use specula_formats::utia::{self, UtiaBrdf};
use specula_reconstruct::energy::{worst_albedo, HELD_ALBEDO};
use specula_reconstruct::provenance::{sidecar_path, Provenance};
use std::fmt::{self, Write};
use std::path::Path;

/// The description of the BRDF source `spec` (a file, a material .toml, a preset name or a
/// model:name fit), one fact a line, starting with `source: SPEC`.
pub fn describe_source(spec: &str) -> Result<String, ReportError> {
    let loaded = Loaded::resolve(spec).or_report()?;
    let provenance = match &loaded {
        Loaded::Merl(_) => Provenance::beside(Path::new(spec)).or_report()?,
        _ => None,
    };
    let mut out = String::new();
    write_description(&mut out, spec, loaded, provenance.as_ref()).or_report()?;
    Ok(out)
}

/// The lines of [`describe_source`].
fn write_description(
    out: &mut String,
    spec: &str,
    loaded: Loaded,
    provenance: Option<&Provenance>,
) -> fmt::Result {
    writeln!(out, "source: {spec}")?;
    match loaded {
        Loaded::Merl(table) => {
            writeln!(out, "format: MERL .binary")?;
            let origin = match provenance {
                Some(_) => format!(
                    "the cells a sample fell in, per {} (interpolated and extrapolated cells left out)",
                    sidecar_path(Path::new(spec)).display()
                ),
                None => "the cells the file holds a value for".to_string(),
            };
            describe_merl(out, &table, provenance, &origin)
        }
        Loaded::Utia(table) => describe_utia(out, &table),
        Loaded::Samples(set) => describe_samples(out, &set),
        Loaded::Rgl(bsdf) => {
            writeln!(out, "format: RGL .bsdf (a tabulated, interpolated BRDF)")?;
            evaluated(out, &*bsdf)
        }
        Loaded::Other(brdf) => {
            writeln!(out, "format: {} (a continuous BRDF)", brdf.name())?;
            evaluated(out, brdf.as_ref())
        }
    }
}

/// A continuous source, evaluated at the MERL bin centres.
fn evaluated(out: &mut String, brdf: &dyn specula_core::Brdf) -> fmt::Result {
    let phi_h_rad = specula_core::GridSpec::paper().phi_h_deg.to_radians();
    let table = tabulate(brdf, phi_h_rad);
    describe_merl(
        out,
        &table,
        None,
        "the MERL bin centres it is evaluated at (phi_h 45 deg)",
    )
}

/// The per-channel minimum, maximum and mean of the statistics, one line per channel.
fn write_channels(out: &mut String, stats: &ChannelStats) -> fmt::Result {
    let Some(mean) = stats.mean() else {
        return Ok(());
    };
    for (c, name) in ["red", "green", "blue"].iter().enumerate() {
        writeln!(
            out,
            "{name}: min {} max {} mean {} (1/sr)",
            plain(stats.min[c]),
            plain(stats.max[c]),
            plain(mean[c])
        )?;
    }
    Ok(())
}

fn describe_merl(
    out: &mut String,
    table: &MerlBrdf,
    provenance: Option<&Provenance>,
    among: &str,
) -> fmt::Result {
    writeln!(
        out,
        "grid: 90 theta_h x 90 theta_d x 180 phi_d cells (MERL)"
    )?;
    let chosen = |index: usize| provenance.is_none_or(|p| p.is_measured(index));
    let stats = ChannelStats::of(
        (0..CELLS)
            .filter(|&i| chosen(i))
            .filter_map(|i| table.cell(i).map(|v| (i, v))),
    );
    writeln!(out, "measured: {} of {CELLS} cells", table.measured_count())?;
    if let Some(p) = provenance {
        writeln!(out, "provenance: cells {}", p.summary())?;
    }
    write_channels(out, &stats)?;
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
        writeln!(
        out,
            "peak within {USED_ELEVATION_DEG} deg: {}, among {among} with light and camera within {USED_ELEVATION_DEG} deg of the normal",
            merl_peak(&peak)
        )?;
    }
    if let Some(peak) = peak_where(&|i| !used(i)) {
        writeln!(
        out,
            "peak of the grazing cells: {} (light or camera beyond {USED_ELEVATION_DEG} deg of the normal, the surface seen edge-on)",
            merl_peak(&peak)
        )?;
    }
    writeln!(out, "directional albedo: {}", albedo_in_words(table))
}

/// The table's largest directional albedo over its channels and the incidences the
/// reconstruction holds it to 1 at ([`worst_albedo`]), in words: above 1 (beyond the
/// quadrature's error, [`HELD_ALBEDO`]) the table reflects more light than arrives, which no
/// material does.
fn albedo_in_words(table: &MerlBrdf) -> String {
    let (incidence_deg, albedo) = worst_albedo(table);
    let verdict = if albedo > HELD_ALBEDO {
        ": above 1, the table reflects more light than arrives (no material does)"
    } else {
        ""
    };
    format!(
        "at most {:.3} (largest channel, at {} deg incidence){verdict}",
        albedo,
        plain(incidence_deg)
    )
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

fn describe_utia(out: &mut String, table: &UtiaBrdf) -> fmt::Result {
    writeln!(out, "format: UTIA .bin")?;
    writeln!(
        out,
        "grid: {} x {} light directions x {} x {} camera directions (elevation 0 to 75 deg by 15, azimuth by 7.5)",
        utia::THETA_COUNT, utia::PHI_COUNT, utia::THETA_COUNT, utia::PHI_COUNT
    )?;
    writeln!(
        out,
        "measured: {} of {} nodes",
        table.measured_count(),
        utia::NODES
    )?;
    let stats = ChannelStats::of((0..utia::NODES).filter_map(|i| table.node(i).map(|v| (i, v))));
    write_channels(out, &stats)?;
    if let Some(peak) = stats.peak {
        let [theta_i, phi_i, theta_v, phi_v] = utia::Node::from_index(peak.index).angles_deg();
        writeln!(
        out,
            "peak: {} 1/sr (mean of R, G, B) at light theta {theta_i} phi {phi_i} deg, camera theta {theta_v} phi {phi_v} deg, among the measured nodes",
            plain(peak.mean),
        )?;
    }
    Ok(())
}

fn describe_samples(out: &mut String, set: &SampleSet) -> fmt::Result {
    writeln!(out, "format: samples .csv")?;
    writeln!(
        out,
        "grid: scattered samples (theta_h, phi_h, theta_d, phi_d)"
    )?;
    let samples = set.samples();
    writeln!(out, "measured: {} samples", samples.len())?;
    let stats = ChannelStats::of(samples.iter().enumerate().map(|(i, s)| (i, s.value)));
    write_channels(out, &stats)?;
    if let Some(peak) = stats.peak {
        let (value, index) = (peak.mean, peak.index);
        let a = samples[index].hd;
        writeln!(
        out,
            "peak: {} 1/sr (mean of R, G, B) at theta_h {} deg, phi_h {} deg, theta_d {} deg, phi_d {} deg (row {}), among the samples",
            plain(value),
            plain(a.theta_h.to_degrees()),
            plain(a.phi_h.to_degrees()),
            plain(a.theta_d.to_degrees()),
            plain(a.phi_d.to_degrees()),
            index + 2
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::Rgb;

    /// A Lambertian table of albedo `rho` (f = rho / pi in every cell).
    fn lambertian(rho: f64) -> MerlBrdf {
        MerlBrdf::from_fn("lambertian", |_| {
            Some(Rgb::splat(rho / std::f64::consts::PI))
        })
    }

    /// The albedo the words give.
    fn stated(words: &str) -> f64 {
        let number = words
            .strip_prefix("at most ")
            .and_then(|w| w.split(' ').next());
        number.and_then(|n| n.parse().ok()).unwrap_or(f64::NAN)
    }

    #[test]
    fn a_lambertian_table_has_its_albedo_at_every_incidence() {
        let words = albedo_in_words(&lambertian(0.5));
        assert!((stated(&words) - 0.5).abs() < 0.002, "{words}");
        assert!(!words.contains("above 1"), "{words}");
    }

    #[test]
    fn a_table_that_reflects_more_than_arrives_is_named() {
        let words = albedo_in_words(&lambertian(2.0));
        assert!((stated(&words) - 2.0).abs() < 0.004, "{words}");
        assert!(
            words.contains("above 1, the table reflects more light than arrives"),
            "{words}"
        );
    }
}
