//! Every read of a file is bounded: a whole file is read only when its size is sensible (its
//! size is checked before any of it is read, and the read stops past the limit, since a
//! device file such as `/dev/zero` or a growing file may claim a size it does not keep), and
//! a text file streamed line by line (a CSV file) is read through [`BoundedText`], which
//! stops at the first line longer than its limit and past a total size. A 4 GiB file or a
//! 200 MB line given by mistake is a one-line error, not gigabytes of memory.

use std::io::{BufReader, Read};
use std::path::Path;

/// The largest TOML file read (a device model, a calibration, a material), bytes.
pub const MAX_TOML_BYTES: u64 = 1 << 20;

/// The bytes of the file at `path`, refused with [`std::io::ErrorKind::InvalidData`] when it
/// holds more than `max_bytes`.
pub fn read_bounded(path: &Path, max_bytes: u64) -> std::io::Result<Vec<u8>> {
    let file = std::fs::File::open(path)?;
    let too_big = |holds: String| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("the file holds {holds}, more than the {max_bytes} bytes this reader accepts"),
        )
    };
    let size = file.metadata()?.len();
    if size > max_bytes {
        return Err(too_big(format!("{size} bytes")));
    }
    let mut bytes = Vec::with_capacity(size as usize);
    file.take(max_bytes + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max_bytes {
        // A device file or a growing one: its size was not what it claimed.
        return Err(too_big("more bytes than its size says".to_string()));
    }
    Ok(bytes)
}

/// The text of a TOML file of at most [`MAX_TOML_BYTES`].
pub fn read_toml_text(path: &Path) -> std::io::Result<String> {
    let bytes = read_bounded(path, MAX_TOML_BYTES)?;
    String::from_utf8(bytes)
        .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidData, e.utf8_error()))
}

/// The limits of a text file read line by line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TextLimits {
    /// The longest line accepted, bytes (without its newline).
    pub max_line_bytes: usize,
    /// The most bytes read in all.
    pub max_total_bytes: u64,
}

/// The limits of every CSV file read: lines of at most 64 KiB (a row of Specula's files is
/// under 200 bytes; a header naming a thousand columns fits), 256 MiB in all (eight times a
/// MERL table written as samples).
pub const CSV_LIMITS: TextLimits = TextLimits {
    max_line_bytes: 64 << 10,
    max_total_bytes: 256 << 20,
};

/// Why a bounded read stopped; carried inside the [`std::io::Error`] (kind
/// [`std::io::ErrorKind::InvalidData`]) that readers such as `csv` pass on, so the message
/// reaches the user whatever parses the text.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LimitError {
    /// A line longer than [`TextLimits::max_line_bytes`].
    #[error("line {line} is longer than {max_bytes} bytes, the most a line may hold")]
    LineTooLong {
        /// The line's number, from 1.
        line: u64,
        /// The limit, bytes.
        max_bytes: usize,
    },
    /// More than [`TextLimits::max_total_bytes`] in all.
    #[error("the file holds more than {max_bytes} bytes, the most this reader accepts")]
    TooLarge {
        /// The limit, bytes.
        max_bytes: u64,
    },
}

impl From<LimitError> for std::io::Error {
    fn from(limit: LimitError) -> Self {
        std::io::Error::new(std::io::ErrorKind::InvalidData, limit)
    }
}

/// A reader of text that fails (with a [`LimitError`]) at the first line longer than its
/// limit and once more than its total has been read, and keeps failing with the same error
/// (a parser that passes over one failed read, as `csv` does with a header, meets it at the
/// next). Lines end at `\n`; a `\r` before it counts towards the line.
#[derive(Debug)]
pub struct BoundedText<R> {
    inner: R,
    limits: TextLimits,
    /// Bytes read so far.
    total_bytes: u64,
    /// Newlines read so far.
    newlines: u64,
    /// Bytes of the current line read so far.
    line_bytes: usize,
    /// The limit met, once one is.
    failed: Option<LimitError>,
}

