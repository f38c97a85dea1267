//! What a user asks of a measurement (`specula measure`, the Python package's `measure`):
//! the simulated device's seed and noise, the probe and the sample's tilt, the grid, the
//! order, the HDR, the method, the checks and where to write, every range checked in one
//! place ([`MeasureRequest::validate`], errors naming the Python argument), and one entry
//! point ([`run_measure`]).

use crate::journal::SequentialSettings;
use crate::resume::session_settings;
use crate::workflow::{
    default_session_path, measure, session_grid, HdrChoice, MeasureOutcome, MeasureSettings,
    Observer, PlanOrder, Source,
};
use crate::workflow_error::WorkflowError;
use specula_acquisition::device::Device;
use specula_core::request::{self, check_merl_out, GridRequest, ProbeRequest, RequestError};
use specula_core::sampling::Family;
use specula_core::GridSpec;
use specula_reconstruct::{Method, PriorBasis};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// Why a measurement is refused or stops with an error.
#[derive(Debug, thiserror::Error)]
pub enum MeasureError {
    /// A value outside its range, a grid too large or an output that is not `.binary`.
    #[error(transparent)]
    Request(#[from] RequestError),
    /// The workflow failed.
    #[error(transparent)]
    Workflow(#[from] WorkflowError),
}

/// A measurement as a user asks for it.
#[derive(Debug, Clone)]
pub struct MeasureRequest {
    /// Seed of the simulated device: its positioning errors and its noise.
    pub seed: u64,
    /// A simulated device without noise or positioning error.
    pub ideal: bool,
    /// Simulate the light as a point instead of its disk.
    pub point_light: bool,
    /// The probe's samples and the simulated sample's tilt.
    pub probe: ProbeRequest,
    /// The sampling function's family.
    pub family: Family,
    /// The grid (a resumed session keeps its own unless a preset is given).
    pub grid: GridRequest,
    /// Order of the samples.
    pub order: PlanOrder,
    /// HDR at each sample.
    pub hdr: HdrChoice,
    /// The reconstruction method.
    pub method: Method,
    /// Fit through the instrument's response.
    pub deblur: bool,
    /// Run the alignment and orientation checks.
    pub checks: bool,
    /// Measure the main stage batch by batch until these limits; `None`: the whole grid.
    pub sequential: Option<SequentialSettings>,
    /// The MERL `.binary` to write.
    pub out: PathBuf,
    /// The session journal; `None`: `OUT.session.sqlite`.
    pub session: Option<PathBuf>,
}

impl MeasureRequest {
    /// Checks every value against its range and that `out` is a `.binary`.
    pub fn validate(&self) -> Result<(), RequestError> {
        check_merl_out(&self.out)?;
        self.probe.validate()?;
        if let Some(limits) = &self.sequential {
            request::MAX_HOURS.check("max_hours", limits.max_hours)?;
            request::MAX_SAMPLES.check("max_samples", limits.max_samples)?;
            if let Some(target) = limits.target_uncertainty_rel {
                request::TARGET_UNCERTAINTY_PERCENT.check("target_uncertainty", 100.0 * target)?;
            }
        }
        self.grid.validate()
    }

    /// The session journal.
    pub fn session_path(&self) -> PathBuf {
        self.session
            .clone()
            .unwrap_or_else(|| default_session_path(&self.out))
    }

    /// The grid measured: a resumed session's own unless a preset is given.
    pub fn grid(&self) -> Result<GridSpec, MeasureError> {
        Ok(self.grid.grid(session_grid(&self.session_path())?)?)
    }

    /// How the main stage is measured: as asked, except that a resumed session measured on
    /// a fixed grid stays on it unless a preset is given (as it keeps its grid, [`Self::grid`]):
    /// the command that started it resumes it.
    pub fn sequential(&self) -> Result<Option<SequentialSettings>, MeasureError> {
        let resumed = session_settings(&self.session_path())?;
        Ok(match resumed {
            Some(stored) if stored.sequential.is_none() && self.grid.preset.is_none() => None,
            _ => self.sequential,
        })
    }

    /// The workflow's settings on `grid` ([`Self::grid`]) with the main stage measured as
    /// `sequential` says ([`Self::sequential`]).
    pub fn settings(
        &self,
        grid: GridSpec,
        sequential: Option<SequentialSettings>,
    ) -> MeasureSettings {
        MeasureSettings {
            seed: self.seed,
            ideal: self.ideal,
            point_light: self.point_light,
            probe_samples: self.probe.samples,
            family: self.family,
            grid,
            order: self.order,
            hdr: self.hdr,
            method: self.method,
            deblur: self.deblur,
            checks: self.checks,
            sequential,
            tilt_deg: self.probe.tilt_deg,
            tilt_azimuth_deg: self.probe.tilt_azimuth_deg,
        }
    }
}

/// Measures `source` on `device` as `request` asks, journaled and resumable, until done or
/// `stop` is set ([`measure`]; `prior`: the basis of the `prior` method).
pub fn run_measure(
    request: &MeasureRequest,
    source: Source,
    device: &Device,
    prior: Option<&PriorBasis>,
    stop: Arc<AtomicBool>,
    observer: &mut dyn Observer,
) -> Result<MeasureOutcome, MeasureError> {
    request.validate()?;
    let settings = request.settings(request.grid()?, request.sequential()?);
    let session = request.session_path();
    Ok(measure(
        source,
        device,
        &settings,
        prior,
        &session,
        &request.out,
        stop,
        observer,
    )?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::ProbeSpec;

    fn request(out: &str) -> MeasureRequest {
        MeasureRequest {
            seed: 1,
            ideal: true,
            point_light: false,
            probe: ProbeRequest {
                samples: ProbeSpec::paper().samples,
                tilt_deg: 0.0,
                tilt_azimuth_deg: 0.0,
            },
            family: Family::Exponential,
            grid: GridRequest::default(),
            order: PlanOrder::Optimized,
            hdr: HdrChoice::Predicted,
            method: "lobe".parse().unwrap(),
            deblur: true,
            checks: true,
            sequential: None,
            out: PathBuf::from(out),
            session: None,
        }
    }

    #[test]
    fn a_request_is_refused_with_the_python_arguments_words() {
        assert!(request("a.binary").validate().is_ok());
        let tilted = MeasureRequest {
            probe: ProbeRequest {
                tilt_deg: 20.0,
                ..request("a.binary").probe
            },
            ..request("a.binary")
        };
        assert_eq!(
            tilted.validate().unwrap_err().to_string(),
            "tilt_deg 20: expected degrees from 0 to 10"
        );
        let csv = request("a.csv").validate().unwrap_err().to_string();
        assert!(
            csv.starts_with("a.csv: this command writes a MERL table"),
            "{csv}"
        );
        assert_eq!(
            request("dir/a.binary").session_path(),
            PathBuf::from("dir/a.session.sqlite")
        );
    }
}
