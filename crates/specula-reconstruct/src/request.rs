//! What a user asks of a reconstruction (`specula reconstruct`, the Python package's
//! `reconstruct`): the method, whether to fit through the instrument's response the samples
//! come with, and the MERL table to write, checked in one place
//! ([`ReconstructRequest::validate`], the same words from both front ends), and one entry
//! point ([`run_reconstruct`]). The samples, the response they were measured through and
//! the `prior` method's basis are the caller's to load (a samples CSV, a session journal,
//! arrays; `specula_accuracy::merl_prior::basis_for`).

use crate::phi_d_halves::reconstruct_halves;
use crate::prior::PriorBasis;
use crate::provenance::sidecar_path;
use crate::{Method, ReconstructError, Reconstruction};
use specula_core::atomic_file::{write_together, WriteError};
use specula_core::capture::CaptureResponse;
use specula_core::request::{check_merl_out, RequestError};
use specula_core::Sample;
use std::path::{Path, PathBuf};

/// The table's name when no output names it.
const DEFAULT_NAME: &str = "reconstruction";

/// A reconstruction as a user asks for it.
#[derive(Debug, Clone, PartialEq)]
pub struct ReconstructRequest {
    /// The reconstruction method.
    pub method: Method,
    /// Fit through the instrument's response when the samples come with one (a session's
    /// calibration holds it); `false`: the BRDF as measured, blurred by the light's disk.
    pub deblur: bool,
    /// The MERL `.binary` to write, with its provenance beside it
    /// ([`sidecar_path`]); `None`: nothing is written.
    pub out: Option<PathBuf>,
}

impl ReconstructRequest {
    /// Checks that `out`, when given, is a `.binary`.
    pub fn validate(&self) -> Result<(), RequestError> {
        self.out.as_deref().map_or(Ok(()), check_merl_out)
    }

    /// The table's name: the output's file stem, else `reconstruction`.
    pub fn name(&self) -> String {
        self.out
            .as_deref()
            .and_then(Path::file_stem)
            .map_or_else(|| DEFAULT_NAME.into(), |s| s.to_string_lossy().into_owned())
    }
}

/// Why a reconstruction is refused or fails.
#[derive(Debug, thiserror::Error)]
pub enum RunReconstructError {
    /// An output that is not a `.binary`.
    #[error(transparent)]
    Request(#[from] RequestError),
    /// The samples could not be reconstructed.
    #[error(transparent)]
    Reconstruct(#[from] ReconstructError),
    /// The table or its provenance could not be written (neither then changes).
    #[error(transparent)]
    Write(#[from] WriteError),
}

/// Reconstructs `samples` as `request` asks ([`reconstruct_halves`], through `response` when
/// the request deblurs; `prior`: the `prior` method's basis) and writes the table and its
/// provenance when it names an output.
pub fn run_reconstruct<R: CaptureResponse + ?Sized>(
    request: &ReconstructRequest,
    samples: &[Sample],
    response: Option<&R>,
    prior: Option<&PriorBasis>,
) -> Result<Reconstruction, RunReconstructError> {
    request.validate()?;
    let response = response.filter(|_| request.deblur);
    let reconstruction =
        reconstruct_halves(samples, request.method, &request.name(), response, prior)?;
    if let Some(out) = &request.out {
        reconstruction.write(out)?;
    }
    Ok(reconstruction)
}

impl Reconstruction {
    /// Writes the table to `out` and its provenance to [`sidecar_path`] beside it, together:
    /// neither changes unless both are written.
    pub fn write(&self, out: &Path) -> Result<(), WriteError> {
        write_together(&[
            (out, &self.brdf.to_bytes()),
            (&sidecar_path(out), &self.provenance.to_npy()),
        ])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::{HalfDiff, MerlBrdf, Rgb};

    fn request(method: Method, out: Option<&Path>) -> ReconstructRequest {
        ReconstructRequest {
            method,
            deblur: true,
            out: out.map(Path::to_path_buf),
        }
    }

    fn samples() -> Vec<Sample> {
        let mut samples = Vec::new();
        for h in [0.0, 5.0, 20.0, 45.0] {
            for d in [0.0, 30.0, 60.0] {
                for p in [0.0, 45.0, 90.0] {
                    let hd = HalfDiff::from_degrees(h, 45.0, d, p);
                    samples.push(Sample::new(hd, Rgb::splat(0.5)));
                }
            }
        }
        samples
    }

    #[test]
    fn an_output_that_is_not_merl_is_refused_in_the_front_ends_words() {
        assert!(request(Method::Lobe, None).validate().is_ok());
        let csv = request(Method::Lobe, Some(Path::new("t.csv")))
            .validate()
            .unwrap_err()
            .to_string();
        assert!(
            csv.starts_with("t.csv: this command writes a MERL table"),
            "{csv}"
        );
        assert_eq!(request(Method::Log, None).name(), "reconstruction");
        assert_eq!(
            request(Method::Log, Some(Path::new("dir/steel.binary"))).name(),
            "steel"
        );
    }

    #[test]
    fn the_table_and_its_provenance_are_written_as_reconstructed() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("flat.binary");
        let none = None::<&dyn CaptureResponse>;
        let r =
            run_reconstruct(&request(Method::Linear, Some(&out)), &samples(), none, None).unwrap();
        assert_eq!(MerlBrdf::read(&out).unwrap().to_bytes(), r.brdf.to_bytes());
        let provenance = crate::provenance::Provenance::beside(&out).unwrap();
        assert_eq!(provenance, Some(r.provenance));
        let refused = run_reconstruct(&request(Method::Prior, None), &samples(), none, None);
        assert!(matches!(
            refused,
            Err(RunReconstructError::Reconstruct(
                ReconstructError::NoPriorBasis
            ))
        ));
    }
}
