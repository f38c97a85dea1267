//! Fitting the analytic materials renderers have to any BRDF (issue 18, item 3): a GGX rough
//! conductor (Mitsuba 3's `roughconductor`, pbrt-v4's `conductor`) or a GGX rough dielectric
//! coat over a Lambertian base (Mitsuba 3's `roughplastic`, non-linear; pbrt-v4's
//! `coateddiffuse`), both evaluated by Specula's own models ([`RoughConductor`],
//! [`ClearCoat`]), so the fit shares their GGX and Fresnel with every other part of Specula.
//!
//! The data are the source tabulated into the MERL grid (its bin centres, docs/book/src/design.md). The fit
//! minimises the mean of `(ln(1 + f_fit cos theta_i) - ln(1 + f_src cos theta_i))^2` over the
//! three channels and a subset of the cells (every theta_h, every [`THETA_D_STRIDE`]-th
//! theta_d, every [`PHI_D_STRIDE`]-th phi_d) whose light and camera are within the chosen
//! elevation: the `log_rmse` of `specula compare`, which weighs the peak and the tail alike
//! (a linear error would fit the highlight and ignore the rest). Nelder-Mead (`argmin`) works
//! on unbounded coordinates (logarithms of alpha and `ior - 1`; logistics of the base albedo
//! and of the conductor's normal reflectance and edge tint per channel, mapped to `eta`, `k`
//! by [`conductor_index_from_reflectivity`], since `eta` and `k` themselves are nearly
//! degenerate) and is restarted from its own result until that stops improving, which guards
//! against the simplex collapsing early. The error reported is `specula compare`'s figures
//! of the fitted model tabulated against the source's table, over every cell.

use argmin::core::{CostFunction, Error as ArgminError, Executor};
use argmin::solver::neldermead::NelderMead;
use rayon::prelude::*;
use specula_core::compare::{compare, ErrorFigures};
use specula_core::materials::clearcoat::{ClearCoat, MAX_BASE_ALBEDO};
use specula_core::materials::conductor::RoughConductor;
use specula_core::materials::microfacet::IsotropicCosines;
use specula_core::materials::{Base, Distribution, Material};
use specula_core::merl::{Bin, MerlBrdf, PHI_D_BINS, THETA_D_BINS, THETA_H_BINS};
use specula_core::request::{parse_choice, ChoiceError};
use specula_core::scattering::fresnel::conductor_index_from_reflectivity;
use specula_core::tabulate::tabulate;
use specula_core::Rgb;

/// theta_d bins between fitted cells (every third degree).
pub const THETA_D_STRIDE: usize = 3;
/// phi_d bins between fitted cells (every sixth degree).
pub const PHI_D_STRIDE: usize = 6;
/// Roughness range of the fit (GGX alpha, dimensionless).
pub const ALPHA_RANGE: (f64, f64) = (1e-3, 1.0);
/// Coat index range of the fit (relative to air).
pub const IOR_RANGE: (f64, f64) = (1.1, 2.5);
/// The smallest extinction coefficient `k` of a metal-like conductor fit. Metals' `k` in the
/// visible is well above it (silver about 3.6, gold 2.5-3, aluminium 6-7, chromium 3.3,
/// titanium and iron about 3), dielectrics' is near 0.
pub const METAL_MIN_K: f64 = 1.0;
/// Cells per parallel part of the loss.
const LOSS_CHUNK: usize = 4096;
/// The conductor's largest normal-incidence reflectance (keeps eta and k finite).
const MAX_REFLECTIVITY: f64 = 0.9999;
/// Nelder-Mead iterations per start.
const MAX_ITERS: u64 = 4000;
/// Restarts stop when one improves the loss by less than this fraction.
const RESTART_GAIN: f64 = 1e-6;
/// At most this many restarts.
const MAX_RESTARTS: usize = 4;

/// The analytic model to fit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FitModel {
    /// A GGX rough conductor: alpha and a complex index `eta + i k` per channel.
    Conductor,
    /// A GGX rough dielectric coat (alpha, index) over a Lambertian base (albedo per channel).
    Coat,
}

