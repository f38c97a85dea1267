//! The problem with a file's content, in words: a leaf that the readers of every format
//! (and `input`'s `FormatError`) share.

/// What is wrong with the content of a file, in words, for the caller to put after the
/// file's name (`truncated: 12 bytes, ...`, `row 3: theta_h is not finite`).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct Malformed(pub String);

impl std::ops::Deref for Malformed {
    type Target = str;

    /// The problem in words.
    fn deref(&self) -> &str {
        &self.0
    }
}

impl From<String> for Malformed {
    fn from(problem: String) -> Self {
        Malformed(problem)
    }
}

impl From<&str> for Malformed {
    fn from(problem: &str) -> Self {
        Malformed(problem.to_string())
    }
}
