//! `specula`: plan, simulate, drive, reconstruct and inspect BRDF measurements of highly
//! specular materials. This crate only parses arguments, shows progress and reports errors;
//! the work lives in the library crates.

mod commands;
mod interrupt;
mod progress;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Measure the BRDF of highly specular materials on a goniometer with few, well-placed samples.
///
/// BRDF arguments accept a MERL .binary file, a material .toml file, a preset name
/// (silver-925, green-paint, chrome, steel) or a published fit as model:name.
#[derive(Parser)]
#[command(name = "specula", version, propagate_version = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    Demo(commands::demo::Args),
    Tabulate(commands::tabulate::Args),
    Info(commands::info::Args),
    Eval(commands::eval::Args),
    Compare(commands::compare::Args),
    Appearance(commands::appearance::Args),
    Convert(commands::convert::Args),
    Render(commands::render::Args),
    Plot(commands::plot::Args),
    Report(commands::report::Args),
    Plan(commands::plan::Args),
    Reconstruct(commands::reconstruct::Args),
    Evaluate(commands::evaluate::Args),
    Probe(commands::probe::Args),
    FitK(commands::fit_k::Args),
    Analyze(commands::analyze::Args),
    Placement(commands::placement::Args),
    Calibrate(commands::calibrate::Args),
    Check(commands::check::Args),
    Measure(commands::measure::Args),
    Session(commands::session::Args),
    Device(commands::device::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Demo(args) => commands::demo::run(args),
        Command::Tabulate(args) => commands::tabulate::run(args),
        Command::Info(args) => commands::info::run(args),
        Command::Eval(args) => commands::eval::run(args),
        Command::Compare(args) => commands::compare::run(args),
        Command::Appearance(args) => commands::appearance::run(args),
        Command::Convert(args) => commands::convert::run(args),
        Command::Render(args) => commands::render::run(args),
        Command::Plot(args) => commands::plot::run(args),
        Command::Report(args) => commands::report::run(args),
        Command::Plan(args) => commands::plan::run(args),
        Command::Reconstruct(args) => commands::reconstruct::run(args),
        Command::Evaluate(args) => commands::evaluate::run(args),
        Command::Probe(args) => commands::probe::run(args),
        Command::FitK(args) => commands::fit_k::run(args),
        Command::Analyze(args) => commands::analyze::run(args),
        Command::Placement(args) => commands::placement::run(args),
        Command::Calibrate(args) => commands::calibrate::run(args),
        Command::Check(args) => commands::check::run(args),
        Command::Measure(args) => commands::measure::run(args),
        Command::Session(args) => commands::session::run(args),
        Command::Device(args) => commands::device::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err:#}");
            ExitCode::from(1)
        }
    }
}
