//! A TOML error as one line, for the messages that name a file and its problem.

/// `line N: message` (or the message alone when the error has no position), on one line.
pub fn one_line(text: &str, error: &toml::de::Error) -> String {
    let message = error.message().trim().replace('\n', " ");
    match error.span() {
        Some(span) => format!("line {}: {message}", line_of(text, span.start)),
        None => message,
    }
}

/// 1-based line number of a byte offset.
fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_name_their_line() {
        let text = "a = 1\nb = [\n";
        let error = text.parse::<toml::Table>().unwrap_err();
        let line = one_line(text, &error);
        assert!(
            line.starts_with("line 2: ") || line.starts_with("line 3: "),
            "{line}"
        );
        assert!(!line.contains('\n'));
    }
}
