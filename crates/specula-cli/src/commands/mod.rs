//! One module per subcommand: its arguments (with the `--help` text) and its `run`.

pub mod compare;
pub mod demo;
pub mod eval;
pub mod info;
pub mod tabulate;
