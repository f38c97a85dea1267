//! Numbers and text in messages as people read them: a value from a file or a device may be
//! 1e300, which `{}` prints with 300 digits, and a name or a header read from a file may be
//! 65,536 characters of anything, control characters included.

/// `x` with at most 6 decimals when its magnitude is in `[1e-4, 1e6)` (or it is 0), in
/// exponent form otherwise (`1e300`, `-3.5e-9`); `inf`, `-inf` and `NaN` as themselves.
pub fn shown(x: f64) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    if x == 0.0 || (1e-4..1e6).contains(&x.abs()) {
        let text = format!("{x:.6}");
        return text.trim_end_matches('0').trim_end_matches('.').to_string();
    }
    format!("{x:e}")
}

/// A number as people write it: four significant digits without an exponent between 1e-4
/// and 1e6 (`5.214`, `0.02`, `3`), otherwise in scientific notation (`1.234e-7`); `0` for
/// zero.
pub fn plain(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{}", if x == 0.0 { 0.0 } else { x });
    }
    let magnitude = x.abs();
    if !(1e-4..1e6).contains(&magnitude) {
        return format!("{x:.3e}");
    }
    let decimals = (3 - magnitude.log10().floor() as i32).max(0) as usize;
    let text = format!("{x:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

/// The cause of a failed read or write in words: `no such file`, `permission denied`, or
/// the system's message.
pub fn io_cause(err: &std::io::Error) -> String {
    match err.kind() {
        std::io::ErrorKind::NotFound => "no such file".to_string(),
        std::io::ErrorKind::PermissionDenied => "permission denied".to_string(),
        _ => err.to_string(),
    }
}

/// The most characters of a file's text that a message or a table quotes: [`excerpt`].
pub const EXCERPT_CHARS: usize = 60;

/// Text from a file (a name, a header, a field name) as a message may quote it: control
/// characters escaped (`\u{1b}`, `\n`), at most [`EXCERPT_CHARS`] characters kept, and a
/// cut marked `...(N more characters)`. Printable text of at most that length is unchanged.
pub fn excerpt(text: &str) -> String {
    let (mut shown, kept) = escaped_prefix(text);
    let more = text.chars().count() - kept;
    if more > 0 {
        shown.push_str(&format!("...({more} more characters)"));
    }
    shown
}

/// [`excerpt`] of bytes that may not be UTF-8 (invalid sequences shown as U+FFFD); a cut is
/// marked `...(N bytes in all)`.
pub fn excerpt_bytes(bytes: &[u8]) -> String {
    let head = &bytes[..bytes.len().min(4 * EXCERPT_CHARS)];
    let text = String::from_utf8_lossy(head);
    let (mut shown, kept) = escaped_prefix(&text);
    if kept < text.chars().count() || head.len() < bytes.len() {
        shown.push_str(&format!("...({} bytes in all)", bytes.len()));
    }
    shown
}

/// The first [`EXCERPT_CHARS`] characters of `text`, control characters escaped, and how
/// many characters that is.
fn escaped_prefix(text: &str) -> (String, usize) {
    let mut shown = String::new();
    let mut kept = 0;
    for c in text.chars().take(EXCERPT_CHARS) {
        if c.is_control() {
            shown.extend(c.escape_default());
        } else {
            shown.push(c);
        }
        kept += 1;
    }
    (shown, kept)
}

/// A duration as a console shows it while work runs: `1h 23m`, `4m 05s` or `12s`.
pub fn duration_text(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    match (s / 3600, (s / 60) % 60, s % 60) {
        (0, 0, s) => format!("{s}s"),
        (0, m, s) => format!("{m}m {s:02}s"),
        (h, m, _) => format!("{h}h {m:02}m"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations_read_well() {
        assert_eq!(duration_text(12.4), "12s");
        assert_eq!(duration_text(245.0), "4m 05s");
        assert_eq!(duration_text(5.0 * 3600.0 + 23.0 * 60.0), "5h 23m");
    }

    #[test]
    fn text_from_a_file_is_quoted_short_and_escaped() {
        assert_eq!(excerpt("silver-925"), "silver-925");
        assert_eq!(excerpt("a\u{1b}[2Jb\n"), "a\\u{1b}[2Jb\\n");
        let long = "x".repeat(65_536);
        let shown = excerpt(&long);
        assert_eq!(
            shown,
            format!("{}...(65476 more characters)", "x".repeat(60))
        );
        let bytes = [b'\x1b'; 65_535];
        let shown = excerpt_bytes(&bytes);
        assert!(shown.len() < 400 && !shown.contains('\x1b'), "{shown}");
    }

    #[test]
    fn numbers_show_with_few_digits() {
        assert_eq!(shown(1e300), "1e300");
        assert_eq!(shown(-1e300), "-1e300");
        assert_eq!(shown(4095.0), "4095");
        assert_eq!(shown(0.25), "0.25");
        assert_eq!(shown(0.0), "0");
        assert_eq!(shown(-3.5e-9), "-3.5e-9");
        assert_eq!(shown(f64::INFINITY), "inf");
        assert_eq!(shown(f64::NAN), "NaN");
        assert_eq!(shown(1234.5678912), "1234.567891");
        assert_eq!(shown(360000.0), "360000");
    }
}