impl<R: Read> BoundedText<R> {
    /// `inner` read within `limits`.
    pub fn new(inner: R, limits: TextLimits) -> Self {
        Self {
            inner,
            limits,
            total_bytes: 0,
            newlines: 0,
            line_bytes: 0,
            failed: None,
        }
    }

    /// Counts `chunk` against the limits.
    fn check(&mut self, chunk: &[u8]) -> Result<(), LimitError> {
        self.total_bytes += chunk.len() as u64;
        if self.total_bytes > self.limits.max_total_bytes {
            return Err(LimitError::TooLarge {
                max_bytes: self.limits.max_total_bytes,
            });
        }
        for (k, segment) in chunk.split(|b| *b == b'\n').enumerate() {
            if k > 0 {
                self.newlines += 1;
                self.line_bytes = 0;
            }
            self.line_bytes += segment.len();
            if self.line_bytes > self.limits.max_line_bytes {
                return Err(LimitError::LineTooLong {
                    line: self.newlines + 1,
                    max_bytes: self.limits.max_line_bytes,
                });
            }
        }
        Ok(())
    }
}

impl<R: Read> Read for BoundedText<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if let Some(limit) = &self.failed {
            return Err(limit.clone().into());
        }
        let n = self.inner.read(buf)?;
        if let Err(limit) = self.check(&buf[..n]) {
            self.failed = Some(limit.clone());
            return Err(limit.into());
        }
        Ok(n)
    }
}

/// The text file at `path` opened for reading line by line within `limits`; its size is
/// checked first, so a file larger than the total is refused before any of it is read.
pub fn open_text(
    path: &Path,
    limits: TextLimits,
) -> std::io::Result<BoundedText<BufReader<std::fs::File>>> {
    let file = std::fs::File::open(path)?;
    if file.metadata()?.len() > limits.max_total_bytes {
        return Err(LimitError::TooLarge {
            max_bytes: limits.max_total_bytes,
        }
        .into());
    }
    Ok(BoundedText::new(BufReader::new(file), limits))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_line_or_an_endless_stream_stops_at_the_limit() {
        let limits = TextLimits {
            max_line_bytes: 10,
            max_total_bytes: 100,
        };
        let read_all = |text: &[u8]| {
            let mut out = Vec::new();
            BoundedText::new(text, limits)
                .read_to_end(&mut out)
                .map(|_| out)
                .map_err(|e| e.to_string())
        };
        assert_eq!(read_all(b"a,b\n0123456789\n").unwrap().len(), 15);
        assert_eq!(
            read_all(b"a,b\n0123456789\n01234567890\n").unwrap_err(),
            "line 3 is longer than 10 bytes, the most a line may hold"
        );
        let many_lines = b"0123456789\n".repeat(10);
        assert!(read_all(&many_lines)
            .unwrap_err()
            .contains("more than 100 bytes"));
        let mut csv =
            csv::Reader::from_reader(open_text(Path::new("/dev/zero"), CSV_LIMITS).unwrap());
        let err = csv.headers().unwrap_err().to_string();
        assert!(err.contains("line 1 is longer than 65536 bytes"), "{err}");
    }

    #[test]
    fn a_file_over_the_limit_is_refused_before_it_is_read() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("big.toml");
        let file = std::fs::File::create(&path).unwrap();
        file.set_len(4 << 30).unwrap(); // 4 GiB, sparse
        let err = read_toml_text(&path).unwrap_err().to_string();
        assert!(
            err.contains("4294967296 bytes") && err.contains("1048576"),
            "{err}"
        );
        std::fs::write(&path, "a = 1\n").unwrap();
        assert_eq!(read_toml_text(&path).unwrap(), "a = 1\n");
        let err = read_bounded(Path::new("/dev/zero"), 16)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains(
                "more bytes than its size says, more than the 16 bytes this reader accepts"
            ),
            "{err}"
        );
    }
}
