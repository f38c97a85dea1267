//! All appearance figures of one BRDF, their differences to a reference, the warnings that
//! go with them, and their text and CSV forms.

use crate::aperture::{ExtrapolatedCells, Flux};
use crate::colour::{self, LabD65, ASPECULAR_DEG};
use crate::gloss::GEOMETRIES;
use crate::haze::{self, DOI_OFFSET_DEG, HAZE_20_OFFSET_DEG, HAZE_OFFSET_DEG};
use specula_core::range::RangeError;
use specula_core::request::RESOLUTION_DEG;
use specula_core::Brdf;
use std::fmt;

/// What the figures of a measured table may lean on.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// The cells of a measured table that were extrapolated, not measured.
    pub extrapolated: Option<ExtrapolatedCells>,
    /// Angular resolution of the instrument that measured the BRDF, degrees (e.g. the
    /// angular radius of its light source): a figure that reads the BRDF at a finer angle
    /// than this is a bound, not a measurement.
    pub resolution_deg: Option<f64>,
}

impl Options {
    /// Checks the resolution against its range ([`RESOLUTION_DEG`], as the CLI's
    /// `--resolution`; the error names the Python argument `resolution_deg`).
    pub fn validate(&self) -> Result<(), RangeError> {
        match self.resolution_deg {
            Some(resolution_deg) => RESOLUTION_DEG
                .check("resolution_deg", resolution_deg)
                .map(|_| ()),
            None => Ok(()),
        }
    }
}

/// Which figure a warning is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Figure {
    /// Specular gloss at 20 deg (ISO 2813 / ASTM D523).
    Gloss20,
    /// Specular gloss at 60 deg.
    Gloss60,
    /// Specular gloss at 85 deg.
    Gloss85,
    /// Reflection haze (ASTM E430).
    Haze,
    /// Distinctness of image (ASTM E430).
    Doi,
    /// Haze at 20 deg (ASTM E430 Test Method B / ISO 13803).
    Haze20,
}

impl Figure {
    /// The figure's CSV column name.
    pub fn column(self) -> &'static str {
        match self {
            Figure::Gloss20 => "gloss_20",
            Figure::Gloss60 => "gloss_60",
            Figure::Gloss85 => "gloss_85",
            Figure::Haze => "haze",
            Figure::Doi => "doi",
            Figure::Haze20 => "haze_20",
        }
    }

    /// The finest angle the figure resolves, degrees: the receptor's in-plane half width
    /// for gloss, the off-specular offset for haze and DOI.
    pub fn angular_scale_deg(self) -> f64 {
        match self {
            Figure::Gloss20 => 0.5 * GEOMETRIES[0].receptor.in_plane_deg,
            Figure::Gloss60 => 0.5 * GEOMETRIES[1].receptor.in_plane_deg,
            Figure::Gloss85 => 0.5 * GEOMETRIES[2].receptor.in_plane_deg,
            Figure::Haze => HAZE_OFFSET_DEG,
            Figure::Doi => DOI_OFFSET_DEG,
            Figure::Haze20 => HAZE_20_OFFSET_DEG,
        }
    }
}

/// Why a figure is less than a measurement.
#[derive(Debug, Clone, PartialEq)]
pub enum Warning {
    /// Part of the integration fell on cells the table has not measured (left out).
    Unmeasured {
        /// The figure.
        figure: Figure,
        /// The fraction of the aperture's weight left out.
        fraction: f64,
    },
    /// Part of the flux comes from extrapolated cells.
    Extrapolated {
        /// The figure.
        figure: Figure,
        /// The fraction of the collected flux from extrapolated cells.
        fraction: f64,
    },
    /// The figure reads the BRDF at a finer angle than the instrument resolves.
    Resolution {
        /// The figure.
        figure: Figure,
        /// The angle the figure reads at, degrees.
        scale_deg: f64,
        /// The instrument's resolution, degrees.
        resolution_deg: f64,
    },
    /// A colour reading's pair of directions is not measured.
    ColourUnmeasured {
        /// The reading's aspecular angle, degrees.
        aspecular_deg: f64,
    },
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::Unmeasured { figure, fraction } => write!(
                f,
                "{}: {:.1} % of its apertures fall on cells the table has not measured (left out)",
                figure.column(),
                100.0 * fraction
            ),
            Warning::Extrapolated { figure, fraction } => write!(
                f,
                "{}: {:.1} % of its flux comes from extrapolated cells, not measured ones",
                figure.column(),
                100.0 * fraction
            ),
            Warning::Resolution {
                figure,
                scale_deg,
                resolution_deg,
            } => write!(
                f,
                "{}: reads the BRDF {scale_deg} deg from the specular, finer than the instrument's {resolution_deg:.2} deg resolution: a bound, not a measurement",
                figure.column()
            ),
            Warning::ColourUnmeasured { aspecular_deg } => write!(
                f,
                "colour at {aspecular_deg} deg aspecular: the table has not measured this pair of directions"
            ),
        }
    }
}

