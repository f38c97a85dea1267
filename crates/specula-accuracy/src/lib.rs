//! The accuracy harness: measure a known BRDF on a plan without noise, reconstruct, and
//! compare the reconstruction with the BRDF tabulated at the MERL bin centres
//! ([`specula_core::compare`]), over the cells whose light and camera are both within the
//! device's elevation limit and over all cells above the surface.
//!
//! The plan ([`PlanSettings`]: [`PlanSettings::paper`], the paper's 5.3, or
//! [`PlanSettings::recommended`], the front ends' default): theta_h placed by a sampling
//! function whose k is fitted to the material's probe (5.2, `specula_sampling`), or by the
//! least-error placement on the probe; a theta_d x phi_d grid at one phi_h
//! ([`GridSpec`]); the samples the device cannot take are left out
//! (`specula_acquisition::plan`). [`within_elevation`] is a simple stand-in for the device
//! (theta_v <= 75 deg, section 5.3) for tests and benchmarks.
//!
//! [`evaluate`] and [`evaluate_through`] reconstruct as `specula reconstruct` does: each
//! half of phi_d from its own samples when the samples measure both
//! (`specula_reconstruct::phi_d_halves`), folded otherwise.
//!
//! **Through the instrument** ([`Measurement::simulate_through`], [`evaluate_through`];
//! issue 14): the samples and the probe are what the device's captures give, the truth
//! integrated over its response ([`ThroughResponse`], as many nodes as the simulator); the
//! probe is deblurred before k is fitted and the method reconstructs through the response,
//! as `specula measure` does, without its noise.
//!
//! Over several materials, [`summary`] combines the figures by their median or mean, per
//! set of truths, the real measured ones first.

pub mod coverage;
mod evaluation;
pub mod merl_prior;
pub mod summary;

pub use evaluation::{
    run_evaluate, EvaluateError, EvaluateRequest, Evaluated, Evaluation, EvaluationTable, MerlFits,
    SetTruth, TruthSets,
};

use specula_acquisition::device::Device;
use specula_acquisition::plan::Plan;
use specula_acquisition::response::{InstrumentResponse, ThroughResponse};
use specula_acquisition::simulator::SIMULATOR_RESPONSE_NODES;
use specula_core::compare::{compare, ErrorFigures};
use specula_core::request::{parse_choice, ChoiceError};
use specula_core::sampling::{Family, InvalidK, SamplingFunction};
use specula_core::tabulate::tabulate;
use specula_core::{Brdf, GridSpec, HalfDiff, MerlBrdf, ProbePoint, ProbeSpec, Sample};
use specula_reconstruct::deblur_probe;
use specula_reconstruct::phi_d_halves::reconstruct_halves;
use specula_reconstruct::{Method, PriorBasis, ReconstructError, Reconstruction};
use specula_sampling::error::SamplingError;
use specula_sampling::{fit_k, place_theta_h, Probe};

/// A plan on a grid: every combination of the theta_h, theta_d and phi_d positions (degrees)
/// at one phi_h, theta_h outermost and phi_d innermost (the paper's nested loops, 5.3).
#[derive(Debug, Clone, PartialEq)]
pub struct GridPlan {
    /// The theta_h positions, deg, outermost loop.
    pub theta_h_deg: Vec<f64>,
    /// The theta_d positions, deg.
    pub theta_d_deg: Vec<f64>,
    /// The phi_d positions, deg, innermost loop.
    pub phi_d_deg: Vec<f64>,
    /// The half-vector azimuth phi_h shared by every configuration, deg.
    pub phi_h_deg: f64,
}

impl GridPlan {
    /// The grid `spec` at the given theta_h positions: its theta_d and phi_d positions
    /// ([`GridSpec::theta_d_deg`], [`GridSpec::phi_d_deg`]) at its phi_h (its theta_h count
    /// is the positions').
    pub fn on(theta_h_deg: Vec<f64>, spec: &GridSpec) -> Self {
        Self {
            theta_h_deg,
            theta_d_deg: spec.theta_d_deg(),
            phi_d_deg: spec.phi_d_deg(),
            phi_h_deg: spec.phi_h_deg,
        }
    }

