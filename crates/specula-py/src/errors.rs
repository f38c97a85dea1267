//! Library errors as Python exceptions, with the CLI's one-line message.

use pyo3::PyErr;
use std::error::Error;

pyo3::create_exception!(
    specula,
    SpeculaError,
    pyo3::exceptions::PyException,
    "A Specula error: the same one-line message as the CLI's `error: ...` (the file and the problem)."
);

/// The error and its causes joined by `": "`, as the CLI prints them (anyhow's `{:#}`).
pub(crate) fn one_line(error: &(dyn Error + 'static)) -> String {
    let mut message = error.to_string();
    let mut cause = error.source();
    while let Some(next) = cause {
        message.push_str(": ");
        message.push_str(&next.to_string());
        cause = next.source();
    }
    message
}

/// A [`SpeculaError`] carrying `error`'s one-line message.
pub(crate) fn to_py(error: impl Into<Box<dyn Error + Send + Sync>>) -> PyErr {
    let error = error.into();
    SpeculaError::new_err(one_line(error.as_ref()))
}

/// `?` on library results: their errors become [`SpeculaError`].
pub(crate) trait OrRaise<T> {
    fn or_raise(self) -> Result<T, PyErr>;
}

impl<T, E: Into<Box<dyn Error + Send + Sync>>> OrRaise<T> for Result<T, E> {
    fn or_raise(self) -> Result<T, PyErr> {
        self.map_err(to_py)
    }
}

/// A [`SpeculaError`] for a bad argument, worded like the CLI's checks.
pub(crate) fn invalid(message: impl Into<String>) -> PyErr {
    SpeculaError::new_err(message.into())
}
