//! What a user asks of a plan (`specula plan`, the Python package's `plan`; paper 5.3): the
//! theta_h positions (a sampling function's or a list), the grid, the order and what the
//! captures are priced for, every range checked in one place ([`PlanRequest::validate`],
//! errors naming the Python argument), and one entry point ([`run_plan`]).

use crate::estimate::{price_before_probe, ASSUMED_MATERIAL};
use crate::workflow::{HdrChoice, PlanOrder};
use crate::workflow_error::WorkflowError;
use specula_acquisition::device::Device;
use specula_acquisition::ordering::order;
use specula_acquisition::plan::{Plan, PlanSummary};
use specula_core::materials::preset;
use specula_core::progress::{is_raised, Progress, Stopped};
use specula_core::request::{sampling_function, GridRequest, RequestError, THETA_H_DEG};
use specula_core::sampling::Family;
use specula_core::{Brdf, GridSpec};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// Why a plan is refused or fails.
#[derive(Debug, thiserror::Error)]
pub enum PlanError {
    /// A value outside its range, k outside its family's domain, or a grid too large.
    #[error(transparent)]
    Request(#[from] RequestError),
    /// Options that do not go together, or a value missing, in words.
    #[error("{0}")]
    Refused(&'static str),
    /// The captures could not be priced.
    #[error(transparent)]
    Workflow(#[from] WorkflowError),
    /// The plan was stopped before it was made.
    #[error(transparent)]
    Stopped(#[from] Stopped),
}

/// Where the theta_h positions come from.
#[derive(Debug, Clone, PartialEq)]
pub enum ThetaH {
    /// The sampling function of the request's family with this k ([`sampling_function`]),
    /// at the grid's count of positions.
    K(f64),
    /// These positions, degrees, each in [`THETA_H_DEG`].
    Positions(Vec<f64>),
}

/// A plan as a user asks for it.
#[derive(Clone)]
pub struct PlanRequest {
    /// The theta_h positions.
    pub theta_h: ThetaH,
    /// The sampling function's family.
    pub family: Family,
    /// The grid of theta_d and phi_d at one phi_h.
    pub grid: GridRequest,
    /// The order of the samples chosen.
    pub order: PlanOrder,
    /// How each capture is priced.
    pub hdr: HdrChoice,
    /// With predicted exposures, the material whose brightness they are predicted for
    /// (`None`: [`ASSUMED_MATERIAL`]); refused with the bracket.
    pub truth: Option<Arc<dyn Brdf>>,
}

/// A plan in both orders, priced.
pub struct PlannedMeasurement {
    /// The grid planned.
    pub grid: GridSpec,
    /// Its theta_h positions, degrees.
    pub theta_h_deg: Vec<f64>,
    /// The paper's nested order.
    pub nested: Plan,
    /// The optimized order.
    pub optimized: Plan,
    /// What the capture times assume, in words.
    pub assumed: String,
}

impl PlanRequest {
    /// Checks every value against its range and that a truth comes with predicted exposures.
    pub fn validate(&self) -> Result<(), PlanError> {
        self.grid.validate()?;
        match &self.theta_h {
            ThetaH::K(k) => {
                sampling_function(self.family, *k)?;
            }
            ThetaH::Positions(positions) if positions.is_empty() => {
                return Err(PlanError::Refused("theta_h_deg needs at least one value"));
            }
            ThetaH::Positions(positions) => {
                for &position in positions {
                    THETA_H_DEG
                        .check("theta_h_deg", position)
                        .map_err(RequestError::from)?;
                }
            }
        }
        if self.truth.is_some() && self.hdr == HdrChoice::Bracket {
            return Err(PlanError::Refused(
                "truth sets the brightness of predicted exposures: it needs hdr predicted",
            ));
        }
        Ok(())
    }
}

impl PlannedMeasurement {
    /// The plan in the order asked for.
    pub fn chosen(&self, order: PlanOrder) -> &Plan {
        match order {
            PlanOrder::Optimized => &self.optimized,
            PlanOrder::Nested => &self.nested,
        }
    }

    /// The summaries of the nested and the optimized order on `device`.
    pub fn summaries(&self, device: &Device) -> (PlanSummary, PlanSummary) {
        (self.nested.summary(device), self.optimized.summary(device))
    }
}

/// Plans `request` on `device` in both orders and prices the captures before any probe.
pub fn run_plan(
    request: &PlanRequest,
    device: &Device,
    stop: &AtomicBool,
    progress: &dyn Progress,
) -> Result<PlannedMeasurement, PlanError> {
    request.validate()?;
    progress.start("ordering", None);
    let planned = plan_until(request, device, stop);
    progress.finish();
    planned
}

/// [`run_plan`]'s work, checking `stop` before each of its steps.
fn plan_until(
    request: &PlanRequest,
    device: &Device,
    stop: &AtomicBool,
) -> Result<PlannedMeasurement, PlanError> {
    let stopped = |done: u64| -> Result<(), PlanError> {
        match is_raised(stop) {
            true => Err(PlanError::Stopped(Stopped {
                done,
                total: 3,
                what: "steps (grid, order, exposures)",
            })),
            false => Ok(()),
        }
    };
    let grid = request.grid.grid(None)?;
    let theta_h_deg = match &request.theta_h {
        ThetaH::K(k) => sampling_function(request.family, *k)?.positions_deg(grid.theta_h_samples),
        ThetaH::Positions(positions) => positions.clone(),
    };
    let (theta_d, phi_d) = (grid.theta_d_deg(), grid.phi_d_deg());
    let mut nested = Plan::from_grid(&theta_h_deg, &theta_d, &phi_d, grid.phi_h_deg, device);
    stopped(1)?;
    let mut optimized = order(&nested);
    stopped(2)?;
    let truth = match request.hdr {
        HdrChoice::Predicted => Some(match &request.truth {
            Some(truth) => truth.clone(),
            None => assumed_material()?,
        }),
        HdrChoice::Bracket => None,
    };
    let plans = &mut [&mut nested, &mut optimized];
    let assumed = price_before_probe(plans, device, truth, grid.phi_h_deg)?;
    Ok(PlannedMeasurement {
        grid,
        theta_h_deg,
        nested,
        optimized,
        assumed,
    })
}

/// [`ASSUMED_MATERIAL`], a built-in preset.
fn assumed_material() -> Result<Arc<dyn Brdf>, PlanError> {
    match preset(ASSUMED_MATERIAL) {
        Some(material) => Ok(Arc::new(material)),
        None => Err(PlanError::Refused(
            "the assumed material is not a built-in preset",
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::progress::NoProgress;

    fn request(theta_h: ThetaH) -> PlanRequest {
        PlanRequest {
            theta_h,
            family: Family::Exponential,
            grid: GridRequest::default(),
            order: PlanOrder::Optimized,
            hdr: HdrChoice::Predicted,
            truth: None,
        }
    }

    #[test]
    fn a_plan_holds_the_grid_in_both_orders() {
        let device = Device::utia();
        let planned = run_plan(
            &request(ThetaH::K(4.78)),
            &device,
            &AtomicBool::new(false),
            &NoProgress,
        )
        .unwrap();
        assert_eq!(
            planned.theta_h_deg.len(),
            GridSpec::recommended().theta_h_samples
        );
        let (nested, optimized) = planned.summaries(&device);
        assert_eq!(nested.total, optimized.total);
        assert_eq!(nested.total, planned.grid.configurations());
        assert!(optimized.duration_s() < nested.duration_s());
        assert!(
            planned.assumed.contains(ASSUMED_MATERIAL),
            "{}",
            planned.assumed
        );
    }

    #[test]
    fn a_raised_stop_ends_the_plan_before_its_ordering() {
        let device = Device::utia();
        let stop = AtomicBool::new(true);
        let error = run_plan(&request(ThetaH::K(4.78)), &device, &stop, &NoProgress)
            .err()
            .map(|e| e.to_string());
        assert_eq!(
            error.as_deref(),
            Some("stopped: 1 of 3 steps (grid, order, exposures) done")
        );
    }

    #[test]
    fn bad_requests_are_refused_with_the_python_arguments_words() {
        let refused = |r: PlanRequest| r.validate().unwrap_err().to_string();
        assert_eq!(
            refused(request(ThetaH::Positions(vec![1.0, 95.0]))),
            "theta_h_deg 95: expected degrees from 0 to 90"
        );
        assert_eq!(
            refused(request(ThetaH::K(0.0))),
            "k 0: expected a number above 0 and at most 100"
        );
        let bracket = PlanRequest {
            hdr: HdrChoice::Bracket,
            truth: Some(assumed_material().unwrap()),
            ..request(ThetaH::K(4.78))
        };
        assert!(refused(bracket).contains("it needs hdr predicted"));
    }
}
