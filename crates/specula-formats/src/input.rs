//! Reading input files with one-line errors that name the file, and finding the measured
//! data: the small permissively licensed tables are built into the program (the MERL-100
//! SGD and ABC fits, public domain; the neural-BRDF weights, MIT: `data/README.md` of this
//! crate, with their provenance), the rest (the RGL files, the GPL Lafortune table) is read
//! from the measured data directory (`shared/data/measured`), found at run time.

use specula_core::materials::MaterialError;
use specula_core::merl::{MerlError, MerlProblem};
use std::borrow::Cow;
use std::path::{Path, PathBuf};

/// Why a BRDF input cannot be found, read, parsed or written: one line that names the file
/// or the argument, as the CLI prints it (causes are part of the message, not error
/// `source`s, so that error chains print them once, as `MerlError` does).
#[derive(Debug, thiserror::Error)]
pub enum FormatError {
    /// A file that cannot be opened, read or written.
    #[error("{path}: cannot {action}: {}", specula_core::shown::io_cause(cause))]
    Io {
        /// The file.
        path: PathBuf,
        /// What was being done: `open`, `read` or `write`.
        action: &'static str,
        /// The cause.
        cause: std::io::Error,
    },
    /// An input file larger than [`MAX_INPUT_BYTES`].
    #[error("{path}: cannot read: the file holds {size} bytes, more than the {MAX_INPUT_BYTES} an input may hold")]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Its size, bytes.
        size: u64,
    },
    /// An input path that names a directory.
    #[error("{path}: is a directory, not a file")]
    Directory {
        /// The path.
        path: PathBuf,
    },
    /// A file of the measured data directory that is not there.
    #[error("{path}: measured data file not found (set {MEASURED_DIR_VAR} to the directory holding {relative})")]
    NotFound {
        /// Where it was looked for.
        path: PathBuf,
        /// Its path inside the measured data directory.
        relative: String,
    },
    /// A CSV file whose header or a row cannot be parsed.
    #[error("{path}: {place}: {cause}")]
    Csv {
        /// The file.
        path: PathBuf,
        /// `row N` or `cannot read the header`.
        place: String,
        /// The cause.
        cause: csv::Error,
    },
    /// A file whose content is not what its format says.
    #[error("{path}: {problem}")]
    Malformed {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        problem: Malformed,
    },
    /// A MERL `.binary` file whose content is wrong.
    #[error("{path}: {problem}")]
    Merl {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        problem: MerlProblem,
    },
    /// A BRDF argument that names nothing Specula can read.
    #[error("{spec}: {problem}")]
    Argument {
        /// The argument as given.
        spec: String,
        /// What is wrong, with near names when there are some.
        problem: String,
    },
    /// A folder given as a BRDF argument that cannot be listed.
    #[error("{spec}: cannot list the folder: {cause}")]
    Folder {
        /// The argument as given.
        spec: String,
        /// The cause.
        cause: std::io::Error,
    },
    /// A MERL table that cannot be read or written.
    #[error(transparent)]
    MerlFile(#[from] MerlError),
    /// A material file that cannot be read.
    #[error(transparent)]
    Material(#[from] MaterialError),
    /// An RGL `.bsdf` file that cannot be made or written.
    #[error(transparent)]
    RglWrite(#[from] crate::rgl::write::RglWriteError),
}

pub use crate::malformed::Malformed;

/// The one-line error `SPEC: PROBLEM` of a BRDF argument.
pub(crate) fn argument_error(spec: &str, problem: impl Into<String>) -> FormatError {
    FormatError::Argument {
        spec: spec.to_string(),
        problem: problem.into(),
    }
}

/// A result whose error is a [`FormatError`].
pub type Result<T, E = FormatError> = std::result::Result<T, E>;

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
    /// Where the file was read from: its path in the data directory, or `(built-in) NAME`.
    pub path: PathBuf,
    /// The file's contents.
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
        None => Err(not_found(on_disk, relative)),
    }
}

/// A file of the measured data directory, or an error saying where it was looked for and how
/// to point Specula at the data.
pub fn measured_file(relative: &str) -> Result<PathBuf> {
    let path = measured_data_dir().join(relative);
    if path.is_file() {
        Ok(path)
    } else {
        Err(not_found(path, relative))
    }
}

/// The error of a measured data file that is not where it was looked for.
fn not_found(path: PathBuf, relative: &str) -> FormatError {
    FormatError::NotFound {
        path,
        relative: relative.to_string(),
    }
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
        .map_err(|cause| io_error(path, "read", cause))
}

/// A CSV input file opened for reading row by row within
/// [`specula_core::bounded_read::CSV_LIMITS`] (a line too long or a file too large is an
/// error of the read, not memory), its header read: the error names the file.
pub fn open_csv(path: &Path) -> Result<csv::Reader<impl std::io::Read>> {
    let file = open_input(path)?;
    let mut reader = csv::Reader::from_reader(specula_core::bounded_read::BoundedText::new(
        std::io::BufReader::new(file),
        specula_core::bounded_read::CSV_LIMITS,
    ));
    reader
        .headers()
        .map_err(|cause| csv_error(path, "cannot read the header", cause))?;
    Ok(reader)
}

/// An input file opened for streaming, once its size (at most [`MAX_INPUT_BYTES`]) is known.
pub fn open_input(path: &Path) -> Result<std::fs::File> {
    if path.is_dir() {
        return Err(FormatError::Directory {
            path: path.to_path_buf(),
        });
    }
    let file = std::fs::File::open(path).map_err(|cause| io_error(path, "read", cause))?;
    let size = file
        .metadata()
        .map_err(|cause| io_error(path, "read", cause))?
        .len();
    if size > MAX_INPUT_BYTES {
        return Err(FormatError::TooLarge {
            path: path.to_path_buf(),
            size,
        });
    }
    Ok(file)
}

/// The one-line error `PATH: PROBLEM` of a file whose content is wrong.
pub fn file_error(path: &Path, problem: impl Into<Malformed>) -> FormatError {
    FormatError::Malformed {
        path: path.to_path_buf(),
        problem: problem.into(),
    }
}

/// The one-line error `PATH: cannot ACTION: CAUSE` of a file that cannot be opened, read or
/// written.
pub fn io_error(path: &Path, action: &'static str, cause: std::io::Error) -> FormatError {
    FormatError::Io {
        path: path.to_path_buf(),
        action,
        cause,
    }
}

/// The one-line error `PATH: PLACE: CAUSE` of a CSV file whose header or a row cannot be
/// parsed (`place` is `row N` or `cannot read the header`).
pub fn csv_error(path: &Path, place: impl Into<String>, cause: csv::Error) -> FormatError {
    FormatError::Csv {
        path: path.to_path_buf(),
        place: place.into(),
        cause,
    }
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
        assert_eq!(
            err,
            format!("{}: cannot read: no such file", missing.display())
        );
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