    /// The paper's plan (5.3) around the given theta_h positions: theta_d 0, 3, ..., 87,
    /// phi_d 0, 15, ..., 90, phi_h 45 degrees.
    pub fn paper(theta_h_deg: Vec<f64>) -> Self {
        Self::on(theta_h_deg, &GridSpec::paper())
    }

    /// Every planned configuration, in the plan's order.
    pub fn configurations(&self) -> Vec<HalfDiff> {
        let mut out = Vec::with_capacity(self.len());
        for &th in &self.theta_h_deg {
            for &td in &self.theta_d_deg {
                for &pd in &self.phi_d_deg {
                    out.push(HalfDiff::from_degrees(th, self.phi_h_deg, td, pd));
                }
            }
        }
        out
    }

    /// Number of configurations: the product of the three position counts.
    pub fn len(&self) -> usize {
        self.theta_h_deg.len() * self.theta_d_deg.len() * self.phi_d_deg.len()
    }

    /// Whether the plan has no configuration (an axis without positions).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The stand-in reach (light and camera within an elevation) and the region people use.
pub use specula_core::geometry::{within_elevation, USED_ELEVATION_DEG};

/// How theta_h positions are placed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ThetaHPlacement {
    /// A sampling function (paper eq. 2-4) with a given k.
    Function(SamplingFunction),
    /// A sampling function of this family with k-hat fitted to the material's probe (5.2).
    FittedFunction(Family),
    /// The least-error placement on the material's probe (`specula_sampling::place_theta_h`).
    Probe,
}

/// How theta_h positions are placed, by the name the front ends give: `function` (a
/// sampling function, with a k given or k-hat fitted) or `probe`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlacementChoice {
    /// [`ThetaHPlacement::Function`] or [`ThetaHPlacement::FittedFunction`].
    Function,
    /// [`ThetaHPlacement::Probe`].
    Probe,
}

impl PlacementChoice {
    /// `function` or `probe`.
    pub fn name(self) -> &'static str {
        match self {
            PlacementChoice::Function => "function",
            PlacementChoice::Probe => "probe",
        }
    }

    /// The placement: with `function`, the `family` function with `k`, or with k-hat
    /// fitted to the material's probe when `k` is `None`; with `probe`, `k` is not used.
    pub fn placement(self, family: Family, k: Option<f64>) -> Result<ThetaHPlacement, InvalidK> {
        Ok(match (self, k) {
            (PlacementChoice::Function, Some(k)) => {
                ThetaHPlacement::Function(SamplingFunction::new(family, k)?)
            }
            (PlacementChoice::Function, None) => ThetaHPlacement::FittedFunction(family),
            (PlacementChoice::Probe, _) => ThetaHPlacement::Probe,
        })
    }
}

impl std::str::FromStr for PlacementChoice {
    type Err = ChoiceError;

    /// [`PlacementChoice::name`].
    fn from_str(text: &str) -> Result<Self, ChoiceError> {
        parse_choice(
            "placement",
            text,
            &[PlacementChoice::Function, PlacementChoice::Probe],
            &["function", "probe"],
            PlacementChoice::name,
        )
    }
}

