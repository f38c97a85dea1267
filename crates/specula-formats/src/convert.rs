//! Which measured format a file is, and conversion between the formats Specula reads and
//! writes: MERL `.binary`, UTIA `.bin`, RGL `.bsdf` (isotropic RGB, [`crate::rgl::RglTables`])
//! and the samples `.csv`. Any other BRDF source (a preset, a `model:name` fit) can be
//! converted too.
//!
//! Where grids differ the source is resampled at the target's nodes with its own evaluator
//! (MERL nearest bin, UTIA quadrilinear, RGL the adaptive warp, samples their binned cells).
//! Provenance is kept where the target can say "not measured": a node whose source value is
//! not measured is written as such in MERL (negative) and UTIA (-1, Specula's convention), and
//! has no row in a samples CSV, and its RGL node holds the nearest measured node's value with
//! its `valid` bit cleared. Same-format conversions copy, except RGL, which is rebuilt at the
//! chosen resolution.

use crate::brdf_source::BrdfSource;
use crate::input::{file_error, read_input};
use crate::input::{io_error, FormatError, Result};
use crate::rgl::write as rgl;
use crate::rgl::{RglBsdf, RglResolution, RglTables};
use crate::samples_csv::SampleSet;
use crate::utia::{self, UtiaBrdf};
use specula_core::merl::{Bin, MerlBrdf, CELLS};
use specula_core::range::{CountRange, RangeError};
use specula_core::request::{parse_choice, ChoiceError, AZIMUTH_DEG};
use specula_core::tabulate::tabulate;
use specula_core::{Brdf, HalfDiff, Sample};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A measured BRDF file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileFormat {
    /// MERL `.binary` (Matusik et al. 2003).
    Merl,
    /// UTIA BRDF database `.bin` (Filip & Vávra 2014).
    Utia,
    /// RGL material database `.bsdf` (Dupuy & Jakob 2018), isotropic RGB.
    Rgl,
    /// Samples `.csv` (`theta_h,phi_h,theta_d,phi_d,r,g,b`, degrees, 1/sr).
    SamplesCsv,
}

impl FileFormat {
    /// A short name for messages.
    pub fn label(self) -> &'static str {
        match self {
            Self::Merl => "MERL .binary",
            Self::Utia => "UTIA .bin",
            Self::Rgl => "RGL .bsdf",
            Self::SamplesCsv => "samples .csv",
        }
    }

    /// The format named by a path's extension (case-insensitive).
    pub fn from_extension(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_string_lossy().to_ascii_lowercase();
        match ext.as_str() {
            "binary" => Some(Self::Merl),
            "bin" => Some(Self::Utia),
            "bsdf" => Some(Self::Rgl),
            "csv" => Some(Self::SamplesCsv),
            _ => None,
        }
    }

    /// The format of a file's content, from its first bytes and its length: the tensor-file
    /// magic (RGL), the MERL header (90, 90, 180), the exact UTIA size, or a samples header.
    pub fn sniff(prefix: &[u8], file_len: u64) -> Option<Self> {
        if prefix.starts_with(crate::rgl::MAGIC) {
            return Some(Self::Rgl);
        }
        let merl_header: Vec<u8> = [90i32, 90, 180]
            .iter()
            .flat_map(|d| d.to_le_bytes())
            .collect();
        if prefix.starts_with(&merl_header) {
            return Some(Self::Merl);
        }
        if file_len == utia::FILE_BYTES as u64 {
            return Some(Self::Utia);
        }
        let text = String::from_utf8_lossy(prefix);
        let first = text.trim_start_matches('\u{feff}').trim_start();
        if first.starts_with("theta_h,") {
            return Some(Self::SamplesCsv);
        }
        None
    }

    /// The format of an existing file: by its magic bytes when they are unambiguous (RGL,
    /// MERL), else by its extension, else by its size or header; `None` if unrecognised.
    pub fn detect(path: &Path) -> Result<Option<Self>> {
        let mut file = std::fs::File::open(path).map_err(|cause| io_error(path, "open", cause))?;
        let len = file.metadata().map(|m| m.len()).unwrap_or(0);
        let mut prefix = Vec::with_capacity(64);
        file.by_ref()
            .take(64)
            .read_to_end(&mut prefix)
            .map_err(|cause| io_error(path, "read", cause))?;
        let sniffed = Self::sniff(&prefix, len);
        Ok(match sniffed {
            Some(Self::Rgl) | Some(Self::Merl) => sniffed,
            _ => Self::from_extension(path).or(sniffed),
        })
    }
}