/// Fractions below this are not worth a warning.
const WARN_FRACTION: f64 = 0.01;

/// The appearance figures of one BRDF.
#[derive(Debug, Clone, PartialEq)]
pub struct Appearance {
    /// Gloss units at 20, 60 and 85 deg (ISO 2813 / ASTM D523).
    pub gloss: [f64; 3],
    /// Narrow-angle haze, ASTM E430 (30 deg, 2 deg off): `100 R_2 / R_s`.
    pub haze: f64,
    /// Distinctness of image, ASTM E430 (30 deg, 0.3 deg off): `100 (R_s - R_0.3) / R_s`.
    pub doi: f64,
    /// Haze at 20 deg, ASTM E430 Test Method B / ISO 13803, relative to the gloss standard.
    pub haze_20: f64,
    /// Haze index of ASTM D4039 (section 3.2.3): `G60 - G20`, the 60 deg gloss less the
    /// 20 deg gloss, for high-gloss nonmetallic specimens (60 deg gloss above 70, section 4.2).
    pub haze_d4039: f64,
    /// CIELAB under D65 at each of [`ASPECULAR_DEG`] (`None`: not measured).
    pub colour: Vec<Option<LabD65>>,
    /// Flop index from L* at 15, 45 and 110 deg (`None` when one is missing).
    pub flop_index: Option<f64>,
    /// Where a figure rests on cells the table did not measure or extrapolated.
    pub warnings: Vec<Warning>,
}

/// Computes every figure of `brdf`.
pub fn appearance(brdf: &dyn Brdf, options: &Options) -> Appearance {
    let cells = options.extrapolated.as_ref();
    let ((gloss_readings, e430), (haze_20, colour)) = rayon::join(
        || {
            rayon::join(
                || GEOMETRIES.map(|g| g.measure(brdf, cells)),
                || haze::e430(brdf, cells),
            )
        },
        || rayon::join(|| haze::haze_20(brdf, cells), || colour::multi_angle(brdf)),
    );
    let mut warnings = Vec::new();
    let mut check = |figure: Figure, flux: &Flux| {
        if flux.unmeasured_fraction > WARN_FRACTION {
            warnings.push(Warning::Unmeasured {
                figure,
                fraction: flux.unmeasured_fraction,
            });
        }
        if flux.extrapolated_fraction > WARN_FRACTION {
            warnings.push(Warning::Extrapolated {
                figure,
                fraction: flux.extrapolated_fraction,
            });
        }
        if let Some(resolution_deg) = options.resolution_deg {
            if figure.angular_scale_deg() < resolution_deg {
                warnings.push(Warning::Resolution {
                    figure,
                    scale_deg: figure.angular_scale_deg(),
                    resolution_deg,
                });
            }
        }
    };
    for (figure, (flux, _)) in [Figure::Gloss20, Figure::Gloss60, Figure::Gloss85]
        .into_iter()
        .zip(&gloss_readings)
    {
        check(figure, flux);
    }
    check(Figure::Haze, &worse_of(&e430.specular, &e430.haze_reading));
    check(Figure::Doi, &worse_of(&e430.specular, &e430.doi_reading));
    check(Figure::Haze20, &haze_20.0);
    for (gamma, lab) in ASPECULAR_DEG.iter().zip(&colour) {
        if lab.is_none() {
            warnings.push(Warning::ColourUnmeasured {
                aspecular_deg: *gamma,
            });
        }
    }
    let lightness = |i: usize| colour[i].map(|c| c[0]);
    let flop_index = match (lightness(0), lightness(2), lightness(4)) {
        (Some(l15), Some(l45), Some(l110)) => Some(colour::flop_index(l15, l45, l110)),
        _ => None,
    };
    Appearance {
        gloss: gloss_readings.map(|(_, gu)| gu),
        haze: e430.haze,
        doi: e430.doi,
        haze_20: haze_20.1,
        haze_d4039: d4039_haze_index(&gloss_readings.map(|(_, gu)| gu)),
        colour,
        flop_index,
        warnings,
    }
}

/// ASTM D4039's haze index from the gloss at 20, 60 and 85 deg: `G60 - G20`.
pub fn d4039_haze_index(gloss: &[f64; 3]) -> f64 {
    gloss[1] - gloss[0]
}

