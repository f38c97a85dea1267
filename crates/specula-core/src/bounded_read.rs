//! Reading a whole file only when its size is sensible: a file's size is checked before any
//! of it is read, and the read stops past the limit (a device file or a growing file may
//! claim a size it does not keep), so a 4 GiB file given by mistake is an error, not 4 GiB
//! of memory.

use std::io::Read;
use std::path::Path;

/// The largest TOML file read (a device model, a calibration, a material), bytes.
pub const MAX_TOML_BYTES: u64 = 1 << 20;

/// The bytes of the file at `path`, refused with [`std::io::ErrorKind::InvalidData`] when it
/// holds more than `max_bytes`.
pub fn read_bounded(path: &Path, max_bytes: u64) -> std::io::Result<Vec<u8>> {
    let file = std::fs::File::open(path)?;
    let too_big = |size: &str| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("the file holds {size} bytes, more than the {max_bytes} this reader accepts"),
        )
    };
    let size = file.metadata()?.len();
    if size > max_bytes {
        return Err(too_big(&size.to_string()));
    }
    let mut bytes = Vec::with_capacity(size as usize);
    file.take(max_bytes + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max_bytes {
        return Err(too_big("at least one more"));
    }
    Ok(bytes)
}

/// The text of a TOML file of at most [`MAX_TOML_BYTES`].
pub fn read_toml_text(path: &Path) -> std::io::Result<String> {
    let bytes = read_bounded(path, MAX_TOML_BYTES)?;
    String::from_utf8(bytes)
        .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidData, e.utf8_error()))
}

#[cfg(test)]
mod tests {
    use super::*;

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
            err.contains("more than the 16 this reader accepts"),
            "{err}"
        );
    }
}