/// A BRDF read from a file of a known format, or from any other source.
pub enum Loaded {
    /// A MERL binary (`.binary`): 90 x 90 x 180 f_r values in 1/sr on the half-difference grid.
    Merl(MerlBrdf),
    /// A UTIA binary (`.bin`): 6 x 48 x 6 x 48 f_r values in 1/sr at incident and outgoing angles.
    Utia(UtiaBrdf),
    /// An RGL `.bsdf` file of Dupuy & Jakob's adaptive parameterisation.
    Rgl(Box<RglBsdf>),
    /// A CSV file of samples at half-difference angles (degrees) with f_r in 1/sr.
    Samples(SampleSet),
    /// A preset, a material file or a model fit.
    Other(BrdfSource),
}

impl Loaded {
    /// Reads `path` as `format`; the error names the file and the problem.
    pub fn read(path: &Path, format: FileFormat) -> Result<Self> {
        Ok(match format {
            FileFormat::Merl => {
                let bytes = read_input(path)?;
                let name = crate::input::file_stem(path);
                Self::Merl(MerlBrdf::from_bytes(name, &bytes).map_err(|problem| {
                    FormatError::Merl {
                        path: path.to_path_buf(),
                        problem,
                    }
                })?)
            }
            FileFormat::Utia => Self::Utia(UtiaBrdf::read(path)?),
            FileFormat::Rgl => Self::Rgl(Box::new(RglBsdf::read(path)?)),
            FileFormat::SamplesCsv => Self::Samples(SampleSet::read(path)?),
        })
    }

    /// A measured file when `spec` is one (by [`FileFormat::detect`]), otherwise whatever
    /// [`crate::load_brdf`] makes of it.
    pub fn resolve(spec: &str) -> Result<Self> {
        let path = Path::new(spec);
        if path.is_file() {
            if let Some(format) = FileFormat::detect(path)? {
                return Self::read(path, format);
            }
        }
        Ok(Self::Other(crate::load_brdf(spec)?))
    }

    /// The BRDF, behind a shared pointer.
    pub fn into_brdf(self) -> BrdfSource {
        match self {
            Self::Merl(t) => Arc::new(t),
            Self::Utia(t) => Arc::new(t),
            Self::Rgl(t) => Arc::new(*t),
            Self::Samples(t) => Arc::new(t),
            Self::Other(b) => b,
        }
    }

    fn as_brdf(&self) -> &dyn Brdf {
        match self {
            Self::Merl(t) => t,
            Self::Utia(t) => t,
            Self::Rgl(t) => t.as_ref(),
            Self::Samples(t) => t,
            Self::Other(b) => b.as_ref(),
        }
    }
}

/// Where to place samples when a continuous source (RGL, a fit) is written as a samples CSV.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CsvGrid {
    /// The 1,458,000 MERL bin centres.
    Merl,
    /// The 82,944 UTIA nodes.
    Utia,
}

impl CsvGrid {
    /// `merl` or `utia`.
    pub fn name(self) -> &'static str {
        match self {
            CsvGrid::Merl => "merl",
            CsvGrid::Utia => "utia",
        }
    }
}

impl std::str::FromStr for CsvGrid {
    type Err = ChoiceError;

    /// [`CsvGrid::name`].
    fn from_str(text: &str) -> Result<Self, ChoiceError> {
        parse_choice(
            "grid",
            text,
            &[CsvGrid::Merl, CsvGrid::Utia],
            &["merl", "utia"],
            CsvGrid::name,
        )
    }
}