impl FitModel {
    /// The name used on the command line and in reports.
    pub fn label(self) -> &'static str {
        match self {
            FitModel::Conductor => "conductor",
            FitModel::Coat => "coat",
        }
    }

    /// The starting point in fit coordinates (alpha 0.05; a metal of normal reflectance 0.73
    /// and edge tint 0.5; an acrylic coat over a mid-grey base).
    fn start(self) -> Vec<f64> {
        let alpha = 0.05f64.ln();
        match self {
            FitModel::Conductor => vec![alpha, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0],
            FitModel::Coat => vec![alpha, 0.49f64.ln(), 0.0, 0.0, 0.0],
        }
    }

    /// The material at fit coordinates `x` (see the module documentation).
    fn material(self, name: &str, x: &[f64]) -> Material {
        let alpha = x[0].exp().clamp(ALPHA_RANGE.0, ALPHA_RANGE.1);
        let base = match self {
            FitModel::Conductor => {
                let (mut eta, mut k) = (Rgb::ZERO, Rgb::ZERO);
                for c in 0..3 {
                    let r = MAX_REFLECTIVITY * logistic(x[1 + c]);
                    (eta[c], k[c]) = conductor_index_from_reflectivity(r, logistic(x[4 + c]));
                }
                Base::Conductor(RoughConductor::new(Distribution::Ggx, alpha, eta, k))
            }
            FitModel::Coat => {
                let ior = (1.0 + x[1].exp()).clamp(IOR_RANGE.0, IOR_RANGE.1);
                let albedo = |t: f64| MAX_BASE_ALBEDO * logistic(t);
                let rho = Rgb::new(albedo(x[2]), albedo(x[3]), albedo(x[4]));
                Base::ClearCoat(ClearCoat::new(Distribution::Ggx, alpha, ior, rho))
            }
        };
        Material::new(name, base)
    }
}

/// Which models a fit tries, by the name the front ends give: `conductor`, `coat` or `both`
/// (the better one is exported).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FitChoice {
    /// [`FitModel::Conductor`] alone.
    Conductor,
    /// [`FitModel::Coat`] alone.
    Coat,
    /// Both models.
    Both,
}

impl FitChoice {
    /// `conductor`, `coat` or `both`.
    pub fn name(self) -> &'static str {
        match self {
            FitChoice::Conductor => "conductor",
            FitChoice::Coat => "coat",
            FitChoice::Both => "both",
        }
    }

    /// The models fitted.
    pub fn models(self) -> &'static [FitModel] {
        match self {
            FitChoice::Conductor => &[FitModel::Conductor],
            FitChoice::Coat => &[FitModel::Coat],
            FitChoice::Both => &[FitModel::Conductor, FitModel::Coat],
        }
    }
}

impl std::str::FromStr for FitChoice {
    type Err = ChoiceError;

    /// [`FitChoice::name`].
    fn from_str(text: &str) -> Result<Self, ChoiceError> {
        parse_choice(
            "model",
            text,
            &[FitChoice::Conductor, FitChoice::Coat, FitChoice::Both],
            &["conductor", "coat", "both"],
            FitChoice::name,
        )
    }
}

