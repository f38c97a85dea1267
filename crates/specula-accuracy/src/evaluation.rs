//! What a user asks of the accuracy harness (`specula evaluate`, the Python package's
//! `evaluate`): the truths, the plan, the method and the region of the figures, every range
//! checked in one place ([`EvaluateRequest::validate`], errors naming the Python argument),
//! one entry point ([`run_evaluate`], stoppable between truths) and the table both print
//! ([`EvaluationTable`]).

use crate::merl_prior::{basis_for, MerlPriorError};
use crate::summary::{SetSummary, REAL_SET};
use crate::{Accuracy, Measurement, PlacementChoice, PlacementError, PlanSettings};
use specula_acquisition::device::Device;
use specula_core::compare::ErrorFigures;
use specula_core::materials::builtin_database;
use specula_core::progress::{is_raised, Progress, Stopped};
use specula_core::request::{
    parse_choice, sampling_function, ChoiceError, GridRequest, RequestError, ELEVATION_DEG,
};
use specula_core::sampling::Family;
use specula_core::statistics::Statistic;
use specula_core::{Brdf, GridSpec, Sample};
use specula_formats::fits::{load_model, FitModel};
use specula_formats::nbrdf::NbrdfSet;
use specula_reconstruct::{Method, PriorBasis, ReconstructError};
use std::error::Error;
use std::fmt;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// Why an evaluation is refused or fails.
#[derive(Debug, thiserror::Error)]
pub enum EvaluateError {
    /// A value outside its range, k outside its family's domain, or a grid too large.
    #[error(transparent)]
    Request(#[from] RequestError),
    /// A truth could not be loaded.
    #[error(transparent)]
    Load(Box<dyn Error + Send + Sync>),
    /// The plan could not be placed on a truth.
    #[error(transparent)]
    Placement(#[from] PlacementError),
    /// The `prior` method's basis could not be derived.
    #[error(transparent)]
    Prior(#[from] MerlPriorError),
    /// The evaluation was stopped before it finished.
    #[error(transparent)]
    Stopped(#[from] Stopped),
    /// The reconstruction of a truth's samples failed.
    #[error("{name}: reconstructing {measured} samples")]
    Reconstruct {
        /// The truth's name.
        name: String,
        /// Its measured samples.
        measured: usize,
        /// The cause.
        #[source]
        source: ReconstructError,
    },
}

/// The 100 MERL materials as fitted by a published model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MerlFits {
    /// The sgd fits.
    Sgd,
    /// The abc fits.
    Abc,
    /// The neural nbrdf fits.
    Nbrdf,
}

impl MerlFits {
    const ALL: [MerlFits; 3] = [MerlFits::Sgd, MerlFits::Abc, MerlFits::Nbrdf];
    const NAMES: &'static [&'static str] = &["sgd", "abc", "nbrdf"];

    /// `sgd`, `abc` or `nbrdf`.
    pub fn name(self) -> &'static str {
        match self {
            MerlFits::Sgd => "sgd",
            MerlFits::Abc => "abc",
            MerlFits::Nbrdf => "nbrdf",
        }
    }

    /// The 100 fitted materials.
    pub fn load(self) -> Result<Vec<Arc<dyn Brdf>>, EvaluateError> {
        let loaded = match self {
            MerlFits::Sgd => load_model(FitModel::Sgd).map_err(Box::from),
            MerlFits::Abc => load_model(FitModel::Abc).map_err(Box::from),
            MerlFits::Nbrdf => NbrdfSet::Merl100.load_all().map_err(Box::from),
        };
        loaded.map_err(EvaluateError::Load)
    }
}

impl std::str::FromStr for MerlFits {
    type Err = ChoiceError;