impl std::fmt::Display for CsvGrid {
    /// [`CsvGrid::name`].
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Choices of a conversion.
#[derive(Debug, Clone, Copy)]
pub struct ConvertOptions {
    /// Azimuth of the half vector, radians, at which MERL cells and bin-centre samples are
    /// taken (matters only for anisotropic sources such as UTIA files).
    pub phi_h_rad: f64,
    /// Sample placement for continuous sources written as CSV.
    pub csv_grid: CsvGrid,
    /// Table sizes of a written RGL `.bsdf`.
    pub rgl: RglResolution,
}

/// Incident elevations of a written RGL file (the writer's [`rgl::ELEVATIONS_RANGE`]).
pub const RGL_ELEVATIONS: CountRange = count_range(rgl::ELEVATIONS_RANGE);
/// Nodes of a written RGL file's microfacet distribution ([`rgl::NDF_SIZE_RANGE`]).
pub const RGL_NDF_SIZE: CountRange = count_range(rgl::NDF_SIZE_RANGE);
/// Samples per axis of a written RGL file's RGB grid ([`rgl::SAMPLE_SIZE_RANGE`]).
pub const RGL_SAMPLE_SIZE: CountRange = count_range(rgl::SAMPLE_SIZE_RANGE);

/// An RGL writer's range of counts as a [`CountRange`].
const fn count_range(range: std::ops::RangeInclusive<usize>) -> CountRange {
    CountRange::from_to(*range.start(), *range.end())
}

/// What `specula convert` and `specula.convert` ask, every range checked in one place
/// ([`ConvertRequest::validate`], errors naming the Python argument; the CLI's parsers say
/// the same words after the flag), and the one entry point both call ([`run_convert`]).
#[derive(Debug, Clone)]
pub struct ConvertRequest {
    /// The BRDF to convert: a file of any readable format, or any BRDF source.
    pub input: String,
    /// The file to write; its extension gives the format.
    pub output: PathBuf,
    /// Azimuth of the half vector, degrees, at which MERL cells and bin-centre samples are
    /// taken, in [`AZIMUTH_DEG`].
    pub phi_h_deg: f64,
    /// Sample placement for continuous sources written as CSV.
    pub csv_grid: CsvGrid,
    /// Table sizes of a written RGL `.bsdf`, in [`RGL_ELEVATIONS`], [`RGL_NDF_SIZE`] and
    /// [`RGL_SAMPLE_SIZE`].
    pub rgl: RglResolution,
}

impl ConvertRequest {
    /// Checks every value against its range.
    pub fn validate(&self) -> std::result::Result<(), RangeError> {
        AZIMUTH_DEG.check("phi_h_deg", self.phi_h_deg)?;
        RGL_ELEVATIONS.check("rgl_elevations", self.rgl.elevations)?;
        RGL_NDF_SIZE.check("rgl_ndf_size", self.rgl.ndf_size)?;
        RGL_SAMPLE_SIZE.check("rgl_sample_size", self.rgl.sample_size)?;
        Ok(())
    }

