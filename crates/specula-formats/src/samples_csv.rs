//! A CSV file of BRDF samples at half-difference angles: the exchange format between
//! measurement, reconstruction and conversion.
//!
//! Header exactly `theta_h,phi_h,theta_d,phi_d,r,g,b` (the same file `specula-reconstruct`
//! reads): angles in degrees, f_r in 1/sr per channel, one sample per row. Elevations
//! lie in `[0, 90]`; azimuths are free and wrapped. Every value must be finite and f_r
//! non-negative; a cell that was not measured simply has no row.
//!
//! As a [`Brdf`], a sample set is its samples binned into the MERL grid (the mean of the
//! samples of each cell; phi_d folded by reciprocity as MERL does, no other symmetry), so it
//! answers `None` where no sample fell: filling the gaps is reconstruction's job.

use crate::input::{file_error, file_stem, io_error, open_input, Malformed, Result};
use glam::DVec3;
use specula_core::merl::{Bin, CELLS};
use specula_core::shown::excerpt;
use specula_core::{Brdf, HalfDiff, MerlBrdf, Rgb, Sample};
use std::io::Write;
use std::path::Path;

/// The header written, and the columns a sample file must have.
pub const HEADER: [&str; 7] = ["theta_h", "phi_h", "theta_d", "phi_d", "r", "g", "b"];

/// Samples, and the MERL table they bin into.
#[derive(Clone)]
pub struct SampleSet {
    name: String,
    samples: Vec<Sample>,
    binned: MerlBrdf,
}

impl std::fmt::Debug for SampleSet {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SampleSet")
            .field("name", &self.name)
            .field("samples", &self.samples.len())
            .finish()
    }
}

#[derive(serde::Deserialize)]
struct Row {
    theta_h: f64,
    phi_h: f64,
    theta_d: f64,
    phi_d: f64,
    r: f64,
    g: f64,
    b: f64,
}

impl Row {
    fn into_sample(self) -> Result<Sample, String> {
        let all = [
            self.theta_h,
            self.phi_h,
            self.theta_d,
            self.phi_d,
            self.r,
            self.g,
            self.b,
        ];
        if let Some(i) = all.iter().position(|v| !v.is_finite()) {
            return Err(format!("{} is not finite ({})", HEADER[i], all[i]));
        }
        for (name, theta) in [("theta_h", self.theta_h), ("theta_d", self.theta_d)] {
            if !(0.0..=90.0).contains(&theta) {
                return Err(format!("{name} = {theta} deg is outside [0, 90]"));
            }
        }
        let value = Rgb::new(self.r, self.g, self.b);
        if value.min_element() < 0.0 {
            return Err(format!("negative f_r ({}, {}, {})", self.r, self.g, self.b));
        }
        Ok(Sample::new(
            HalfDiff::from_degrees(self.theta_h, self.phi_h, self.theta_d, self.phi_d),
            value,
        ))
    }
}

impl SampleSet {
    /// A set from samples; bins them into the MERL grid.
    pub fn new(name: impl Into<String>, samples: Vec<Sample>) -> Self {
        let name = name.into();
        let binned = bin_into_merl(&name, &samples);
        Self {
            name,
            samples,
            binned,
        }
    }

    /// Reads a samples CSV file, streamed (its size checked first); the error names the
    /// file, the row and the problem.
    pub fn read(path: &Path) -> Result<Self> {
        let file = std::io::BufReader::new(open_input(path)?);
        Self::from_csv(file_stem(path), file).map_err(|problem| file_error(path, problem))
    }

