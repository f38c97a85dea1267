//! Published analytic fits of the 100 MERL materials (Jonathan Dupuy's `dj_brdf` tables):
//! the shifted-gamma microfacet model of Bagher, Soler & Holzschuch 2012 ([`sgd`], `sgd:NAME`)
//! and the ABC model of Löw, Kronander, Ynnerman & Unger 2012 ([`abc`], `abc:NAME`). They
//! stand in for the MERL-100 measurements, which are not distributed here.
//! Tables, formulas and check values: `shared/data/measured/merl_fits_djbrdf/PROVENANCE.md`.

pub mod abc;
pub mod sgd;

use crate::brdf_source::BrdfSource;
use crate::input::argument_error;
use crate::input::{csv_error, data_file, file_error, read_input, Malformed, Result};
use specula_core::bounded_read::{BoundedText, CSV_LIMITS};
use specula_core::Rgb;
use std::path::Path;
use std::sync::Arc;

/// The two fitted models.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FitModel {
    /// Bagher et al. 2012, `sgd:NAME`.
    Sgd,
    /// Löw et al. 2012, `abc:NAME`.
    Abc,
}

impl FitModel {
    /// The model of a `model:name` prefix.
    pub fn from_prefix(prefix: &str) -> Option<Self> {
        match prefix {
            "sgd" => Some(FitModel::Sgd),
            "abc" => Some(FitModel::Abc),
            _ => None,
        }
    }

    /// The `model:` prefix naming this model in BRDF arguments.
    pub(crate) fn prefix(self) -> &'static str {
        match self {
            FitModel::Sgd => "sgd",
            FitModel::Abc => "abc",
        }
    }

    /// The table's path inside the measured data directory.
    pub fn table(self) -> &'static str {
        match self {
            FitModel::Sgd => "merl_fits_djbrdf/merl_sgd_bagher2012.csv",
            FitModel::Abc => "merl_fits_djbrdf/merl_abc_low2012.csv",
        }
    }

    /// The model whose table has these column names.
    fn of_headers(headers: &csv::StringRecord) -> Option<Self> {
        let has = |name: &str| headers.iter().any(|h| h == name);
        if has("rhoD_r") && has("theta0_r") {
            Some(FitModel::Sgd)
        } else if has("kD_r") && has("ior") {
            Some(FitModel::Abc)
        } else {
            None
        }
    }
}

/// Every material of a fits table (SGD or ABC, told apart by its columns), as BRDFs.
pub fn load_fits(path: &Path) -> Result<Vec<BrdfSource>> {
    parse_fits(path, &read_input(path)?)
}

/// Every material of a model's table (built in: [`crate::input::data_file`]).
pub fn load_model(model: FitModel) -> Result<Vec<BrdfSource>> {
    let file = data_file(model.table())?;
    parse_fits(&file.path, &file.bytes)
}

/// The fits of a table's bytes; errors name `path`.
fn parse_fits(path: &Path, bytes: &[u8]) -> Result<Vec<BrdfSource>> {
    let mut reader = csv::Reader::from_reader(BoundedText::new(bytes, CSV_LIMITS));
    let headers = reader
        .headers()
        .map_err(|e| csv_error(path, "cannot read the header", e))?
        .clone();
    let model = FitModel::of_headers(&headers).ok_or_else(|| {
        file_error(
            path,
            "not an SGD or ABC fits table (expected the columns of merl_fits_djbrdf)",
        )
    })?;
    let mut fits: Vec<BrdfSource> = Vec::new();
    for (i, record) in reader.records().enumerate() {
        let row_number = i + 2;
        let record = record.map_err(|e| csv_error(path, format!("row {row_number}"), e))?;
        let row = TableRow {
            headers: &headers,
            record: &record,
        };
        let brdf: Result<BrdfSource, Malformed> = match model {
            FitModel::Sgd => sgd::Sgd::from_row(&row).map(|f| Arc::new(f) as BrdfSource),
            FitModel::Abc => abc::Abc::from_row(&row).map(|f| Arc::new(f) as BrdfSource),
        };
        fits.push(brdf.map_err(|p| file_error(path, format!("row {row_number}: {p}")))?);
    }
    if fits.is_empty() {
        return Err(file_error(path, "the table has no rows"));
    }
    Ok(fits)
}

/// The fit of one material from the model's table in the measured data directory.
pub fn load_fit(model: FitModel, material: &str) -> Result<BrdfSource> {
    let all = load_model(model)?;
    let count = all.len();
    let wanted = format!("{}:{material}", model.prefix());
    let names: Vec<String> = all.iter().map(|f| f.name()).collect();
    all.into_iter().find(|f| f.name() == wanted).ok_or_else(|| {
        argument_error(
            &wanted,
            format!(
                "no such material among the {count} {} fits{}",
                model.prefix(),
                crate::near_name::did_you_mean(&wanted, &names)
            ),
        )
    })
}

/// A row of a fits table with access by column name.
pub(crate) struct TableRow<'a> {
    headers: &'a csv::StringRecord,
    record: &'a csv::StringRecord,
}

