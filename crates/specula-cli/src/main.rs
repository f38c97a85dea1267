//! `specula`: plan, simulate, drive, reconstruct and inspect BRDF measurements of highly
//! specular materials. This crate only parses arguments, shows progress and reports errors;
//! the work lives in the library crates.

#[macro_use]
mod output;
mod commands;
mod interrupt;
mod progress;
mod range;
mod verdict;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use std::process::ExitCode;

/// Measure the BRDF of highly specular materials on a goniometer with few, well-placed samples. A
/// BRDF argument is a MERL .binary, RGL .bsdf, UTIA .bin or material .toml file, a preset or a
/// model:name fit (`specula materials` lists them); angles are in degrees.
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
    Materials(commands::materials::Args),
    Eval(commands::eval::Args),
    Compare(commands::compare::Args),
    Coverage(commands::coverage::Args),
    Appearance(commands::appearance::Args),
    Convert(commands::convert::Args),
    Render(commands::render::Args),
    Plot(commands::plot::Args),
    Report(commands::report::Args),
    View(commands::view::Args),
    Plan(commands::plan::Args),
    Reconstruct(commands::reconstruct::Args),
    Evaluate(commands::evaluate::Args),
    Probe(commands::probe::Args),
    Fit(commands::fit::Args),
    FitK(commands::fit_k::Args),
    Analyze(commands::analyze::Args),
    Placement(commands::placement::Args),
    Calibrate(commands::calibrate::Args),
    Check(commands::check::Args),
    Measure(commands::measure::Args),
    Session(commands::session::Args),
    Device(commands::device::Args),
}

/// The command line as clap reads it: [`Cli`], with every option that takes a value taking a
/// negative number as that value, so that `--theta-d -40` meets the option's range check
/// (one line naming the option and its range) instead of being read as an unknown flag.
fn command() -> clap::Command {
    fn negative_values(cmd: clap::Command) -> clap::Command {
        cmd.mut_args(|arg| {
            if arg.get_action().takes_values() {
                arg.allow_negative_numbers(true)
            } else {
                arg
            }
        })
        .mut_subcommands(negative_values)
    }
    guide_links(negative_values(Cli::command()))
}

/// Where the user guide's reference pages live, relative to the repository root.
const REFERENCE_PAGES: &str = "docs/book/src/reference";

/// The longest option, with its value name, that keeps each option's help on its own line
/// (clap moves every help text below its option once the names take 40 % of the width).
const MAX_OPTION_WIDTH: usize = 28;

/// `--theta-h-samples <SAMPLES>` rather than `<THETA_H_SAMPLES>`: an option's value is named by
/// the last word of its name, or `X` when that is still too wide for [`MAX_OPTION_WIDTH`].
fn short_value_name(arg: clap::Arg) -> clap::Arg {
    let (Some(long), Some([name])) = (arg.get_long(), arg.get_value_names()) else {
        return arg;
    };
    let width = |value: &str| long.len() + value.len() + 5;
    if width(name.as_str()) <= MAX_OPTION_WIDTH {
        return arg;
    }
    let last = name.as_str().rsplit('_').next().unwrap_or("X").to_string();
    let short = if width(&last) <= MAX_OPTION_WIDTH {
        last
    } else {
        "X".to_string()
    };
    arg.value_name(short)
}

/// Every command's help is its short summary (`-h` and `--help` alike, one line per option
/// where it fits) ending with the guide's reference page that explains it in full: the top
/// level names the command index, each command its own page (a subcommand shares its
/// parent's page).
fn guide_links(cmd: clap::Command) -> clap::Command {
    fn link(cmd: clap::Command, page: &str) -> clap::Command {
        summary(cmd, page).mut_subcommands(|sub| link(sub, page))
    }
    fn summary(cmd: clap::Command, page: &str) -> clap::Command {
        cmd.mut_args(short_value_name)
            .disable_help_flag(true)
            .arg(
                clap::Arg::new("help")
                    .short('h')
                    .long("help")
                    .action(clap::ArgAction::HelpShort)
                    .help("Print help"),
            )
            .after_help(format!(
                "Every option, explained: {REFERENCE_PAGES}/{page}.md in the Specula repository"
            ))
    }
    summary(cmd, "commands").mut_subcommands(|sub| {
        let page = sub.get_name().to_string();
        link(sub, &page)
    })
}

