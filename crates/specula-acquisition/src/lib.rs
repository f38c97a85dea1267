//! Acquisition: the goniometer's model (device, kinematics, occlusion, timing), measurement
//! planning and ordering (paper sections 4.1 and 5.3).

pub mod calibration;
mod capture_bracket;
pub mod checks;
pub mod device;
pub mod hdr;
pub mod instrument;
pub mod kinematics;
pub mod occlusion;
pub mod ordering;
pub mod plan;
pub mod response;
pub mod simulator;
pub mod timing;

pub use checks::{run_check, Check, CheckOutcome, CheckRequest, CheckRunError, Found};
