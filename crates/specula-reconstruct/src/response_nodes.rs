//! The instrument's response as quadrature nodes for a lobe fitted through it: how many
//! nodes the fit takes and how many each sample's ratio to the lobe as measured takes.

use specula_core::capture::{CaptureNode, CaptureResponse};

/// Quadrature nodes of the response for the fit through the instrument: enough for lobes
/// down to alpha 0.005 under a 1.8-degree disk.
pub(crate) const FIT_RESPONSE_NODES: usize = 256;

/// Quadrature nodes of the response for each sample's ratio to the lobe as measured. The fit
/// averages the quadrature's error over many samples, the ratio does not: each sample keeps
/// it, and the table is the sharp lobe times the ratio. With [`FIT_RESPONSE_NODES`] this
/// error alone took a GGX alpha 0.011 conductor measured noise-free through the UTIA
/// response (exponential theta_h, k 6.02, the paper's grid) to 0.0166 relative RMSE within
/// 75 deg with the lobe fitted exactly (alpha 0.01111 as with a point light, whose table
/// scores 0.0009); `specula evaluate --through-instrument` measures it.
pub(crate) const RESIDUAL_RESPONSE_NODES: usize = 4096;

/// The capture nodes of an instrument's response for a lobe fitted through it
/// ([`FIT_RESPONSE_NODES`] for the fit, [`RESIDUAL_RESPONSE_NODES`] for each sample's ratio to
/// the lobe as measured) and its resolution; empty (a point light) without a response or
/// with a point one.
pub(crate) struct ResponseNodes {
    /// The nodes of the lobe's fit.
    pub(crate) fit: Vec<CaptureNode>,
    /// The nodes of each sample's ratio to the lobe.
    pub(crate) residual: Vec<CaptureNode>,
    /// The response's resolution in theta_h (degrees).
    pub(crate) resolution_deg: Option<f64>,
}

impl ResponseNodes {
    pub(crate) fn of<R: CaptureResponse + ?Sized>(response: Option<&R>) -> Self {
        let through = response.filter(|r| !r.is_point());
        Self {
            fit: through.map_or_else(Vec::new, |r| r.capture_nodes(FIT_RESPONSE_NODES)),
            residual: through.map_or_else(Vec::new, |r| r.capture_nodes(RESIDUAL_RESPONSE_NODES)),
            resolution_deg: through.map(|r| r.resolution_deg()),
        }
    }
}