    /// [`MerlFits::name`].
    fn from_str(text: &str) -> Result<Self, ChoiceError> {
        parse_choice("merl fits", text, &Self::ALL, Self::NAMES, MerlFits::name)
    }
}

impl fmt::Display for MerlFits {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A truth with the name of the set it belongs to.
pub type SetTruth = (String, Arc<dyn Brdf>);

/// The truths to evaluate, each with the set it belongs to: `real` for measured files and
/// folders among `sources`, `given` for other sources, `builtin`, `merl-sgd`, ...
#[derive(Debug, Clone, Default)]
pub struct TruthSets {
    /// Sources as `specula_formats::load_brdfs` reads them (a folder gives every file).
    pub sources: Vec<String>,
    /// Every material of the built-in database.
    pub builtin: bool,
    /// The MERL fit sets.
    pub merl_fits: Vec<MerlFits>,
}

impl TruthSets {
    /// Every truth with its set's name, in the order given.
    pub fn load(&self) -> Result<Vec<SetTruth>, EvaluateError> {
        let mut truths = Vec::new();
        for spec in &self.sources {
            let set = if Path::new(spec).exists() && !spec.ends_with(".toml") {
                REAL_SET
            } else {
                "given"
            };
            let loaded =
                specula_formats::load_brdfs(spec).map_err(|e| EvaluateError::Load(e.into()))?;
            truths.extend(loaded.into_iter().map(|truth| (set.to_string(), truth)));
        }
        if self.builtin {
            truths.extend(
                builtin_database()
                    .into_iter()
                    .map(|m| ("builtin".to_string(), Arc::new(m) as Arc<dyn Brdf>)),
            );
        }
        for fits in &self.merl_fits {
            let set = format!("merl-{fits}");
            truths.extend(fits.load()?.into_iter().map(|t| (set.clone(), t)));
        }
        Ok(truths)
    }
}

/// How each truth is measured, reconstructed and compared.
#[derive(Debug, Clone, Copy)]
pub struct EvaluateRequest {
    /// The reconstruction method.
    pub method: Method,
    /// k of the sampling function ([`sampling_function`]); `None`:
    /// k-hat of each truth's probe.
    pub k: Option<f64>,
    /// theta_h placement.
    pub placement: PlacementChoice,
    /// The sampling function's family.
    pub family: Family,
    /// The grid.
    pub grid: GridRequest,
    /// Largest elevation of the "within" figures, in [`ELEVATION_DEG`].
    pub max_elevation_deg: f64,
    /// Measure and reconstruct through the instrument's response, as `measure` does.
    pub through_instrument: bool,
}

/// One evaluated truth.
#[derive(Debug, Clone)]
pub struct Evaluated {
    /// The truth's name.
    pub name: String,
    /// k of the plan (`None` for the probe placement).
    pub k: Option<f64>,
    /// The simulated samples.
    pub samples: Vec<Sample>,
    /// The error figures.
    pub accuracy: Accuracy,
}

impl EvaluateRequest {
    /// Checks every value against its range (the grid's with [`GridRequest::validate`]).
    pub fn validate(&self) -> Result<(), EvaluateError> {
        self.grid.validate()?;
        ELEVATION_DEG
            .check("max_elevation_deg", self.max_elevation_deg)
            .map_err(RequestError::from)?;
        if let Some(k) = self.k {
            sampling_function(self.family, k)?;
        }
        Ok(())
    }

