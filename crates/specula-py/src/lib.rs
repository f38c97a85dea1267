//! Specula for Python: the library crates behind a PyO3 module (`specula._specula`, re-exported
//! by the `specula` package), numpy arrays in and out. The binding is thin: every function
//! converts its arguments, calls one library function with the GIL released and converts the
//! result; the science lives in the crates it calls.
//!
//! Conventions at this edge (docs/book/src/conventions.md): angles in degrees, named `*_deg`; f_r in
//! 1/sr per RGB channel; a MERL table is a `(90, 90, 180, 3)` float64 array indexed
//! `[theta_h_i, theta_d_i, phi_d_i, channel]`, NaN where a cell is not measured.

mod appearance;
mod brdf;
mod errors;
mod export;
mod interrupt;
mod picture;
mod plan;
mod reconstruction;
mod sampling;
mod session;
mod table;

use pyo3::prelude::*;

/// The native module; `python/specula/__init__.py` re-exports it as `specula`.
#[pymodule]
fn _specula(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("SpeculaError", m.py().get_type::<errors::SpeculaError>())?;
    m.add_class::<brdf::PyBrdf>()?;
    m.add_function(wrap_pyfunction!(brdf::load, m)?)?;
    m.add_function(wrap_pyfunction!(brdf::compare, m)?)?;
    m.add_function(wrap_pyfunction!(brdf::materials, m)?)?;
    m.add_function(wrap_pyfunction!(export::convert, m)?)?;
    m.add_function(wrap_pyfunction!(export::fit, m)?)?;
    m.add_function(wrap_pyfunction!(picture::render, m)?)?;
    m.add_function(wrap_pyfunction!(picture::report, m)?)?;
    m.add_function(wrap_pyfunction!(appearance::appearance, m)?)?;
    m.add_function(wrap_pyfunction!(table::read_merl, m)?)?;
    m.add_function(wrap_pyfunction!(table::write_merl, m)?)?;
    m.add_function(wrap_pyfunction!(sampling::probe, m)?)?;
    m.add_function(wrap_pyfunction!(sampling::fit_k, m)?)?;
    m.add_function(wrap_pyfunction!(plan::plan, m)?)?;
    m.add_function(wrap_pyfunction!(reconstruction::reconstruct, m)?)?;
    m.add_function(wrap_pyfunction!(reconstruction::read_provenance, m)?)?;
    m.add_function(wrap_pyfunction!(reconstruction::read_uncertainty, m)?)?;
    m.add_function(wrap_pyfunction!(reconstruction::evaluate, m)?)?;
    m.add_function(wrap_pyfunction!(session::calibrate, m)?)?;
    m.add_function(wrap_pyfunction!(session::measure, m)?)?;
    m.add_function(wrap_pyfunction!(session::read_session, m)?)?;
    Ok(())
}
