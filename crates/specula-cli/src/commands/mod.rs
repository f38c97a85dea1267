//! One module per subcommand: its arguments (with the `--help` text) and its `run`.

pub mod analyze;
pub mod appearance;
pub mod calibrate;
pub mod check;
pub mod compare;
pub mod convert;
pub mod demo;
pub mod device;
pub mod eval;
pub mod evaluate;
pub mod fit_k;
pub mod grid_args;
pub mod info;
pub mod measure;
pub mod placement;
pub mod plan;
pub mod plot;
pub mod probe;
pub mod reconstruct;
pub mod render;
pub mod report;
pub mod session;
pub mod tabulate;
pub mod token_args;