impl std::fmt::Display for FitChoice {
    /// [`FitChoice::name`].
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The logistic function, onto (0, 1).
fn logistic(t: f64) -> f64 {
    1.0 / (1.0 + (-t).exp())
}

/// A fitted material and how well it matches its source.
#[derive(Debug, Clone)]
pub struct MaterialFit {
    /// The analytic model that was fitted.
    pub model: FitModel,
    /// The fitted material (GGX, no scratch lobe), named after the source.
    pub material: Material,
    /// `specula compare`'s figures of the fit against the source over every cell above the
    /// surface.
    pub error_all: ErrorFigures,
    /// The same within the fit's elevation limit.
    pub error_within: ErrorFigures,
    /// Cells the fit used.
    pub cells: usize,
}

impl MaterialFit {
    /// Whether the fitted material is a metal's: a coat never is; a conductor is when its
    /// extinction coefficient `k` reaches [`METAL_MIN_K`] in some channel. A conductor with
    /// `k` near 0 is a dielectric's Fresnel reflection (a glossy film or plastic with a dark
    /// base), which glTF's `metallicFactor` 1 and a renderer's conductor would render as a
    /// metal.
    pub fn is_metal_like(&self) -> bool {
        match &self.material.base {
            Base::Conductor(c) => c.k.max_element() >= METAL_MIN_K,
            Base::ClearCoat(_) => false,
        }
    }
}

/// Why a fit failed.
#[derive(Debug, thiserror::Error)]
pub enum FitError {
    /// The source has fewer measured cells (the count) within the elevation limit than the
    /// fit needs.
    #[error("the source has only {0} measured cells within the elevation limit; at least 100 are needed")]
    TooFewCells(usize),
    /// The optimiser stopped with an error (its message).
    #[error("the optimiser failed: {0}")]
    Optimiser(String),
}

/// One fitted cell: its cosines and the target `ln(1 + f cos theta_i)` per channel.
struct Cell {
    cosines: IsotropicCosines,
    target: Rgb,
}

/// The fit's loss (module documentation) at fit coordinates.
#[derive(Clone, Copy)]
struct Loss<'a> {
    model: FitModel,
    cells: &'a [Cell],
}

impl Loss<'_> {
    fn at(&self, x: &[f64]) -> f64 {
        let material = self.model.material("fit", x);
        let squared_error = |cell: &Cell| {
            let fitted = material.base.eval_cosines(cell.cosines) * cell.cosines.cos_i;
            (fitted.map(f64::ln_1p) - cell.target).length_squared()
        };
        // Fixed chunks summed in order: the same loss on every run, whatever the threads do.
        let partial: Vec<f64> = self
            .cells
            .par_chunks(LOSS_CHUNK)
            .map(|chunk| chunk.iter().map(squared_error).sum())
            .collect();
        partial.iter().sum::<f64>() / (3 * self.cells.len()) as f64
    }
}

impl CostFunction for Loss<'_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, x: &Vec<f64>) -> Result<f64, ArgminError> {
        Ok(self.at(x))
    }
}

/// The cells of `table` the fit uses (module documentation).
fn fit_cells(table: &MerlBrdf, max_elevation_deg: f64) -> Vec<Cell> {
    let min_cos = max_elevation_deg.to_radians().cos().max(1e-12);
    let mut cells = Vec::new();
    for theta_h_i in 0..THETA_H_BINS {
        for theta_d_i in (0..THETA_D_BINS).step_by(THETA_D_STRIDE) {
            for phi_d_i in (0..PHI_D_BINS).step_by(PHI_D_STRIDE) {
                let bin = Bin {
                    theta_h_i,
                    theta_d_i,
                    phi_d_i,
                };
                let Some(value) = table.cell(bin.index()) else {
                    continue;
                };
                let Some(cosines) = IsotropicCosines::from_half_diff(bin.centre(0.0)) else {
                    continue;
                };
                if cosines.cos_i < min_cos || cosines.cos_o < min_cos {
                    continue;
                }
                let target = (value.max(Rgb::ZERO) * cosines.cos_i).map(f64::ln_1p);
                cells.push(Cell { cosines, target });
            }
        }
    }
    cells
}

/// Nelder-Mead from `start`: the best coordinates and their loss.
fn minimise(loss: &Loss, start: &[f64]) -> Result<(Vec<f64>, f64), FitError> {
    let step = 0.5;
    let mut simplex = vec![start.to_vec()];
    for i in 0..start.len() {
        let mut vertex = start.to_vec();
        vertex[i] += step;
        simplex.push(vertex);
    }
    let solver = NelderMead::new(simplex)
        .with_sd_tolerance(1e-12)
        .map_err(|e| FitError::Optimiser(e.to_string()))?;
    let result = Executor::new(*loss, solver)
        .configure(|state| state.max_iters(MAX_ITERS))
        .run()
        .map_err(|e| FitError::Optimiser(e.to_string()))?;
    let best = result
        .state
        .best_param
        .ok_or_else(|| FitError::Optimiser("no parameters".into()))?;
    Ok((best, result.state.best_cost))
}