/// `argv` read into [`Cli`] through [`command`].
fn parse(argv: impl IntoIterator<Item = std::ffi::OsString>) -> Result<Cli, clap::Error> {
    let mut matches = command().try_get_matches_from(argv)?;
    Cli::from_arg_matches_mut(&mut matches)
}

fn main() -> ExitCode {
    specula_core::atomic_file::refuse_oversized_writes();
    let cli = parse(std::env::args_os()).unwrap_or_else(|err| err.exit());
    let result = match cli.command {
        Command::Demo(args) => commands::demo::run(args),
        Command::Tabulate(args) => commands::tabulate::run(args),
        Command::Info(args) => commands::info::run(args),
        Command::Materials(args) => commands::materials::run(args),
        Command::Eval(args) => commands::eval::run(args),
        Command::Compare(args) => commands::compare::run(args),
        Command::Coverage(args) => commands::coverage::run(args),
        Command::Appearance(args) => commands::appearance::run(args),
        Command::Convert(args) => commands::convert::run(args),
        Command::Render(args) => commands::render::run(args),
        Command::Plot(args) => commands::plot::run(args),
        Command::Report(args) => commands::report::run(args),
        Command::View(args) => commands::view::run(args),
        Command::Plan(args) => commands::plan::run(args),
        Command::Reconstruct(args) => commands::reconstruct::run(args),
        Command::Evaluate(args) => commands::evaluate::run(args),
        Command::Probe(args) => commands::probe::run(args),
        Command::Fit(args) => commands::fit::run(args),
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
        Err(err) if output::is_closed_pipe(&err) => ExitCode::SUCCESS,
        Err(err) if err.is::<interrupt::Interrupted>() => {
            eprintln!("{err}");
            ExitCode::from(interrupt::stop_exit_code())
        }
        Err(err) if err.is::<verdict::Failed>() => {
            eprintln!("{err}");
            ExitCode::from(verdict::FAILED_EXIT)
        }
        Err(err) => {
            eprintln!("error: {err:#}");
            ExitCode::from(1)
        }
    }
}

#[cfg(test)]
mod tests {
    //! The command line as a whole: every numeric option refuses what lies outside its
    //! documented range, and one flag name means one thing in every command.

    use clap::{Arg, Command};
    use std::collections::BTreeMap;

    /// Every leaf command with the words that reach it (`["check", "orientation"]`).
    fn leaves(cmd: &Command, path: Vec<String>) -> Vec<(Vec<String>, Command)> {
        if cmd.get_subcommands().next().is_none() {
            return vec![(path, cmd.clone())];
        }
        cmd.get_subcommands()
            .flat_map(|sub| {
                let mut path = path.clone();
                path.push(sub.get_name().to_string());
                leaves(sub, path)
            })
            .collect()
    }

    /// Every long option of every leaf command: (command words, option).
    fn options() -> Vec<(Vec<String>, Arg)> {
        let mut cli = super::command();
        cli.build();
        leaves(&cli, Vec::new())
            .into_iter()
            .flat_map(|(path, cmd)| {
                cmd.get_arguments()
                    .filter(|a| a.get_long().is_some_and(|l| l != "help" && l != "version"))
                    .map(|a| (path.clone(), a.clone()))
                    .collect::<Vec<_>>()
            })
            .collect()
    }

    /// The Rust type an option's values are parsed into (its parser's type name in debug
    /// builds, which tests are).
    fn value_type(arg: &Arg) -> String {
        format!("{:?}", arg.get_value_parser().type_id())
    }

    fn is_numeric(arg: &Arg) -> bool {
        arg.get_action().takes_values()
            && [
                "f32", "f64", "u8", "u16", "u32", "u64", "usize", "i8", "i16", "i32", "i64",
                "isize",
            ]
            .contains(&value_type(arg).as_str())
    }

