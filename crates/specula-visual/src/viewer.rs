//! The interactive BRDF viewer: one self-contained HTML fragment (or page) that draws, in the
//! browser, the lobe as polar plots with an incident-angle slider, the characteristic slice
//! (theta_h x theta_d) as a heatmap with a phi_d slider, and a sphere lit by a point light
//! the user drags, for one or several BRDFs overlaid, with readouts under the pointer.
//!
//! The page needs no network and no install: the drawing code is the hand-written asset
//! `viewer/viewer.js` and its markup and styles `viewer/viewer.html`, both included here with
//! `include_str!`, and every BRDF travels in the page as a [`CompactTable`]. The same
//! fragment is what `specula view` writes as a page and what the HTML report embeds.
//!
//! A compact table is a reduced half-difference grid: MERL's 90 theta_h bins
//! (square-root spaced), 45 theta_d bins of 2 deg and 45 phi_d bins of 4 deg over
//! `[0, 180)`. Each reduced cell holds f_r of one MERL bin inside it (theta_d bin `2 j + 1`,
//! phi_d bin `4 k + 2`, so that the characteristic slice phi_d = 90 deg is a MERL bin of its
//! own), evaluated at that bin's centre: a MERL table gives its own cells, uninterpolated.
//! Values are stored log-quantised as little-endian u16 in base64 ([`quantise`]).

use crate::report::escape;
use base64::Engine;
use rayon::prelude::*;
use serde::Serialize;
use specula_core::merl::{Bin, PHI_D_BINS, THETA_D_BINS, THETA_H_BINS};
use specula_core::{Brdf, Rgb};
use std::fmt::Write;

/// theta_h bins of a compact table (MERL's own, square-root spaced).
pub const VIEW_THETA_H_BINS: usize = THETA_H_BINS;
/// theta_d bins of a compact table, 2 deg each.
pub const VIEW_THETA_D_BINS: usize = 45;
/// phi_d bins of a compact table, 4 deg each over `[0, 180)`.
pub const VIEW_PHI_D_BINS: usize = 45;
/// Cells of a compact table.
pub const VIEW_CELLS: usize = VIEW_THETA_H_BINS * VIEW_THETA_D_BINS * VIEW_PHI_D_BINS;

const THETA_D_STRIDE: usize = THETA_D_BINS / VIEW_THETA_D_BINS;
const PHI_D_STRIDE: usize = PHI_D_BINS / VIEW_PHI_D_BINS;

/// The quantised code of a cell without a value (not measured).
pub const CODE_NONE: u16 = 0;
/// The quantised code of f_r = 0.
pub const CODE_ZERO: u16 = 1;
/// The first code of a positive value; codes run up to `u16::MAX`.
const CODE_FIRST: u16 = 2;

/// The MERL bin whose value the reduced cell `index` holds.
pub fn merl_bin_of(index: usize) -> Bin {
    let phi_d_i = index % VIEW_PHI_D_BINS;
    let theta_d_i = (index / VIEW_PHI_D_BINS) % VIEW_THETA_D_BINS;
    let theta_h_i = index / (VIEW_PHI_D_BINS * VIEW_THETA_D_BINS);
    Bin {
        theta_h_i,
        theta_d_i: THETA_D_STRIDE * theta_d_i + THETA_D_STRIDE / 2,
        phi_d_i: PHI_D_STRIDE * phi_d_i + PHI_D_STRIDE / 2,
    }
}

/// Values of one quantity per cell and channel, log-quantised: `ln f` between `ln_min` and
/// `ln_max` spread over the codes `2..=65535`; code [`CODE_NONE`] for no value and
/// [`CODE_ZERO`] for zero. The relative step is `(ln_max - ln_min) / 65533`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Quantised {
    /// ln of the smallest positive value (of code 2).
    pub ln_min: f64,
    /// ln of the largest value (of code 65535).
    pub ln_max: f64,
    /// The codes, cell after cell, R G B per cell, as little-endian u16 in base64.
    pub codes: String,
}