impl TableRow<'_> {
    /// The text under `column`.
    pub(crate) fn text(&self, column: &str) -> Result<&str, Malformed> {
        let at = self
            .headers
            .iter()
            .position(|h| h == column)
            .ok_or_else(|| Malformed(format!("no column {column}")))?;
        self.record
            .get(at)
            .map(str::trim)
            .ok_or_else(|| Malformed(format!("missing value under {column}")))
    }

    /// The finite number under `column`.
    pub(crate) fn number(&self, column: &str) -> Result<f64, Malformed> {
        let text = self.text(column)?;
        match text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(Malformed(format!(
                "{column} = '{text}' is not a finite number"
            ))),
        }
    }

    /// The three numbers under `{prefix}_r`, `{prefix}_g`, `{prefix}_b`.
    pub(crate) fn rgb(&self, prefix: &str) -> Result<Rgb, Malformed> {
        Ok(Rgb::new(
            self.number(&format!("{prefix}_r"))?,
            self.number(&format!("{prefix}_g"))?,
            self.number(&format!("{prefix}_b"))?,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::HalfDiff;

    fn green_at(spec: &str, theta_h_rad: f64, theta_d_rad: f64) -> f64 {
        let (model, name) = spec.split_once(':').unwrap();
        let brdf = load_fit(FitModel::from_prefix(model).unwrap(), name).unwrap();
        let hd = HalfDiff::new(theta_h_rad, 0.0, theta_d_rad, std::f64::consts::FRAC_PI_2);
        brdf.eval_half_diff(hd).unwrap().y
    }

    /// The check values of `merl_nbrdf/PROVENANCE.md` (green channel, phi_d = 90 degrees),
    /// to the digits printed there.
    #[test]
    fn provenance_check_values() {
        let (peak, off) = ((0.0, 0.2), (0.261799388, 0.5));
        // (fit, point, printed value, one unit of its last printed digit: the document
        // rounds 0.24549 to 0.246, i.e. it rounded twice)
        let cases = [
            ("sgd:chrome-steel", peak, 417.5, 0.1),
            ("abc:chrome-steel", peak, 200.4, 0.1),
            ("sgd:gold-metallic-paint", peak, 0.332, 1e-3),
            ("abc:gold-metallic-paint", peak, 0.246, 1e-3),
            ("sgd:gold-metallic-paint", off, 0.0707, 1e-4),
            ("abc:gold-metallic-paint", off, 0.0692, 1e-4),
            ("sgd:silver-metallic-paint", peak, 0.722, 1e-3),
            ("abc:silver-metallic-paint", peak, 0.505, 1e-3),
            ("sgd:blue-acrylic", peak, 20.45, 1e-2),
            ("abc:blue-acrylic", peak, 13.44, 1e-2),
            ("sgd:specular-black-phenolic", peak, 30.19, 1e-2),
            ("abc:specular-black-phenolic", peak, 25.2, 0.1),
            ("sgd:white-diffuse-bball", off, 0.102, 1e-3),
            ("abc:white-diffuse-bball", off, 0.092, 1e-3),
        ];
        for (spec, (theta_h, theta_d), expected, unit) in cases {
            let got = green_at(spec, theta_h, theta_d);
            assert!(
                (got - expected).abs() <= unit,
                "{spec}: {got} vs {expected}"
            );
        }
    }

    #[derive(serde::Deserialize)]
    struct Reference {
        model: String,
        material: String,
        theta_h_deg: f64,
        phi_h_deg: f64,
        theta_d_deg: f64,
        phi_d_deg: f64,
        r: f64,
        g: f64,
        b: f64,
    }

    /// Values computed by `tools/merl_fits_reference.py`, an independent numpy evaluation of
    /// the PROVENANCE.md formulas, for every material of both tables.
    #[test]
    fn matches_the_python_reference() {
        let reference =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/merl_fits_reference.csv");
        let mut tables = std::collections::HashMap::new();
        for model in [FitModel::Sgd, FitModel::Abc] {
            let fits = load_model(model).unwrap();
            assert_eq!(fits.len(), 100);
            for f in fits {
                tables.insert(f.name(), f);
            }
        }
        let mut reader = csv::Reader::from_path(reference).unwrap();
        let mut rows = 0;
        for row in reader.deserialize::<Reference>() {
            let row = row.unwrap();
            let brdf = &tables[&format!("{}:{}", row.model, row.material)];
            let hd = HalfDiff::from_degrees(
                row.theta_h_deg,
                row.phi_h_deg,
                row.theta_d_deg,
                row.phi_d_deg,
            );
            let got = brdf.eval_half_diff(hd).unwrap();
            let want = Rgb::new(row.r, row.g, row.b);
            for c in 0..3 {
                // At theta_h = 0 the narrowest SGD lobes (alpha ~ 2e-5) turn the last-bit
                // rounding of h (theta_h ~ 1e-8) into a relative change of p tan^2 / alpha^2
                // ~ 3e-8; a formula error would be orders of magnitude larger.
                let tolerance = 1e-6 * want[c].abs() + 1e-12;
                assert!(
                    (got[c] - want[c]).abs() <= tolerance,
                    "{}:{} at {:?}: channel {c}: {} vs {}",
                    row.model,
                    row.material,
                    (row.theta_h_deg, row.theta_d_deg, row.phi_d_deg),
                    got[c],
                    want[c]
                );
            }
            rows += 1;
        }
        assert!(rows >= 1000, "{rows} reference rows");
    }

    #[test]
    fn bad_tables_name_the_file_and_row() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("fits.csv");
        std::fs::write(
            &path,
            "material,kD_r,kD_g,kD_b,A_r,A_g,A_b,B,C,ior\nx,0.1,0.1,0.1,1,1,1,10,nan,1.5\n",
        )
        .unwrap();
        let err = load_fits(&path).err().unwrap().to_string();
        assert!(
            err.contains("fits.csv") && err.contains("row 2") && err.contains('C'),
            "{err}"
        );
        std::fs::write(&path, "a,b\n1,2\n").unwrap();
        let err = load_fits(&path).err().unwrap().to_string();
        assert!(err.contains("not an SGD or ABC"), "{err}");
        let err = load_fit(FitModel::Sgd, "unobtainium")
            .err()
            .unwrap()
            .to_string();
        assert!(
            err.contains("sgd:unobtainium") && err.contains("100"),
            "{err}"
        );
    }
}