/// The larger of two readings' unmeasured and extrapolated fractions (a ratio figure
/// depends on both).
fn worse_of(a: &Flux, b: &Flux) -> Flux {
    Flux {
        value: a.value,
        unmeasured_fraction: a.unmeasured_fraction.max(b.unmeasured_fraction),
        extrapolated_fraction: a.extrapolated_fraction.max(b.extrapolated_fraction),
    }
}

/// Differences of a material's figures to a reference's (material minus reference).
#[derive(Debug, Clone, PartialEq)]
pub struct Differences {
    /// Specular gloss at 20, 60 and 85 deg, gloss units (ISO 2813 / ASTM D523).
    pub gloss: [f64; 3],
    /// Reflection haze, haze units (ASTM E430).
    pub haze: f64,
    /// Distinctness of image, DOI units (ASTM E430).
    pub doi: f64,
    /// Haze at 20 deg, ASTM E430 Test Method B / ISO 13803.
    pub haze_20: f64,
    /// Haze index, ASTM D4039.
    pub haze_d4039: f64,
    /// Flop index (`None` when either lacks one).
    pub flop_index: Option<f64>,
    /// CIEDE2000 at each of [`ASPECULAR_DEG`].
    pub delta_e00: Vec<Option<f64>>,
}

impl Appearance {
    /// The differences to `reference`.
    pub fn against(&self, reference: &Appearance) -> Differences {
        Differences {
            gloss: [0, 1, 2].map(|i| self.gloss[i] - reference.gloss[i]),
            haze: self.haze - reference.haze,
            doi: self.doi - reference.doi,
            haze_20: self.haze_20 - reference.haze_20,
            haze_d4039: self.haze_d4039 - reference.haze_d4039,
            flop_index: self
                .flop_index
                .zip(reference.flop_index)
                .map(|(a, b)| a - b),
            delta_e00: self
                .colour
                .iter()
                .zip(&reference.colour)
                .map(|(a, b)| a.zip(*b).map(|(a, b)| colour::ciede2000(a, b)))
                .collect(),
        }
    }
}

/// The names of the differences to a reference, in column order: `gloss_20`, `gloss_60`,
/// `gloss_85`, `haze`, `doi`, `haze_20`, `haze_d4039`, `flop_index` (material minus
/// reference), then
/// `de00_15` ... `de00_110` (CIEDE2000 per aspecular angle). The CSV's difference columns
/// and a tolerance file's keys ([`crate::tolerance`]) are these names.
pub fn difference_names() -> Vec<String> {
    let mut names: Vec<String> = DIFFERENCE_FIGURES.map(String::from).to_vec();
    names.extend(ASPECULAR_DEG.iter().map(|gamma| format!("de00_{gamma}")));
    names
}

/// The figures whose differences are plain subtractions, in column order.
const DIFFERENCE_FIGURES: [&str; 8] = [
    "gloss_20",
    "gloss_60",
    "gloss_85",
    "haze",
    "doi",
    "haze_20",
    "haze_d4039",
    "flop_index",
];

impl Differences {
    /// The differences in [`difference_names`] order (`None` where unknown).
    pub fn values(&self) -> Vec<Option<f64>> {
        let mut values: Vec<Option<f64>> = self.gloss.map(Some).to_vec();
        values.extend([self.haze, self.doi, self.haze_20, self.haze_d4039].map(Some));
        values.push(self.flop_index);
        values.extend(self.delta_e00.iter().copied());
        values
    }
}

/// The CSV header: `source,gloss_20,gloss_60,gloss_85,haze,doi`, then `haze_20`,
/// `haze_d4039`, the
/// CIELAB columns per aspecular angle (`L_15,a_15,b_15,...`), `flop_index`, and with a
/// reference the differences (`d_gloss_20,...,d_flop_index`, `de00_15,...`).
pub fn csv_header(with_reference: bool) -> Vec<String> {
    let mut header: Vec<String> = [
        "source",
        "gloss_20",
        "gloss_60",
        "gloss_85",
        "haze",
        "doi",
        "haze_20",
        "haze_d4039",
    ]
    .map(String::from)
    .to_vec();
    for gamma in ASPECULAR_DEG {
        for channel in ["L", "a", "b"] {
            header.push(format!("{channel}_{gamma}"));
        }
    }
    header.push("flop_index".into());
    if with_reference {
        header.extend(difference_names().into_iter().map(|name| {
            if DIFFERENCE_FIGURES.contains(&name.as_str()) {
                format!("d_{name}")
            } else {
                name
            }
        }));
    }
    header
}

/// A number as the CSV writes it (empty when unknown).
fn cell(value: Option<f64>) -> String {
    value.map_or_else(String::new, |v| format!("{v:.4}"))
}