/// `values` (R, G, B per cell, `None` where there is none) as [`Quantised`] codes.
pub fn quantise(values: &[Option<Rgb>]) -> Quantised {
    let positive = values
        .iter()
        .flatten()
        .flat_map(|v| v.to_array())
        .filter(|x| x.is_finite() && *x > 0.0);
    let (min, max) = positive.fold((f64::INFINITY, 0.0f64), |(lo, hi), x| {
        (lo.min(x), hi.max(x))
    });
    let (ln_min, ln_max) = if max > 0.0 {
        (min.ln(), max.ln())
    } else {
        (0.0, 0.0)
    };
    let span = (ln_max - ln_min).max(f64::MIN_POSITIVE);
    let steps = f64::from(u16::MAX - CODE_FIRST);
    let code = |x: f64| -> u16 {
        if !x.is_finite() || x < 0.0 {
            CODE_NONE
        } else if x == 0.0 {
            CODE_ZERO
        } else {
            let step = ((x.ln() - ln_min) / span * steps).round().clamp(0.0, steps);
            CODE_FIRST + step as u16
        }
    };
    let mut bytes = Vec::with_capacity(values.len() * 6);
    for value in values {
        let codes = match value {
            Some(v) => v.to_array().map(code),
            None => [CODE_NONE; 3],
        };
        for c in codes {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
    }
    Quantised {
        ln_min,
        ln_max,
        codes: base64::engine::general_purpose::STANDARD.encode(bytes),
    }
}

/// The value of a code of `q`, the inverse of [`quantise`] (up to its step).
pub fn dequantise(q: &Quantised, code: u16) -> Option<f64> {
    match code {
        CODE_NONE => None,
        CODE_ZERO => Some(0.0),
        c => {
            let t = f64::from(c - CODE_FIRST) / f64::from(u16::MAX - CODE_FIRST);
            Some((q.ln_min + t * (q.ln_max - q.ln_min)).exp())
        }
    }
}

/// f_r of `brdf` at every reduced cell, in cell order.
pub fn reduced_values(brdf: &dyn Brdf) -> Vec<Option<Rgb>> {
    (0..VIEW_CELLS)
        .into_par_iter()
        .map(|index| brdf.eval_half_diff(merl_bin_of(index).centre(0.0)))
        .collect()
}

/// One BRDF as the viewer receives it.
#[derive(Debug, Clone, Serialize)]
pub struct CompactTable {
    /// The name shown in the legend and the readouts.
    pub name: String,
    /// f_r, 1/sr, per cell and channel.
    pub values: Quantised,
    /// Where each cell's value comes from, one byte per cell in base64, with the codes of
    /// the provenance sidecar (0 measured, 1 interpolated, 2 extrapolated, 3 extrapolated
    /// with the prior); `None` when not known.
    pub origins: Option<String>,
    /// The standard uncertainty of f_r, 1/sr, per cell and channel, when known.
    pub uncertainty: Option<Quantised>,
}

impl CompactTable {
    /// The compact table of `brdf`, named `name`, without provenance or uncertainty.
    pub fn new(name: impl Into<String>, brdf: &dyn Brdf) -> Self {
        CompactTable {
            name: name.into(),
            values: quantise(&reduced_values(brdf)),
            origins: None,
            uncertainty: None,
        }
    }

    /// With the origin of each cell: `origin_of_merl_cell` gives the provenance code of a
    /// MERL cell index.
    pub fn with_origins(mut self, origin_of_merl_cell: impl Fn(usize) -> u8) -> Self {
        let codes: Vec<u8> = (0..VIEW_CELLS)
            .map(|index| origin_of_merl_cell(merl_bin_of(index).index()))
            .collect();
        self.origins = Some(base64::engine::general_purpose::STANDARD.encode(codes));
        self
    }

    /// With the standard uncertainty of f_r given as a BRDF (1/sr per channel).
    pub fn with_uncertainty(mut self, uncertainty: &dyn Brdf) -> Self {
        self.uncertainty = Some(quantise(&reduced_values(uncertainty)));
        self
    }
}

/// The data the page's script reads: the grid's shape and the tables.
#[derive(Serialize)]
struct ViewerData<'a> {
    theta_h_bins: usize,
    theta_d_bins: usize,
    phi_d_bins: usize,
    tables: &'a [CompactTable],
}

/// The viewer's markup and styles (the asset `viewer/viewer.html`).
const MARKUP: &str = include_str!("viewer/viewer.html");
/// The viewer's script (the asset `viewer/viewer.js`).
const SCRIPT: &str = include_str!("viewer/viewer.js");