    /// The conversion's options.
    pub fn options(&self) -> ConvertOptions {
        ConvertOptions {
            phi_h_rad: self.phi_h_deg.to_radians(),
            csv_grid: self.csv_grid,
            rgl: self.rgl,
        }
    }
}

/// Why a conversion is refused or fails.
#[derive(Debug, thiserror::Error)]
pub enum ConvertError {
    /// A value outside its range.
    #[error(transparent)]
    Range(#[from] RangeError),
    /// The input cannot be read or the output written.
    #[error(transparent)]
    Format(#[from] FormatError),
}

/// Converts as `request` asks ([`convert`]).
pub fn run_convert(request: &ConvertRequest) -> std::result::Result<Conversion, ConvertError> {
    request.validate()?;
    Ok(convert(
        &request.input,
        &request.output,
        &request.options(),
    )?)
}

/// What a conversion did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Conversion {
    /// The format written.
    pub target: FileFormat,
    /// How the values were obtained (copied, binned, evaluated at the target's nodes).
    pub method: &'static str,
    /// Cells, nodes or rows written with a measured value.
    pub measured: usize,
    /// Cells or nodes written as not measured (always 0 for CSV: such points have no row).
    pub not_measured: usize,
}

/// Converts the BRDF source `input` (a file of any readable format, or any BRDF source) into
/// the file `output`, whose format is given by its extension.
pub fn convert(input: &str, output: &Path, options: &ConvertOptions) -> Result<Conversion> {
    let Some(target) = FileFormat::from_extension(output) else {
        return Err(file_error(
            output,
            "unknown output format (use .binary for MERL, .bin for UTIA, .bsdf for RGL, .csv for samples)",
        ));
    };
    let source = Loaded::resolve(input)?;
    match target {
        FileFormat::Merl => {
            let (table, method) = to_merl(source, options);
            table.write(output)?;
            let measured = table.measured_count();
            Ok(Conversion {
                target,
                method,
                measured,
                not_measured: CELLS - measured,
            })
        }
        FileFormat::Utia => {
            let (table, method) = to_utia(source);
            table.write(output)?;
            let measured = table.measured_count();
            Ok(Conversion {
                target,
                method,
                measured,
                not_measured: utia::NODES - measured,
            })
        }
        FileFormat::SamplesCsv => {
            let (set, method) = to_samples(source, options);
            set.write(output)?;
            Ok(Conversion {
                target,
                method,
                measured: set.samples().len(),
                not_measured: 0,
            })
        }
        FileFormat::Rgl => {
            let tables = to_rgl(&source, options.rgl)?;
            tables.write(output)?;
            Ok(Conversion {
                target,
                method: "evaluated on the VNDF-warped grid (NDF from the retro-reflection by power iteration)",
                measured: tables.nodes() - tables.not_measured - tables.below_horizon,
                not_measured: tables.not_measured,
            })
        }
    }
}

/// The source as the tables of an RGL `.bsdf` file.
pub fn to_rgl(source: &Loaded, resolution: RglResolution) -> Result<RglTables> {
    let brdf = source.as_brdf();
    let description = format!("{} (written by Specula)", brdf.name());
    Ok(RglTables::from_brdf(brdf, resolution, &description)?)
}

/// The source as a MERL table.
pub fn to_merl(source: Loaded, options: &ConvertOptions) -> (MerlBrdf, &'static str) {
    match source {
        Loaded::Merl(table) => (table, "copied"),
        Loaded::Samples(set) => (
            set.binned().clone(),
            "binned samples into MERL cells (mean per cell)",
        ),
        other => (
            tabulate(other.as_brdf(), options.phi_h_rad),
            "evaluated at MERL bin centres",
        ),
    }
}

/// The source as a UTIA table.
pub fn to_utia(source: Loaded) -> (UtiaBrdf, &'static str) {
    match source {
        Loaded::Utia(table) => (table, "copied"),
        other => (
            UtiaBrdf::tabulate(other.as_brdf()),
            "evaluated at UTIA nodes",
        ),
    }
}

/// The source as samples.
pub fn to_samples(source: Loaded, options: &ConvertOptions) -> (SampleSet, &'static str) {
    match source {
        Loaded::Samples(set) => (set, "copied"),
        Loaded::Merl(table) => (
            SampleSet::from_merl(&table, options.phi_h_rad),
            "measured MERL cells at their bin centres",
        ),
        Loaded::Utia(table) => (utia_samples(&table), "measured UTIA nodes"),
        other => match options.csv_grid {
            CsvGrid::Merl => {
                let centres = (0..CELLS).map(|i| Bin::from_index(i).centre(options.phi_h_rad));
                (
                    SampleSet::from_brdf_at(other.as_brdf(), centres),
                    "evaluated at MERL bin centres",
                )
            }
            CsvGrid::Utia => (
                utia_samples(&UtiaBrdf::tabulate(other.as_brdf())),
                "evaluated at UTIA nodes",
            ),
        },
    }
}

/// The measured nodes of a UTIA table as samples, with their exact stored values.
fn utia_samples(table: &UtiaBrdf) -> SampleSet {
    let samples = (0..utia::NODES)
        .filter_map(|i| {
            let value = table.node(i)?;
            let (wi, wo) = utia::Node::from_index(i).directions();
            Some(Sample::new(HalfDiff::from_directions(wi, wo), value))
        })
        .collect();
    SampleSet::new(table.name(), samples)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_request_out_of_range_is_refused_with_the_python_arguments_words() {
        let dir = tempfile::tempdir().unwrap();
        let request = ConvertRequest {
            input: "chrome".to_string(),
            output: dir.path().join("chrome.bsdf"),
            phi_h_deg: 45.0,
            csv_grid: CsvGrid::Merl,
            rgl: RglResolution {
                elevations: 1,
                ..RglResolution::DEFAULT
            },
        };
        let error = run_convert(&request).unwrap_err().to_string();
        assert_eq!(
            error,
            "rgl_elevations 1: expected a whole number from 2 to 90"
        );
        let turned = ConvertRequest {
            phi_h_deg: -400.0,
            rgl: RglResolution::DEFAULT,
            ..request
        };
        let error = run_convert(&turned).unwrap_err().to_string();
        assert_eq!(error, "phi_h_deg -400: expected degrees from -360 to 360");
        assert!(!turned.output.exists());
    }

    #[test]
    fn formats_are_recognised_by_content() {
        assert_eq!(
            FileFormat::sniff(b"tensor_file\0\x01\x00", 100),
            Some(FileFormat::Rgl)
        );
        let merl: Vec<u8> = [90i32, 90, 180]
            .iter()
            .flat_map(|d| d.to_le_bytes())
            .collect();
        assert_eq!(FileFormat::sniff(&merl, 5), Some(FileFormat::Merl));
        assert_eq!(
            FileFormat::sniff(&[0; 64], utia::FILE_BYTES as u64),
            Some(FileFormat::Utia)
        );
        assert_eq!(
            FileFormat::sniff(b"theta_h,phi_h,theta_d", 99),
            Some(FileFormat::SamplesCsv)
        );
        assert_eq!(FileFormat::sniff(b"[material]", 99), None);
        assert_eq!(
            FileFormat::from_extension(Path::new("a/B.BSDF")),
            Some(FileFormat::Rgl)
        );
        assert_eq!(FileFormat::from_extension(Path::new("a.toml")), None);
    }
}