/// The figures in [`csv_header`]'s order after `source` (`None` where unknown): the
/// columns of the CSV and of the Python package's `specula.appearance`.
pub fn column_values(figures: &Appearance, differences: Option<&Differences>) -> Vec<Option<f64>> {
    let mut values: Vec<Option<f64>> = figures.gloss.iter().map(|v| Some(*v)).collect();
    values.extend(
        [
            figures.haze,
            figures.doi,
            figures.haze_20,
            figures.haze_d4039,
        ]
        .map(Some),
    );
    for lab in &figures.colour {
        values.extend((0..3).map(|i| lab.map(|c| c[i])));
    }
    values.push(figures.flop_index);
    if let Some(d) = differences {
        values.extend(d.values());
    }
    values
}

/// One CSV row matching [`csv_header`].
pub fn csv_row(
    source: &str,
    figures: &Appearance,
    differences: Option<&Differences>,
) -> Vec<String> {
    std::iter::once(source.to_string())
        .chain(column_values(figures, differences).into_iter().map(cell))
        .collect()
}

/// The rows of the text table, one per figure: its label, then its value per material;
/// with a reference, each value is followed by its difference in brackets.
pub fn text_rows(figures: &[&Appearance], differences: Option<&[Differences]>) -> Vec<Vec<String>> {
    text_rows_with(figures, differences, &[])
}

/// As [`text_rows`], each value followed by `± U` where `expanded[material]` holds the
/// figures' expanded uncertainties ([`crate::uncertainty::expanded_uncertainty`], in
/// [`column_values`]'s order); a material beyond `expanded` or `None` there shows none.
pub fn text_rows_with(
    figures: &[&Appearance],
    differences: Option<&[Differences]>,
    expanded: &[Option<Vec<Option<f64>>>],
) -> Vec<Vec<String>> {
    let show = |value: Option<f64>, delta: Option<f64>, u: Option<f64>| {
        let plus_minus = u.map_or_else(String::new, |u| format!(" ± {u:.2}"));
        match (value, delta) {
            (Some(v), Some(d)) => format!("{v:.2}{plus_minus} ({d:+.2})"),
            (Some(v), None) => format!("{v:.2}{plus_minus}"),
            (None, Some(d)) => format!("{d:.2}"),
            (None, None) => "n/a".to_string(),
        }
    };
    let u_of = |material: usize, column: Option<usize>| {
        let column = column?;
        expanded
            .get(material)?
            .as_ref()?
            .get(column)
            .copied()
            .flatten()
    };
    let mut rows: Vec<Vec<String>> = Vec::new();
    let mut add = |label: String,
                   column: Option<usize>,
                   value: &dyn Fn(&Appearance) -> Option<f64>,
                   delta: &dyn Fn(&Differences) -> Option<f64>| {
        let cells: Vec<String> = figures
            .iter()
            .enumerate()
            .map(|(i, f)| {
                show(
                    value(f),
                    differences.and_then(|d| delta(&d[i])),
                    u_of(i, column),
                )
            })
            .collect();
        rows.push(std::iter::once(label).chain(cells).collect());
    };
    for (k, g) in GEOMETRIES.iter().enumerate() {
        add(
            format!("gloss {} deg (GU)", g.angle_deg),
            Some(k),
            &|f| Some(f.gloss[k]),
            &|d| Some(d.gloss[k]),
        );
    }
    add(
        "haze, E430 30 deg".into(),
        Some(3),
        &|f| Some(f.haze),
        &|d| Some(d.haze),
    );
    add("DOI, E430 30 deg".into(), Some(4), &|f| Some(f.doi), &|d| {
        Some(d.doi)
    });
    add(
        "haze 20 deg, ISO 13803".into(),
        Some(5),
        &|f| Some(f.haze_20),
        &|d| Some(d.haze_20),
    );
    add(
        "haze index, D4039 (G60 - G20)".into(),
        Some(6),
        &|f| Some(f.haze_d4039),
        &|d| Some(d.haze_d4039),
    );
    for (k, gamma) in ASPECULAR_DEG.iter().enumerate() {
        for (i, channel) in ["L*", "a*", "b*"].iter().enumerate() {
            add(
                format!("{channel} {gamma} deg"),
                Some(7 + 3 * k + i),
                &|f| f.colour[k].map(|c| c[i]),
                &|_| None,
            );
        }
        if differences.is_some() {
            add(format!("dE00 {gamma} deg"), None, &|_| None, &|d| {
                d.delta_e00[k]
            });
        }
    }
    add(
        "flop index".into(),
        Some(7 + 3 * ASPECULAR_DEG.len()),
        &|f| f.flop_index,
        &|d| d.flop_index,
    );
    rows
}