/// The viewer of `tables` as an HTML fragment to place in a page's body: markup, styles,
/// the tables as JSON and the script. One viewer per page.
pub fn viewer_fragment(tables: &[CompactTable]) -> String {
    let data = ViewerData {
        theta_h_bins: VIEW_THETA_H_BINS,
        theta_d_bins: VIEW_THETA_D_BINS,
        phi_d_bins: VIEW_PHI_D_BINS,
        tables,
    };
    // Serialising plain numbers and strings cannot fail; `</` is escaped so that a name
    // cannot close the script element.
    let json = serde_json::to_string(&data)
        .unwrap_or_default()
        .replace("</", "<\\/");
    let mut html = String::with_capacity(json.len() + MARKUP.len() + SCRIPT.len() + 200);
    html.push_str(MARKUP);
    let _ = write!(
        html,
        "<script type=\"application/json\" id=\"sv-data\">{json}</script>\n<script>\n{SCRIPT}</script>\n"
    );
    html
}

/// A whole page holding only the viewer of `tables`, titled `title`.
pub fn viewer_page(title: &str, generator: &str, tables: &[CompactTable]) -> String {
    let title = escape(title);
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <meta name=\"generator\" content=\"{}\">\n<title>{title}</title>\n\
         <style>body{{font-family:system-ui,sans-serif;margin:0;background:#f5f5f7;color:#1d1d1f}}\
         main{{max-width:1100px;margin:0 auto;padding:16px 24px}}h1{{font-size:1.5em}}</style>\n\
         </head>\n<body>\n<main>\n<h1>{title}</h1>\n{}</main>\n</body>\n</html>\n",
        escape(generator),
        viewer_fragment(tables)
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::materials;
    use specula_core::merl::MerlBrdf;

    fn codes(q: &Quantised) -> Vec<u16> {
        let bytes = base64::engine::general_purpose::STANDARD
            .decode(&q.codes)
            .unwrap();
        bytes
            .chunks_exact(2)
            .map(|b| u16::from_le_bytes([b[0], b[1]]))
            .collect()
    }

    #[test]
    fn quantised_values_come_back_within_their_step() {
        let values = [
            Some(Rgb::new(1e-4, 0.0, 3.0)),
            None,
            Some(Rgb::new(2.5e4, 0.5, f64::NAN)),
        ];
        let q = quantise(&values);
        let c = codes(&q);
        assert_eq!(c.len(), 9);
        assert_eq!(&c[3..6], &[CODE_NONE; 3]);
        assert_eq!(c[1], CODE_ZERO);
        assert_eq!(c[8], CODE_NONE);
        let step = (q.ln_max - q.ln_min) / 65533.0;
        for (code, expected) in [(c[0], 1e-4), (c[2], 3.0), (c[6], 2.5e4), (c[7], 0.5)] {
            let back = dequantise(&q, code).unwrap();
            assert!(
                (back / expected).ln().abs() <= step / 2.0 + 1e-12,
                "{back} for {expected}"
            );
        }
    }

    #[test]
    fn a_merl_table_keeps_its_own_cells() {
        let table = MerlBrdf::from_fn("t", |i| Some(Rgb::splat(i as f64 + 1.0)));
        let values = reduced_values(&table);
        for index in [0, 1, 45, 2024, VIEW_CELLS - 1] {
            let merl = merl_bin_of(index).index();
            // The file's channel scales round-trip to within a few ulp.
            let value = values[index].unwrap();
            let expected = merl as f64 + 1.0;
            assert!(
                (value - Rgb::splat(expected)).abs().max_element() < 1e-9 * expected,
                "{index}: {value} for {expected}"
            );
        }
        // The characteristic slice phi_d = 90 deg is a bin of its own.
        assert_eq!(merl_bin_of(22).phi_d_i, 90);
    }

    #[test]
    fn the_page_is_self_contained_and_carries_every_table() {
        let steel = materials::preset("steel").unwrap();
        let table = CompactTable::new("a</script>", &steel).with_origins(|i| (i % 4) as u8);
        let page = viewer_page("steel & co", "test", &[table.clone(), table]);
        // No address to fetch (base64 data may spell "http" by chance, never "http:").
        let lower = page.to_ascii_lowercase();
        assert!(!lower.contains("http:") && !lower.contains("https:"));
        assert!(!page.contains("a</script>") && page.contains("a<\\/script>"));
        assert_eq!(page.matches("\"origins\":\"").count(), 2);
        assert!(page.contains("<title>steel &amp; co</title>"));
    }
}