    /// Parses the text of a samples CSV file, streamed; the error says which row is wrong and
    /// why.
    pub fn from_csv(name: impl Into<String>, text: impl std::io::Read) -> Result<Self, Malformed> {
        let text = specula_core::bounded_read::BoundedText::new(
            text,
            specula_core::bounded_read::CSV_LIMITS,
        );
        let mut reader = csv::ReaderBuilder::new()
            .trim(csv::Trim::All)
            .from_reader(text);
        let header = reader
            .headers()
            .map_err(|e| format!("unreadable header: {e}"))?
            .clone();
        if header.iter().ne(HEADER.iter().copied()) {
            return Err(format!(
                "header is '{}', expected '{}'",
                excerpt(&header.iter().collect::<Vec<_>>().join(",")),
                HEADER.join(",")
            )
            .into());
        }
        let mut samples = Vec::new();
        for (i, row) in reader.deserialize::<Row>().enumerate() {
            let line = i + 2;
            let sample = row
                .map_err(|e| format!("row {line}: {}", one_line(&e.to_string())))
                .and_then(|r| r.into_sample().map_err(|p| format!("row {line}: {p}")))?;
            samples.push(sample);
        }
        if samples.is_empty() {
            return Err("no samples (the file has a header and no rows)".into());
        }
        Ok(Self::new(name, samples))
    }

    /// The measured cells of a MERL table as samples at their bin centres, at azimuth `phi_h_rad`.
    pub fn from_merl(table: &MerlBrdf, phi_h_rad: f64) -> Self {
        let samples = (0..CELLS)
            .filter_map(|i| {
                table
                    .cell(i)
                    .map(|value| Sample::new(Bin::from_index(i).centre(phi_h_rad), value))
            })
            .collect();
        Self::new(table.name(), samples)
    }

    /// Samples of any BRDF at the given half-difference angles; angles where it reports
    /// "not measured" give no sample.
    pub fn from_brdf_at(brdf: &dyn Brdf, angles: impl IntoIterator<Item = HalfDiff>) -> Self {
        let samples = angles
            .into_iter()
            .filter_map(|hd| brdf.eval_half_diff(hd).map(|value| Sample::new(hd, value)))
            .collect();
        Self::new(brdf.name(), samples)
    }

    /// Writes the CSV file.
    pub fn write(&self, path: &Path) -> Result<()> {
        specula_core::atomic_file::write_with(path, |out| self.write_to(out))
            .map_err(|cause| io_error(path, "write", cause))
    }

    /// Writes the CSV text; f64 values are printed in their shortest exact form.
    pub fn write_to(&self, out: &mut impl Write) -> std::io::Result<()> {
        writeln!(out, "{}", HEADER.join(","))?;
        for s in &self.samples {
            let a = s.hd;
            writeln!(
                out,
                "{},{},{},{},{},{},{}",
                a.theta_h.to_degrees(),
                a.phi_h.to_degrees(),
                a.theta_d.to_degrees(),
                a.phi_d.to_degrees(),
                s.value.x,
                s.value.y,
                s.value.z
            )?;
        }
        Ok(())
    }

    /// The samples, in file order.
    pub fn samples(&self) -> &[Sample] {
        &self.samples
    }

    /// The samples binned into the MERL grid (mean per cell; cells without samples are not measured).
    pub fn binned(&self) -> &MerlBrdf {
        &self.binned
    }
}

/// The mean of the samples falling in each MERL cell; cells without samples stay unmeasured.
fn bin_into_merl(name: &str, samples: &[Sample]) -> MerlBrdf {
    let mut sums = vec![(Rgb::ZERO, 0u32); CELLS];
    for s in samples {
        let cell = &mut sums[Bin::of(s.hd).index()];
        cell.0 += s.value;
        cell.1 += 1;
    }
    let mut table = MerlBrdf::empty(name);
    for (index, (sum, count)) in sums.into_iter().enumerate() {
        if count > 0 {
            table.set_cell(index, Some(sum / count as f64));
        }
    }
    table
}

/// The first line of a message (csv errors can span several).
fn one_line(message: &str) -> &str {
    message.lines().next().unwrap_or(message)
}

impl Brdf for SampleSet {
    fn eval(&self, wi: DVec3, wo: DVec3) -> Option<Rgb> {
        self.binned.eval(wi, wo)
    }

    fn eval_half_diff(&self, hd: HalfDiff) -> Option<Rgb> {
        self.binned.eval_half_diff(hd)
    }

