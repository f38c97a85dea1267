//! Reading input files with one-line errors that name the file, and locating the directory of
//! real measured data (`shared/data/measured`: the RGL files, MERL-100 fits and neural fits).

use anyhow::{anyhow, Error, Result};
use std::path::{Path, PathBuf};

/// Environment variable that overrides where the measured data lives.
pub const MEASURED_DIR_VAR: &str = "SPECULA_MEASURED_DIR";

/// The directory of measured data: `$SPECULA_MEASURED_DIR` when set, otherwise the
/// `shared/data/measured` directory next to the source tree this crate was built from.
pub fn measured_data_dir() -> PathBuf {
    match std::env::var_os(MEASURED_DIR_VAR) {
        Some(dir) => PathBuf::from(dir),
        None => Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/measured"),
    }
}

/// A file of the measured data directory, or an error saying where it was looked for and how
/// to point Specula at the data.
pub fn measured_file(relative: &str) -> Result<PathBuf> {
    let path = measured_data_dir().join(relative);
    if path.is_file() {
        Ok(path)
    } else {
        Err(anyhow!(
            "{}: measured data file not found (set {MEASURED_DIR_VAR} to the directory holding {relative})",
            path.display()
        ))
    }
}

/// The largest input file read whole, bytes: 8 times a MERL table (33 MB), above every
/// measured file of the formats read here. A larger file is refused before it is read.
pub const MAX_INPUT_BYTES: u64 = 256 << 20;

/// The bytes of an input file of at most [`MAX_INPUT_BYTES`]; the error names the file and
/// says why it cannot be read.
pub fn read_input(path: &Path) -> Result<Vec<u8>> {
    open_input(path)?;
    specula_core::bounded_read::read_bounded(path, MAX_INPUT_BYTES)
        .map_err(|e| file_error(path, format!("cannot read: {e}")))
}

/// An input file opened for streaming, once its size (at most [`MAX_INPUT_BYTES`]) is known.
pub fn open_input(path: &Path) -> Result<std::fs::File> {
    if path.is_dir() {
        return Err(file_error(path, "is a directory, not a file"));
    }
    let file =
        std::fs::File::open(path).map_err(|e| file_error(path, format!("cannot read: {e}")))?;
    let size = file
        .metadata()
        .map_err(|e| file_error(path, format!("cannot read: {e}")))?
        .len();
    if size > MAX_INPUT_BYTES {
        return Err(file_error(
            path,
            format!("cannot read: the file holds {size} bytes, more than the {MAX_INPUT_BYTES} an input may hold"),
        ));
    }
    Ok(file)
}

/// A one-line error `PATH: PROBLEM`.
pub fn file_error(path: &Path, problem: impl std::fmt::Display) -> Error {
    anyhow!("{}: {problem}", path.display())
}

/// The file name without its extension, used as the BRDF's name.
pub fn file_stem(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_name_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let err = read_input(dir.path()).unwrap_err().to_string();
        assert!(err.contains("is a directory") && err.contains(&dir.path().display().to_string()));
        let missing = dir.path().join("nothing.bsdf");
        let err = read_input(&missing).unwrap_err().to_string();
        assert!(err.starts_with(&missing.display().to_string()) && err.contains("cannot read"));
        assert!(!err.contains('\n'));
        assert_eq!(file_stem(Path::new("/a/b/gold.binary")), "gold");
    }

    #[test]
    fn a_huge_file_is_refused_before_it_is_read() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("huge.binary");
        std::fs::File::create(&path)
            .unwrap()
            .set_len(4 << 30)
            .unwrap(); // sparse 4 GiB
        for err in [
            read_input(&path).unwrap_err().to_string(),
            open_input(&path).unwrap_err().to_string(),
        ] {
            assert!(
                err.contains("huge.binary") && err.contains("4294967296 bytes"),
                "{err}"
            );
        }
    }
}