/// Fits `model` to the BRDF tabulated in `table` over the cells whose light and camera are
/// within `max_elevation_deg` of the normal; the fitted material is named after the source
/// and the model, `name (coat fit)` or `name (conductor fit)`, so that every export says
/// which model it holds.
pub fn fit_material(
    table: &MerlBrdf,
    model: FitModel,
    max_elevation_deg: f64,
    name: &str,
) -> Result<MaterialFit, FitError> {
    let cells = fit_cells(table, max_elevation_deg);
    if cells.len() < 100 {
        return Err(FitError::TooFewCells(cells.len()));
    }
    let loss = Loss {
        model,
        cells: &cells,
    };
    let (mut x, mut cost) = minimise(&loss, &model.start())?;
    for _ in 0..MAX_RESTARTS {
        let (next, next_cost) = minimise(&loss, &x)?;
        let gain = cost - next_cost;
        if next_cost < cost {
            x = next;
            cost = next_cost;
        }
        if gain <= RESTART_GAIN * cost {
            break;
        }
    }
    let material = model.material(&format!("{name} ({} fit)", model.label()), &x);
    let fitted = tabulate(&material, 0.0);
    Ok(MaterialFit {
        model,
        error_all: compare(&fitted, table, 90.0),
        error_within: compare(&fitted, table, max_elevation_deg),
        material,
        cells: cells.len(),
    })
}

/// Fits each of `models` to `table` (as [`fit_material`]) and returns the fits in the order
/// of export, the one to export first: from the lowest fit error (`log_rmse` within the
/// elevation limit, the figure the fit minimises) to the highest, except that a conductor
/// that is not metal-like ([`MaterialFit::is_metal_like`]) comes after the dielectric coat
/// when both were fitted ([`ExportReason`]).
pub fn fit_models(
    table: &MerlBrdf,
    models: &[FitModel],
    max_elevation_deg: f64,
    name: &str,
) -> Result<Vec<MaterialFit>, FitError> {
    let mut fits = models
        .iter()
        .map(|&model| fit_material(table, model, max_elevation_deg, name))
        .collect::<Result<Vec<_>, _>>()?;
    fits.sort_by(|a, b| a.error_within.log_rmse.total_cmp(&b.error_within.log_rmse));
    if let ExportReason::NotMetalLike { .. } = ExportReason::of(&fits) {
        fits.swap(0, 1);
    }
    Ok(fits)
}

/// Why the first of a list of fits is the one exported.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ExportReason {
    /// Only one model was fitted.
    OnlyModel,
    /// It has the lowest fit error of the models fitted.
    LowerError,
    /// The conductor had the lower fit error, but its extinction coefficient (the largest
    /// over the channels) is not a metal's, so the data are a dielectric's and the coat is
    /// exported.
    NotMetalLike {
        /// The conductor's largest `k`.
        k_max: f64,
    },
}

impl ExportReason {
    /// The reason for the first of `fits`, ordered by fit error (lowest first) or by
    /// [`fit_models`].
    pub fn of(fits: &[MaterialFit]) -> Self {
        let [first, second, ..] = fits else {
            return ExportReason::OnlyModel;
        };
        let conductor_k = |fit: &MaterialFit| match &fit.material.base {
            Base::Conductor(c) if !fit.is_metal_like() => Some(c.k.max_element()),
            _ => None,
        };
        match (conductor_k(first), conductor_k(second), second.model) {
            (Some(k_max), _, FitModel::Coat) => ExportReason::NotMetalLike { k_max },
            (None, Some(k_max), FitModel::Conductor)
                if first.error_within.log_rmse > second.error_within.log_rmse =>
            {
                ExportReason::NotMetalLike { k_max }
            }
            _ => ExportReason::LowerError,
        }
    }
}

impl std::fmt::Display for ExportReason {
    /// The reason in words, as `specula fit` prints it after "exported model: MODEL".
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ExportReason::OnlyModel => f.write_str("the only model fitted"),
            ExportReason::LowerError => f.write_str("the lower log_rmse of the models fitted"),
            ExportReason::NotMetalLike { k_max } => write!(
                f,
                "a dielectric: the conductor fitted better but its k (at most {k_max:.2}) is not a metal's (at least {METAL_MIN_K})"
            ),
        }
    }
}