impl std::fmt::Display for PlacementChoice {
    /// [`PlacementChoice::name`].
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A plan on a grid, decided per material (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanSettings {
    /// How the theta_h positions are chosen.
    pub placement: ThetaHPlacement,
    /// The grid: theta_h count, theta_d and phi_d positions, phi_h.
    pub grid: GridSpec,
}

impl PlanSettings {
    /// The paper's plan (5.3): 30 theta_h of the exponential function with k-hat, theta_d
    /// step 3 deg, phi_d step 15 deg, phi_h 45 deg.
    pub fn paper() -> Self {
        Self {
            placement: ThetaHPlacement::FittedFunction(Family::Exponential),
            grid: GridSpec::paper(),
        }
    }

    /// The recommended plan ([`GridSpec::recommended`]): 16 theta_h of the exponential
    /// function with k-hat, theta_d 3:1@60, phi_d every 30 deg over the half turn, phi_h 45.
    pub fn recommended() -> Self {
        Self {
            placement: ThetaHPlacement::FittedFunction(Family::Exponential),
            grid: GridSpec::recommended(),
        }
    }

    /// theta_h positions (degrees) for a material, with the k they come from (none for the
    /// probe placement).
    pub fn theta_h_deg(&self, truth: &dyn Brdf) -> Result<(Vec<f64>, Option<f64>), SamplingError> {
        self.theta_h_deg_of_probe(|| Probe::take(truth, &ProbeSpec::paper()))
    }

    /// [`Self::theta_h_deg`] with the probe `take` gives, taken only when the placement
    /// needs one.
    fn theta_h_deg_of_probe(
        &self,
        take: impl FnOnce() -> Result<Probe, SamplingError>,
    ) -> Result<(Vec<f64>, Option<f64>), SamplingError> {
        let n = self.grid.theta_h_samples;
        if let ThetaHPlacement::Function(f) = self.placement {
            return Ok((f.positions_deg(n), Some(f.k)));
        }
        let probe = take()?;
        match self.placement {
            ThetaHPlacement::FittedFunction(family) => {
                let fit = fit_k(&probe.column(), family, n)?;
                Ok((fit.function.positions_deg(n), Some(fit.function.k)))
            }
            _ => Ok((place_theta_h(&probe, n), None)),
        }
    }

    /// The grid for a material.
    pub fn grid(&self, truth: &dyn Brdf) -> Result<(GridPlan, Option<f64>), SamplingError> {
        let (theta_h, k) = self.theta_h_deg(truth)?;
        Ok((GridPlan::on(theta_h, &self.grid), k))
    }
}

/// The points of `probe` (taken on `column`) that the device reaches, as `measure`'s probe
/// has them: the lobe fitted through the response to the blurred probe must not see the
/// grazing captures beyond the device's reach, whose disk dips below the horizon (with them
/// a noise-free green-paint probe fitted a lobe a third as wide as the truth's, and k-hat
/// went to the end of its range).
fn reachable_points(probe: &Probe, column: &ProbeSpec, device: &Device) -> Vec<ProbePoint> {
    let hds: Vec<HalfDiff> = probe
        .points()
        .iter()
        .map(|p| column.half_diff(p.theta_h_deg))
        .collect();
    let points = probe.points();
    let mut reached: Vec<usize> = Plan::from_half_diffs(&hds, device)
        .measured()
        .map(|(s, _)| s.index)
        .collect();
    reached.sort_unstable();
    reached.into_iter().map(|i| points[i]).collect()
}

/// The configurations of a grid that the device takes (status ok), in plan order.
pub fn reached_by(grid: &GridPlan, device: &Device) -> Vec<HalfDiff> {
    Plan::from_grid(
        &grid.theta_h_deg,
        &grid.theta_d_deg,
        &grid.phi_d_deg,
        grid.phi_h_deg,
        device,
    )
    .samples
    .iter()
    .filter(|s| s.status.is_ok())
    .map(|s| s.hd)
    .collect()
}

/// Why a material's measurement could not be planned: its theta_h could not be placed.
#[derive(Debug, thiserror::Error)]
#[error("{material}: placing theta_h: {cause}")]
pub struct PlacementError {
    /// The material's name.
    pub material: String,
    /// The cause.
    pub cause: SamplingError,
}

impl PlacementError {
    /// The error of placing theta_h for `truth`.
    fn of(truth: &dyn Brdf) -> impl FnOnce(SamplingError) -> Self {
        let material = truth.name();
        move |cause| PlacementError { material, cause }
    }
}

/// A material measured on its plan, without noise.
#[derive(Debug, Clone)]
pub struct Measurement {
    /// The plan the material was measured on.
    pub grid: GridPlan,
    /// k of the sampling function, when one placed theta_h.
    pub k: Option<f64>,
    /// The measured values, one per configuration of the plan.
    pub samples: Vec<Sample>,
}

impl Measurement {
    /// Plans the material's measurement and takes the reachable samples from the truth.
    pub fn simulate(
        truth: &dyn Brdf,
        settings: &PlanSettings,
        device: &Device,
    ) -> Result<Self, PlacementError> {
        let (grid, k) = settings.grid(truth).map_err(PlacementError::of(truth))?;
        let samples = measure(truth, &reached_by(&grid, device));
        Ok(Self { grid, k, samples })
    }
}

impl Measurement {
    /// [`Self::simulate`] through the instrument's `response` (see the module
    /// documentation): the probe and the samples are the truth as captures integrate it, and
    /// the probe is deblurred ([`deblur_probe`]) before theta_h is placed on it. `None`: as
    /// [`Self::simulate`].
    pub fn simulate_through(
        truth: &dyn Brdf,
        settings: &PlanSettings,
        device: &Device,
        response: Option<&InstrumentResponse>,
    ) -> Result<Self, PlacementError> {
        let Some(response) = response else {
            return Self::simulate(truth, settings, device);
        };
        let measured = ThroughResponse {
            truth,
            nodes: response.capture_nodes(SIMULATOR_RESPONSE_NODES),
        };
        let column = ProbeSpec::paper();
        let deblurred = Probe::take(&measured, &column)
            .map(|blurred| {
                deblur_probe(
                    &reachable_points(&blurred, &column, device),
                    &column,
                    response,
                )
            })
            .map_err(PlacementError::of(truth))?;
        let (theta_h, values) = deblurred
            .points
            .iter()
            .map(|p| (p.theta_h_deg, p.value))
            .unzip();
        let probe = Probe::new(theta_h, values)
            .map_err(SamplingError::from)
            .map_err(PlacementError::of(truth))?;
        // The grid `measure` would take (`GridSpec::for_material`).
        let on = |grid: &GridSpec| {
            let settings = PlanSettings {
                grid: *grid,
                ..*settings
            };
            let (theta_h, k) = settings.theta_h_deg_of_probe(|| Ok(probe.clone()))?;
            Ok::<_, SamplingError>((GridPlan::on(theta_h, grid), k))
        };
        let unresolved = deblurred.peak_unresolved(response.resolution_deg());
        let (grid, k) = settings
            .grid
            .for_material(
                unresolved,
                |grid| Ok(reached_by(&on(grid)?.0, device).len()),
            )
            .and_then(|grid| on(&grid))
            .map_err(PlacementError::of(truth))?;
        let samples = measure(&measured, &reached_by(&grid, device));
        Ok(Self { grid, k, samples })
    }
}

impl Measurement {
    /// The error of rebuilding these samples with `method` (and its `prior` basis, see
    /// [`merl_prior::basis_for`]), through `response` when they were measured through it
    /// ([`evaluate_through`]), against `truth` tabulated at the MERL bin centres at the
    /// plan's phi_h.
    pub fn accuracy(
        &self,
        truth: &dyn Brdf,
        method: Method,
        max_elevation_deg: f64,
        response: Option<&InstrumentResponse>,
        prior: Option<&PriorBasis>,
    ) -> Result<Accuracy, ReconstructError> {
        let table = tabulate(truth, self.grid.phi_h_deg.to_radians());
        let (_, accuracy) = evaluate_through(
            &self.samples,
            method,
            &table,
            max_elevation_deg,
            response,
            prior,
        )?;
        Ok(accuracy)
    }
}

/// Noise-free measurement of `truth` at each configuration; configurations the BRDF does not
/// answer are left out.
pub fn measure(truth: &dyn Brdf, configurations: &[HalfDiff]) -> Vec<Sample> {
    configurations
        .iter()
        .filter_map(|&hd| truth.eval_half_diff(hd).map(|v| Sample::new(hd, v)))
        .collect()
}

/// Error figures of a reconstruction against the truth, near the normal and everywhere.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Accuracy {
    /// Cells with light and camera within the elevation limit.
    pub within: ErrorFigures,
    /// All cells above the surface.
    pub all: ErrorFigures,
}

impl Accuracy {
    /// Compares `reconstructed` with the tabulated truth.
    pub fn of(reconstructed: &MerlBrdf, truth: &MerlBrdf, max_elevation_deg: f64) -> Self {
        Self {
            within: compare(reconstructed, truth, max_elevation_deg),
            all: compare(reconstructed, truth, 90.0),
        }
    }
}

/// Reconstructs the samples with a method (by halves of phi_d when they measure both,
/// [`reconstruct_halves`]; `prior`: the basis of the `prior` method, see
/// [`merl_prior::basis_for`]) and compares with the tabulated truth.
pub fn evaluate(
    samples: &[Sample],
    method: Method,
    truth: &MerlBrdf,
    max_elevation_deg: f64,
    prior: Option<&PriorBasis>,
) -> Result<(Reconstruction, Accuracy), ReconstructError> {
    evaluate_through(samples, method, truth, max_elevation_deg, None, prior)
}

/// [`evaluate`] for samples measured through the instrument's `response`: the method
/// reconstructs through it ([`reconstruct_halves`], as `specula_reconstruct::
/// reconstruct_through` for each half). `None`: as [`evaluate`].
pub fn evaluate_through(
    samples: &[Sample],
    method: Method,
    truth: &MerlBrdf,
    max_elevation_deg: f64,
    response: Option<&InstrumentResponse>,
    prior: Option<&PriorBasis>,
) -> Result<(Reconstruction, Accuracy), ReconstructError> {
    let reconstruction = reconstruct_halves(samples, method, "reconstruction", response, prior)?;
    let accuracy = Accuracy::of(&reconstruction.brdf, truth, max_elevation_deg);
    Ok((reconstruction, accuracy))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_placement_is_chosen_by_name() {
        let exponential = Family::Exponential;
        let function: PlacementChoice = "function".parse().unwrap();
        assert_eq!(
            function.placement(exponential, None),
            Ok(ThetaHPlacement::FittedFunction(exponential))
        );
        assert_eq!(
            function.placement(exponential, Some(4.78)),
            Ok(ThetaHPlacement::Function(
                SamplingFunction::new(exponential, 4.78).unwrap()
            ))
        );
        let probe: PlacementChoice = "probe".parse().unwrap();
        assert_eq!(
            probe.placement(exponential, Some(4.78)),
            Ok(ThetaHPlacement::Probe)
        );
        assert_eq!(probe.to_string(), "probe");
        assert_eq!(
            "grid".parse::<PlacementChoice>().unwrap_err().to_string(),
            "placement 'grid': expected one of function, probe"
        );
    }
    use specula_core::grid::UnresolvedPeak;
    use specula_core::materials::preset;
    use specula_core::sampling::{Family, SamplingFunction};
    use specula_core::tabulate::tabulate;
    use specula_core::ThetaDSteps;

    #[test]
    fn the_paper_plan_has_6300_configurations() {
        let theta_h = SamplingFunction::new(Family::Exponential, 4.78)
            .unwrap()
            .positions_deg(30);
        let plan = GridPlan::paper(theta_h);
        assert_eq!(
            (plan.theta_d_deg.len(), plan.phi_d_deg.len(), plan.len()),
            (30, 7, 6300)
        );
        assert_eq!(plan.theta_d_deg[29], 87.0);
        assert_eq!(plan.phi_d_deg[6], 90.0);
        let reached = plan
            .configurations()
            .into_iter()
            .filter(|&hd| within_elevation(hd, 75.0))
            .count();
        // The 75 degree limit alone; the UTIA arms' occlusion takes the paper's count to 4073.
        assert_eq!(reached, 4316);
    }

    #[test]
    fn through_the_instrument_the_samples_are_blurred_and_the_lobe_deblurs_them() {
        // chrome (GGX alpha 0.01) on a small plan: measured through the UTIA response its
        // peak sample is well below the truth's; reconstructed through the response the
        // error is far below the same samples reconstructed as if they were sharp.
        let truth = preset("chrome").unwrap();
        let device = Device::utia();
        let response = device.response();
        let settings = PlanSettings {
            placement: ThetaHPlacement::Function(
                SamplingFunction::new(Family::Exponential, 6.0).unwrap(),
            ),
            grid: GridSpec {
                theta_h_samples: 12,
                theta_d: ThetaDSteps::even(15.0),
                phi_d_step_deg: 45.0,
                ..GridSpec::paper()
            },
        };
        let sharp = Measurement::simulate(&truth, &settings, &device).unwrap();
        let blurred =
            Measurement::simulate_through(&truth, &settings, &device, Some(&response)).unwrap();
        assert_eq!(sharp.samples.len(), blurred.samples.len());
        assert_eq!(sharp.samples[0].hd, blurred.samples[0].hd);
        assert!(blurred.samples[0].value.y < 0.5 * sharp.samples[0].value.y);
        let table = tabulate(&truth, 45f64.to_radians());
        let (_, kept) = evaluate(&blurred.samples, Method::Lobe, &table, 75.0, None).unwrap();
        let (_, deblurred) = evaluate_through(
            &blurred.samples,
            Method::Lobe,
            &table,
            75.0,
            Some(&response),
            None,
        )
        .unwrap();
        assert!(
            deblurred.within.relative_rmse < 0.3 * kept.within.relative_rmse,
            "{deblurred:?} vs {kept:?}"
        );
        assert_eq!(
            blurred
                .accuracy(&truth, Method::Lobe, 75.0, Some(&response), None)
                .unwrap(),
            deblurred
        );
    }

    #[test]
    fn through_the_instrument_a_hidden_peak_gets_the_grid_measure_would_take() {
        // chrome (GGX alpha 0.01, half width 0.5 deg) is narrower than the UTIA resolution
        // (1.09 deg): its plan takes the rule's theta_h and theta_d within the budget, as
        // `measure` does; a small stand-in rule keeps the test quick. Without the response
        // the grid is the one given.
        let truth = preset("chrome").unwrap();
        let device = Device::utia();
        let response = device.response();
        let rule = UnresolvedPeak {
            theta_h_samples: 8,
            theta_d: ThetaDSteps::even(10.0),
            budget_samples: 400,
        };
        let settings = PlanSettings {
            placement: ThetaHPlacement::FittedFunction(Family::Exponential),
            grid: GridSpec {
                theta_h_samples: 4,
                theta_d: ThetaDSteps::even(15.0),
                phi_d_step_deg: 45.0,
                unresolved_peak: Some(rule),
                ..GridSpec::paper()
            },
        };
        let through =
            Measurement::simulate_through(&truth, &settings, &device, Some(&response)).unwrap();
        let theta_h = through.grid.theta_h_deg.len();
        assert!((5..=8).contains(&theta_h), "{theta_h} theta_h");
        assert_eq!(through.grid.theta_d_deg.len(), 9);
        assert!(through.samples.len() <= 400, "{}", through.samples.len());
        let sharp = Measurement::simulate(&truth, &settings, &device).unwrap();
        assert_eq!(sharp.grid.theta_h_deg.len(), 4);
    }

    #[test]
    fn the_probe_through_the_instrument_is_what_the_device_reaches() {
        // green-paint's clear coat is GGX alpha 0.008: the lobe fitted through the UTIA
        // response to the probe the device reaches finds it (within 5 %); with the 11 grazing
        // captures beyond the reach it took alpha 0.003 (gamma 1.74), and k-hat went to the
        // end of its range.
        let truth = preset("green-paint").unwrap();
        let device = Device::utia();
        let response = device.response();
        let measured = ThroughResponse {
            truth: &truth,
            nodes: response.capture_nodes(SIMULATOR_RESPONSE_NODES),
        };
        let column = ProbeSpec::paper();
        let probe = Probe::take(&measured, &column).unwrap();
        let reached = reachable_points(&probe, &column, &device);
        assert!(reached.len() < probe.points().len());
        assert!(reached
            .windows(2)
            .all(|w| w[0].theta_h_deg < w[1].theta_h_deg));
        let shape = deblur_probe(&reached, &column, &response)
            .lobe
            .unwrap()
            .shape;
        assert!((shape.alpha / 0.008 - 1.0).abs() < 0.05, "{shape:?}");
        assert!((shape.gamma - 2.0).abs() < 0.1, "{shape:?}");
    }

    #[test]
    fn a_dense_plan_reconstructs_a_smooth_material_closely() {
        let truth = preset("silver-925").unwrap();
        let theta_h = SamplingFunction::new(Family::Exponential, 5.0)
            .unwrap()
            .positions_deg(30);
        let plan = GridPlan::paper(theta_h);
        let reached: Vec<HalfDiff> = plan
            .configurations()
            .into_iter()
            .filter(|&hd| within_elevation(hd, 75.0))
            .collect();
        let samples = measure(&truth, &reached);
        assert_eq!(samples.len(), reached.len());
        let table = tabulate(&truth, 0.0);
        let (_, linear) = evaluate(&samples, Method::Linear, &table, 75.0, None).unwrap();
        let (_, lobe) = evaluate(&samples, Method::Lobe, &table, 75.0, None).unwrap();
        assert!(linear.within.relative_rmse < 0.5, "{linear:?}");
        // The lobe method is the better one on a microfacet material.
        assert!(
            lobe.within.relative_rmse < linear.within.relative_rmse,
            "{lobe:?} vs {linear:?}"
        );
        assert!(lobe.within.log_rmse < linear.within.log_rmse);
    }
}