    /// The plan settings on the grid asked for, validated.
    pub fn plan_settings(&self) -> Result<PlanSettings, EvaluateError> {
        self.validate()?;
        Ok(PlanSettings {
            placement: (self.placement.placement(self.family, self.k))
                .map_err(RequestError::from)?,
            grid: self.grid.grid(None)?,
        })
    }
}

/// The evaluated truths, each with its set, and the plan they were measured on.
#[derive(Debug, Clone)]
pub struct Evaluation {
    /// The plan settings on the grid asked for.
    pub settings: PlanSettings,
    /// Each truth's set and evaluation, in the order given.
    pub rows: Vec<(String, Evaluated)>,
}

impl Evaluation {
    /// The table `specula evaluate` prints of it.
    pub fn table<'a>(&'a self, request: &'a EvaluateRequest) -> EvaluationTable<'a> {
        EvaluationTable {
            request,
            grid: &self.settings.grid,
            rows: &self.rows,
        }
    }
}

/// Evaluates each of `truths` as `request` asks: measured on its plan without noise (through
/// `device`'s response when the request says so), reconstructed and compared with the truth.
/// `progress` counts the truths; a raised `stop` ends the evaluation before the next truth or
/// the next reconstruction with [`Stopped`].
pub fn run_evaluate(
    request: &EvaluateRequest,
    truths: &[SetTruth],
    device: &Device,
    stop: &AtomicBool,
    progress: &dyn Progress,
) -> Result<Evaluation, EvaluateError> {
    let settings = request.plan_settings()?;
    let prior = basis_for(request.method)?;
    let mut rows = Vec::with_capacity(truths.len());
    progress.start("evaluating", Some(truths.len() as u64));
    for (set, truth) in truths {
        let stopped = || Stopped {
            done: rows.len() as u64,
            total: truths.len() as u64,
            what: "materials",
        };
        let evaluated = evaluate_truth(
            request,
            &settings,
            truth.as_ref(),
            device,
            prior.as_deref(),
            stop,
        )?
        .ok_or_else(stopped);
        match evaluated {
            Ok(evaluated) => rows.push((set.clone(), evaluated)),
            Err(stopped) => {
                progress.finish();
                return Err(stopped.into());
            }
        }
        progress.set(rows.len() as u64);
    }
    progress.finish();
    Ok(Evaluation { settings, rows })
}

/// Measures `truth` on `settings`, reconstructs it and compares it with the truth, unless
/// `stop` rises before the reconstruction (`None`).
fn evaluate_truth(
    request: &EvaluateRequest,
    settings: &PlanSettings,
    truth: &dyn Brdf,
    device: &Device,
    prior: Option<&PriorBasis>,
    stop: &AtomicBool,
) -> Result<Option<Evaluated>, EvaluateError> {
    if is_raised(stop) {
        return Ok(None);
    }
    let name = truth.name();
    let response = request.through_instrument.then(|| device.response());
    let measurement = Measurement::simulate_through(truth, settings, device, response.as_ref())?;
    if is_raised(stop) {
        return Ok(None);
    }
    let accuracy = measurement
        .accuracy(
            truth,
            request.method,
            request.max_elevation_deg,
            response.as_ref(),
            prior,
        )
        .map_err(|source| EvaluateError::Reconstruct {
            name: name.clone(),
            measured: measurement.samples.len(),
            source,
        })?;
    Ok(Some(Evaluated {
        name,
        k: measurement.k,
        samples: measurement.samples,
        accuracy,
    }))
}

/// The table of `specula evaluate`: a header naming the method, the grid and the region, one
/// CSV row per truth, their mean when there are several, and per set the median and the
/// mean (lines starting `# `, real measured truths first).
pub struct EvaluationTable<'a> {
    /// The request evaluated.
    pub request: &'a EvaluateRequest,
    /// Its grid.
    pub grid: &'a GridSpec,
    /// Each truth's set and evaluation.
    pub rows: &'a [(String, Evaluated)],
}

/// The figure columns after the leading ones.
const FIGURE_COLUMNS: &str =
    "rel_rmse_within,log_rmse_within,slice_mae_within,rel_rmse_all,log_rmse_all,slice_mae_all";

/// `within` and `all`'s figures as CSV fields.
fn figure_fields(a: &Accuracy) -> String {
    let fields = |f: &ErrorFigures| {
        format!(
            "{:.5},{:.5},{:.4e}",
            f.relative_rmse, f.log_rmse, f.slice_mae
        )
    };
    format!("{},{}", fields(&a.within), fields(&a.all))
}

impl fmt::Display for EvaluationTable<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = self.request;
        let placement = match r.placement {
            PlacementChoice::Function => format!("the {} function", r.family),
            PlacementChoice::Probe => "probe placement".to_string(),
        };
        let through = if r.through_instrument {
            " through the instrument's response"
        } else {
            ""
        };
        writeln!(
            f,
            "# method {}{through}, grid {} (theta_h by {placement}); within = light and camera <= {} deg",
            r.method, self.grid, r.max_elevation_deg
        )?;
        writeln!(f, "material,k,measured,{FIGURE_COLUMNS}")?;
        for (_, row) in self.rows {
            let k = row.k.map_or(String::new(), |k| format!("{k:.3}"));
            let measured = row.samples.len();
            writeln!(
                f,
                "{},{k},{measured},{}",
                row.name,
                figure_fields(&row.accuracy)
            )?;
        }
        if self.rows.len() < 2 {
            return Ok(());
        }
        let accuracies: Vec<Accuracy> = self.rows.iter().map(|(_, r)| r.accuracy).collect();
        let accuracy = Accuracy::combined(&accuracies, Statistic::Mean);
        let mut measured: Vec<f64> = self
            .rows
            .iter()
            .map(|(_, r)| r.samples.len() as f64)
            .collect();
        let measured = Statistic::Mean.of(&mut measured);
        let n = self.rows.len();
        writeln!(f, "mean of {n},,{measured:.0},{}", figure_fields(&accuracy))?;
        writeln!(f, "# per set: set,statistic,materials,{FIGURE_COLUMNS}")?;
        let sets = self.rows.iter().map(|(set, r)| (set.as_str(), r.accuracy));
        for summary in SetSummary::of(sets) {
            writeln!(
                f,
                "# {},{},{},{}",
                summary.set,
                summary.statistic.name(),
                summary.materials,
                figure_fields(&summary.accuracy)
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::materials::preset;
    use specula_core::progress::NoProgress;

    fn request() -> EvaluateRequest {
        EvaluateRequest {
            method: "lobe".parse().unwrap(),
            k: None,
            placement: PlacementChoice::Function,
            family: Family::Exponential,
            grid: GridRequest::default(),
            max_elevation_deg: 75.0,
            through_instrument: false,
        }
    }

    #[test]
    fn out_of_range_values_are_named_as_the_python_arguments() {
        let refused = |r: EvaluateRequest| r.validate().unwrap_err().to_string();
        let high = EvaluateRequest {
            max_elevation_deg: 95.0,
            ..request()
        };
        assert_eq!(
            refused(high),
            "max_elevation_deg 95: expected degrees above 0 and at most 90"
        );
        let k = EvaluateRequest {
            k: Some(0.0),
            ..request()
        };
        assert_eq!(refused(k), "k 0: expected a number above 0 and at most 100");
        assert_eq!(
            "fine".parse::<MerlFits>().unwrap_err().to_string(),
            "merl fits 'fine': expected one of sgd, abc, nbrdf"
        );
    }

    #[test]
    fn a_table_has_a_row_per_truth_their_mean_and_the_sets() {
        let request = EvaluateRequest {
            grid: GridRequest {
                preset: Some(specula_core::request::GridPreset::Paper),
                ..GridRequest::default()
            },
            ..request()
        };
        let device = Device::utia();
        let truths: Vec<SetTruth> = ["green-paint", "chrome"]
            .iter()
            .map(|name| {
                let truth: Arc<dyn Brdf> = Arc::new(preset(name).unwrap());
                ("given".to_string(), truth)
            })
            .collect();
        let evaluation = run_evaluate(
            &request,
            &truths,
            &device,
            &AtomicBool::new(false),
            &NoProgress,
        )
        .unwrap();
        assert!(evaluation
            .rows
            .iter()
            .all(|(_, r)| r.accuracy.within.relative_rmse < 1.0));
        let table = evaluation.table(&request).to_string();
        let stopped = run_evaluate(
            &request,
            &truths,
            &device,
            &AtomicBool::new(true),
            &NoProgress,
        )
        .unwrap_err()
        .to_string();
        assert_eq!(stopped, "stopped: 0 of 2 materials done");
        let lines: Vec<&str> = table.lines().collect();
        assert!(lines[0].starts_with("# method lobe, grid "), "{table}");
        assert!(lines[2].starts_with("green-paint,"), "{table}");
        assert!(lines[4].starts_with("mean of 2,,"), "{table}");
        assert!(lines[6].starts_with("# given,median,2,"), "{table}");
        assert_eq!(lines[2].split(',').count(), 9);
    }
}
