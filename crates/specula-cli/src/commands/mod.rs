//! One module per subcommand: its arguments (with the `--help` text) and its `run`.

pub(crate) mod analyze;
pub(crate) mod appearance;
pub(crate) mod calibrate;
pub(crate) mod check;
pub(crate) mod compare;
pub(crate) mod connect_args;
pub(crate) mod convert;
pub(crate) mod demo;
pub(crate) mod device;
pub(crate) mod eval;
pub(crate) mod evaluate;
pub(crate) mod fit;
pub(crate) mod fit_k;
pub(crate) mod grid_args;
pub(crate) mod info;
pub(crate) mod materials;
pub(crate) mod measure;
pub(crate) mod placement;
pub(crate) mod plan;
pub(crate) mod plot;
pub(crate) mod probe;
pub(crate) mod reconstruct;
pub(crate) mod render;
pub(crate) mod report;
pub(crate) mod session;
pub(crate) mod tabulate;
pub(crate) mod token_args;
pub(crate) mod view;

/// The device description `--device` names, or the paper's UTIA gonioreflectometer.
pub(crate) fn load_device(
    path: Option<&std::path::Path>,
) -> anyhow::Result<specula_acquisition::device::Device> {
    Ok(specula_acquisition::device::Device::load_or_utia(path)?)
}
