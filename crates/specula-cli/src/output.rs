//! The program's outputs. Standard output: everything the CLI prints goes through
//! [`write`] ([`out!`], [`outln!`]) or the [`Stdout`] writer (CSV), never `print!`, so that
//! it ends the program quietly when its reader goes away (`specula info x.binary | head -1`):
//! exit 0 as the reader asked for no more, no panic, no "Broken pipe" message; any other
//! failure to write (`> /dev/full`) ends it with a one-line error and exit 1. Output files:
//! [`OUTPUT_FILE`] checks each while the command line is read, before any work starts.

use clap::builder::TypedValueParser;
use std::io::{self, Write};
use std::path::PathBuf;

/// Writes `text` to standard output, as [`Stdout`] does.
pub(crate) fn write(text: std::fmt::Arguments) {
    let mut out = io::stdout().lock();
    handled(out.write_fmt(text).and_then(|()| out.flush()));
}

/// Standard output as a writer (for CSV writers): a write that fails ends the program, as
/// the module documentation says, so callers never see an error.
pub(crate) struct Stdout;

impl Write for Stdout {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        handled(io::stdout().lock().write_all(buf));
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        handled(io::stdout().lock().flush());
        Ok(())
    }
}

/// Ends the program when writing to standard output failed: exit 0 for a closed pipe,
/// otherwise a one-line error and exit 1.
fn handled(result: io::Result<()>) {
    if let Err(e) = result {
        if e.kind() == io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: cannot write to standard output: {e}");
        std::process::exit(1);
    }
}

/// The parser of every option naming a file to write: refuses, while the command line is
/// read (exit 2), a directory, a missing folder or a folder that takes no new file
/// ([`specula_core::atomic_file::check_writable`]), so a measurement never runs for an hour
/// to fail at its last step.
#[derive(Clone, Copy, Debug)]
pub(crate) struct OutputFile;

/// [`OutputFile`], for `value_parser = crate::output::OUTPUT_FILE`.
pub(crate) const OUTPUT_FILE: OutputFile = OutputFile;

impl TypedValueParser for OutputFile {
    type Value = PathBuf;

    fn parse_ref(
        &self,
        _cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<PathBuf, clap::Error> {
        let path = PathBuf::from(value);
        specula_core::atomic_file::check_writable(&path).map_err(|problem| {
            let flag = arg
                .and_then(|a| a.get_long())
                .map_or_else(|| "output".to_string(), |long| format!("--{long}"));
            clap::Error::raw(
                clap::error::ErrorKind::ValueValidation,
                format!("{flag} {}: {problem}\n", path.display()),
            )
        })?;
        Ok(path)
    }
}

/// True when `err` comes from writing to a reader that has gone away.
pub(crate) fn is_closed_pipe(err: &anyhow::Error) -> bool {
    err.chain().any(|cause| {
        cause
            .downcast_ref::<io::Error>()
            .is_some_and(|e| e.kind() == io::ErrorKind::BrokenPipe)
    })
}

/// `println!` through [`write`].
macro_rules! outln {
    () => {
        $crate::output::write(format_args!("\n"))
    };
    ($($arg:tt)*) => {
        $crate::output::write(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// `print!` through [`write`].
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::output::write(format_args!($($arg)*))
    };
}

pub(crate) use specula_core::shown::plain;

/// An error figure as `compare` and `fit` print it (relative RMSE, log RMSE): six decimals,
/// or, below 0.001, where six decimals keep fewer than four significant digits, seven in
/// exponent form. A near-diffuse table's log RMSE of 7.7e-7 against another's 1.28e-6 both
/// printed as 0.000001, which made two tables a third apart look level.
pub(crate) fn error_figure(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || x.abs() >= 1e-3 {
        format!("{x:.6}")
    } else {
        format!("{x:.6e}")
    }
}

#[cfg(test)]
mod tests {
    use super::{error_figure, plain};

    #[test]
    fn error_figures_keep_their_significant_digits() {
        assert_eq!(error_figure(0.003684), "0.003684");
        assert_eq!(error_figure(1100.717144), "1100.717144");
        assert_eq!(error_figure(0.0), "0.000000");
        // Six decimals would print both as 0.000001.
        assert_eq!(error_figure(7.70352192e-7), "7.703522e-7");
        assert_eq!(error_figure(1.27737047e-6), "1.277370e-6");
        assert_eq!(error_figure(0.000851), "8.510000e-4");
        assert_eq!(error_figure(f64::NAN), "NaN");
    }

    #[test]
    fn numbers_print_plainly() {
        assert_eq!(plain(5.2144), "5.214");
        assert_eq!(plain(0.0), "0");
        assert_eq!(plain(3.000_000_000_000_000_4), "3");
        assert_eq!(plain(0.02), "0.02");
        assert_eq!(plain(-1234.4), "-1234");
        assert_eq!(plain(1.2344e-7), "1.234e-7");
        assert_eq!(plain(f64::NAN), "NaN");
    }
}