    #[test]
    fn every_numeric_option_refuses_values_outside_its_documented_range() {
        let mut checked = 0;
        for (path, arg) in options().into_iter().filter(|(_, a)| is_numeric(a)) {
            let long = arg.get_long().unwrap();
            if long == "seed" {
                // A seed is any whole number the type holds.
                continue;
            }
            let help = arg
                .get_long_help()
                .or(arg.get_help())
                .map(|h| {
                    h.to_string()
                        .split_whitespace()
                        .collect::<Vec<_>>()
                        .join(" ")
                })
                .unwrap_or_default();
            for (bad, joined) in [
                ("nan", true),
                ("inf", true),
                ("1e300", true),
                ("-1e300", true),
                ("99999999999", true),
                // A negative value as its own word is the option's value, not a flag.
                ("-1e300", false),
            ] {
                let mut argv = vec!["specula".to_string()];
                argv.extend(path.iter().cloned());
                if joined {
                    argv.push(format!("--{long}={bad}"));
                } else {
                    argv.extend([format!("--{long}"), bad.to_string()]);
                }
                let err = match super::parse(argv.iter().map(Into::into)) {
                    Ok(_) => panic!("{argv:?} was accepted"),
                    Err(err) => err.to_string(),
                };
                let needle = format!("--{long} {bad}: expected ");
                let words = err
                    .split_once(&needle)
                    .map(|(_, words)| words.trim().to_string())
                    .unwrap_or_else(|| panic!("{argv:?}: not a range error: {err}"));
                assert_eq!(err.trim().lines().count(), 1, "{argv:?}: {err}");
                assert!(
                    help.contains(&format!("Range: {words}")),
                    "{} --{long}: the help does not give the range '{words}': {help}",
                    path.join(" ")
                );
            }
            checked += 1;
        }
        assert!(checked > 40, "only {checked} numeric options found");
    }

    /// Options whose default differs between commands on purpose.
    const DEFAULTS_DIFFER: [(&str, &str); 4] = [
        (
            "out",
            "demo writes a folder, demo-out, by default; the others have no default",
        ),
        (
            "size",
            "a report's renders are smaller than a picture of its own",
        ),
        (
            "spp",
            "a report's renders take fewer rays than a picture of its own",
        ),
        (
            "theta-h-samples",
            "a plan's (plan, measure, evaluate) is its --grid-preset's, 16 for the recommended \
             grid; the paper's analysis of 5.1 and 5.2 (analyze, placement, fit-k, plot) keeps \
             the paper's 30",
        ),
    ];

    #[test]
    fn one_flag_name_means_one_thing_in_every_command() {
        let mut seen: BTreeMap<String, Vec<(String, String, Vec<String>)>> = BTreeMap::new();
        for (path, arg) in options() {
            let long = arg.get_long().unwrap().to_string();
            assert!(
                !long.ends_with("-deg") && !long.ends_with("-sr"),
                "{} --{long}: flag names carry no unit (docs/book/src/conventions.md)",
                path.join(" ")
            );
            let kind = if arg.get_action().takes_values() {
                value_type(&arg)
            } else {
                "switch".to_string()
            };
            let defaults = arg
                .get_default_values()
                .iter()
                .map(|v| v.to_string_lossy().into_owned())
                .collect();
            seen.entry(long)
                .or_default()
                .push((path.join(" "), kind, defaults));
        }
        for (long, uses) in &seen {
            let (first_cmd, kind, defaults) = &uses[0];
            for (cmd, other_kind, other_defaults) in uses {
                assert_eq!(
                    other_kind, kind,
                    "--{long} is {kind} in `{first_cmd}` but {other_kind} in `{cmd}`"
                );
                if !DEFAULTS_DIFFER.iter().any(|(name, _)| name == long) {
                    assert_eq!(
                        other_defaults, defaults,
                        "--{long} defaults to {defaults:?} in `{first_cmd}` but {other_defaults:?} in `{cmd}`"
                    );
                }
            }
        }
        // The spellings the issue found split, now one each.
        for gone in [
            "samples",
            "grid-side-by-side",
            "device-model",
            "tilt-deg",
            "phi-h-deg",
        ] {
            assert!(!seen.contains_key(gone), "--{gone} is still a visible flag");
        }
        let phi_h = &seen["phi-h"];
        assert!(phi_h.len() >= 7, "--phi-h in {} commands", phi_h.len());
    }
}
