//! Reading input files with one-line errors that name the file, and finding the measured
//! data: the small permissively licensed tables are built into the program (the MERL-100
//! SGD and ABC fits, public domain; the neural-BRDF weights, MIT: `data/README.md` of this
//! crate, with their provenance), the rest (the RGL files, the GPL Lafortune table) is read
//! from the measured data directory (`shared/data/measured`), found at run time.

use anyhow::{anyhow, Error, Result};
use std::borrow::Cow;
use std::path::{Path, PathBuf};

/// Environment variable that overrides where the measured data lives.
pub const MEASURED_DIR_VAR: &str = "SPECULA_MEASURED_DIR";

/// Where the measured data directory lies below a folder: `FOLDER/shared/data/measured`.
const MEASURED_DIR: &str = "shared/data/measured";

/// The tables built into the program, by their path in the measured data directory.
const BUILT_IN: [(&str, &[u8]); 8] = [
    (
        "merl_fits_djbrdf/merl_sgd_bagher2012.csv",
        include_bytes!("../data/merl_fits_djbrdf/merl_sgd_bagher2012.csv"),
    ),
    (
        "merl_fits_djbrdf/merl_abc_low2012.csv",
        include_bytes!("../data/merl_fits_djbrdf/merl_abc_low2012.csv"),
    ),
    (
        "merl_nbrdf/merl100_names.txt",
        include_bytes!("../data/merl_nbrdf/merl100_names.txt"),
    ),
    (
        "merl_nbrdf/merl100_nbrdf_weights_f32le.bin",
        include_bytes!("../data/merl_nbrdf/merl100_nbrdf_weights_f32le.bin"),
    ),
    (
        "merl_nbrdf/rgl_isotropic_names.txt",
        include_bytes!("../data/merl_nbrdf/rgl_isotropic_names.txt"),
    ),
    (
        "merl_nbrdf/rgl_isotropic_nbrdf_weights_f32le.bin",
        include_bytes!("../data/merl_nbrdf/rgl_isotropic_nbrdf_weights_f32le.bin"),
    ),
    (
        "merl_nbrdf/nielsen2015_names.txt",
        include_bytes!("../data/merl_nbrdf/nielsen2015_names.txt"),
    ),
    (
        "merl_nbrdf/nielsen2015_nbrdf_weights_f32le.bin",
        include_bytes!("../data/merl_nbrdf/nielsen2015_nbrdf_weights_f32le.bin"),
    ),
];

/// The directory of measured data: `$SPECULA_MEASURED_DIR` when set, otherwise the first
/// `shared/data/measured` found in the current folder or one above it (a clone with the
/// shared data beside it, as in CI), otherwise `shared/data/measured` (which then does not
/// exist, and errors name it).
pub fn measured_data_dir() -> PathBuf {
    if let Some(dir) = std::env::var_os(MEASURED_DIR_VAR) {
        return PathBuf::from(dir);
    }
    std::env::current_dir()
        .ok()
        .and_then(|cwd| {
            cwd.ancestors()
                .map(|folder| folder.join(MEASURED_DIR))
                .find(|dir| dir.is_dir())
        })
        .unwrap_or_else(|| PathBuf::from(MEASURED_DIR))
}

/// A file of the measured data: where it was read from (for messages) and its bytes.
pub struct DataFile {
    pub path: PathBuf,
    pub bytes: Cow<'static, [u8]>,
}

/// A file of the measured data by its path in the directory: the directory's copy when
/// there is one (so that `$SPECULA_MEASURED_DIR` can stand in newer data), else the
/// built-in copy, else an error saying where it was looked for.
pub fn data_file(relative: &str) -> Result<DataFile> {
    let on_disk = measured_data_dir().join(relative);
    if on_disk.is_file() {
        let bytes = read_input(&on_disk)?;
        return Ok(DataFile {
            path: on_disk,
            bytes: Cow::Owned(bytes),
        });
    }
    match BUILT_IN.iter().find(|(name, _)| *name == relative) {
        Some((name, bytes)) => Ok(DataFile {
            path: PathBuf::from(format!("(built-in) {name}")),
            bytes: Cow::Borrowed(bytes),
        }),
        None => Err(not_found(&on_disk, relative)),
    }
}

/// A file of the measured data directory, or an error saying where it was looked for and how
/// to point Specula at the data.
pub fn measured_file(relative: &str) -> Result<PathBuf> {
    let path = measured_data_dir().join(relative);
    if path.is_file() {
        Ok(path)
    } else {
        Err(not_found(&path, relative))
    }
}

/// The error of a measured data file that is not where it was looked for.
fn not_found(path: &Path, relative: &str) -> Error {
    anyhow!(
        "{}: measured data file not found (set {MEASURED_DIR_VAR} to the directory holding {relative})",
        path.display()
    )
}

/// The bytes of an input file; the error names the file and says why it cannot be read.
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