    fn name(&self) -> String {
        self.name.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "theta_h,phi_h,theta_d,phi_d,r,g,b\n\
                        1.0,45,40.5,90.5,0.5,0.25,0.125\n\
                        1.02,45,40.7,270.9,1.5,0.75,0.375\n\
                        30,0,10,10,2,2,2\n";

    #[test]
    fn samples_bin_into_merl_cells() {
        let set = SampleSet::from_csv("t", TEXT.as_bytes()).unwrap();
        assert_eq!(set.samples().len(), 3);
        assert_eq!(
            set.binned().measured_count(),
            2,
            "rows 1 and 2 share a cell (phi_d folded by 180)"
        );
        let mean = set
            .eval_half_diff(HalfDiff::from_degrees(1.01, 0.0, 40.6, 90.6))
            .unwrap();
        assert!((mean - Rgb::new(1.0, 0.5, 0.25)).length() < 1e-12, "{mean}");
        assert_eq!(
            set.eval_half_diff(HalfDiff::from_degrees(50.0, 0.0, 10.0, 10.0)),
            None
        );
    }

    #[test]
    fn text_round_trips_exactly() {
        let set = SampleSet::from_csv("t", TEXT.as_bytes()).unwrap();
        let mut out = Vec::new();
        set.write_to(&mut out).unwrap();
        let back = SampleSet::from_csv("t", out.as_slice()).unwrap();
        for (a, b) in set.samples().iter().zip(back.samples()) {
            assert!((a.hd.theta_h - b.hd.theta_h).abs() < 1e-15);
            assert!((a.hd.phi_d - b.hd.phi_d).abs() < 1e-14);
            assert_eq!(a.value, b.value);
        }
        let spaced = "theta_h, phi_h, theta_d, phi_d, r, g, b\n3, 0, 4, 5, 1, 1, 1\n";
        assert_eq!(
            SampleSet::from_csv("d", spaced.as_bytes())
                .unwrap()
                .samples()
                .len(),
            1
        );
    }

    #[test]
    fn bad_rows_are_described() {
        let cases = [
            (
                "theta_h,phi_h,theta_d,phi_d,r,g\n1,2,3,4,5,6\n",
                "header is 'theta_h,phi_h,theta_d,phi_d,r,g', expected",
            ),
            ("theta_h,phi_h,theta_d,phi_d,r,g,b\n", "no samples"),
            (
                "theta_h,phi_h,theta_d,phi_d,r,g,b\n1,2,3,4,5,6,NaN\n",
                "row 2: b is not finite",
            ),
            (
                "theta_h,phi_h,theta_d,phi_d,r,g,b\n1,2,3,4,5,6,7\n95,0,3,4,5,6,7\n",
                "row 3: theta_h = 95",
            ),
            (
                "theta_h,phi_h,theta_d,phi_d,r,g,b\n1,2,3,4,5,-6,7\n",
                "row 2: negative f_r",
            ),
            (
                "theta_h,phi_h,theta_d,phi_d,r,g,b\n1,2,3,4,5,six,7\n",
                "row 2:",
            ),
            ("theta_h,phi_h,theta_d,phi_d,r,g,b\n1,2,3,4,5,6\n", "row 2:"),
        ];
        for (text, expected) in cases {
            let err = SampleSet::from_csv("bad", text.as_bytes()).unwrap_err();
            assert!(err.contains(expected), "{text:?}: {err}");
            assert!(!err.contains('\n'), "{err}");
        }
        let long_header = format!("theta_h,{}\x1b\n1\n", "x".repeat(60_000));
        let err = SampleSet::from_csv("bad", long_header.as_bytes()).unwrap_err();
        assert!(err.len() < 200 && !err.contains('\x1b'), "{err}");
        let long_row = format!(
            "theta_h,phi_h,theta_d,phi_d,r,g,b\n{}\n",
            "1".repeat(200_000)
        );
        let err = SampleSet::from_csv("bad", long_row.as_bytes()).unwrap_err();
        assert!(
            err.contains("line 2 is longer than 65536 bytes") && err.len() < 200,
            "{err}"
        );
    }
}
