//! Standard output that ends the program quietly when its reader goes away (`specula info
//! x.binary | head -1`), as Unix tools do: exit 0, no panic, no "Broken pipe" message.

use std::io::{self, Write};

/// Writes `text` to standard output; a closed pipe ends the program (exit 0) and any other
/// failure to write (a full disk behind a redirect) ends it with a one-line error (exit 1).
pub(crate) fn write(text: std::fmt::Arguments) {
    let mut out = io::stdout().lock();
    if let Err(e) = out.write_fmt(text).and_then(|()| out.flush()) {
        if e.kind() == io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: cannot write to standard output: {e}");
        std::process::exit(1);
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

#[cfg(test)]
mod tests {
    use super::plain;

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
