//! Writing an output file so that it is either complete or absent: the bytes go to a
//! temporary file in the same folder, which is flushed to disk and then renamed over the
//! target (a rename within one file system is atomic on POSIX and on Windows). A kill, a
//! full disk or an error half-way leaves the target as it was, never truncated.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

/// Makes a write past the file-size limit (`ulimit -f`) fail with an error (EFBIG), which
/// the writers here report in one line after removing their temporary, instead of the
/// system killing the process silently (SIGXFSZ) and leaving the temporary behind. Call it
/// once at start-up, before any thread is started. Does nothing where there is no such
/// signal.
pub fn refuse_oversized_writes() {
    #[cfg(target_os = "linux")]
    // SAFETY: `signal` with SIG_IGN installs no handler code; called before threads start.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
}

/// Whether a file can be written at `path`, checked before any work that ends by writing it:
/// not a directory, and its folder exists and takes a new file (a temporary is made there
/// and removed at once). The error says why not, in words.
pub fn check_writable(path: &Path) -> Result<(), String> {
    if path.is_dir() {
        return Err("is a directory, not a file".into());
    }
    let folder = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    if !folder.is_dir() {
        return Err(format!("its folder {} does not exist", folder.display()));
    }
    if path.file_name().is_none() {
        return Err("not a file name".into());
    }
    tempfile::Builder::new()
        .prefix(".specula-check.")
        .tempfile_in(folder)
        .map(drop)
        .map_err(|e| {
            format!(
                "cannot write in its folder {}: {}",
                folder.display(),
                crate::shown::io_cause(&e)
            )
        })
}

/// Writes `path` through `write`, atomically (see the module documentation). The
/// temporary file is `.NAME.XXXXXX.tmp` beside `path` and is removed when `write` fails.
pub fn write_with(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<&mut File>) -> io::Result<()>,
) -> io::Result<()> {
    let temporary = written_temporary(path, write)?;
    temporary.persist(path).map_err(|e| e.error)?;
    Ok(())
}

/// A file of several written together that could not be written.
#[derive(Debug, thiserror::Error)]
#[error("{}: cannot write: {}", path.display(), crate::shown::io_cause(cause))]
pub struct WriteError {
    /// The file.
    pub path: PathBuf,
    /// The cause.
    pub cause: io::Error,
}

/// Writes several files (a table and its sidecar) so that either every one is replaced or
/// none is: each is written in full to its temporary first, and only when all are complete
/// are they renamed over their targets (renames within a folder need no space, so a disk
/// that fills part-way leaves every target as it was). Temporaries are removed on every
/// error. The error names the file.
pub fn write_together(files: &[(&Path, &[u8])]) -> Result<(), WriteError> {
    let fail = |path: &Path| {
        let path = path.to_path_buf();
        move |cause| WriteError { path, cause }
    };
    let mut written = Vec::with_capacity(files.len());
    for (path, bytes) in files {
        let temporary = written_temporary(path, |out| out.write_all(bytes)).map_err(fail(path))?;
        written.push((path, temporary));
    }
    for (path, temporary) in written {
        temporary.persist(path).map_err(|e| fail(path)(e.error))?;
    }
    Ok(())
}

/// A temporary file beside `path` (`.NAME.XXXXXX.tmp`) filled by `write` and flushed to
/// disk; it is removed when dropped unless persisted, so an error leaves nothing behind.
fn written_temporary(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<&mut File>) -> io::Result<()>,
) -> io::Result<tempfile::NamedTempFile> {
    let folder = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "not a file name"))?;
    let mut prefix = std::ffi::OsString::from(".");
    prefix.push(name);
    prefix.push(".");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    #[cfg(unix)]
    {
        // Read and write for everyone the umask allows, as `File::create` gives (a
        // temporary file is owner-only by default).
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let mut temporary = builder.tempfile_in(folder)?;
    {
        let mut out = BufWriter::new(temporary.as_file_mut());
        write(&mut out)?;
        out.flush()?;
    }
    temporary.as_file().sync_all()?;
    Ok(temporary)
}

/// Writes `bytes` to `path` atomically (see the module documentation).
pub fn write_bytes(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_with(path, |out| out.write_all(bytes))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_leaves_the_old_file_and_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("table.binary");
        write_bytes(&path, b"old").unwrap();
        let failed = write_with(&path, |out| {
            out.write_all(&[7; 100_000])?;
            Err(io::Error::other("disk full"))
        });
        assert_eq!(failed.unwrap_err().to_string(), "disk full");
        assert_eq!(std::fs::read(&path).unwrap(), b"old");
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("table.binary")]);
    }

    #[test]
    fn an_output_path_is_checked_before_work_starts() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(
            check_writable(dir.path()).unwrap_err(),
            "is a directory, not a file"
        );
        let err = check_writable(&dir.path().join("none").join("t.binary")).unwrap_err();
        assert!(
            err.starts_with("its folder") && err.ends_with("does not exist"),
            "{err}"
        );
        check_writable(&dir.path().join("t.binary")).unwrap();
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            0,
            "nothing left"
        );
    }

    #[test]
    fn files_written_together_all_change_or_none_does() {
        let dir = tempfile::tempdir().unwrap();
        let table = dir.path().join("t.binary");
        let sidecar = dir.path().join("t.provenance.npy");
        write_together(&[(&table, b"table 1"), (&sidecar, b"sidecar 1")]).unwrap();
        // The sidecar cannot be written (its folder is missing): the table stays as it was.
        let missing = dir.path().join("missing").join("t.provenance.npy");
        let err = write_together(&[(&table, b"table 2"), (&missing, b"sidecar 2")])
            .unwrap_err()
            .to_string();
        assert!(
            err.ends_with("t.provenance.npy: cannot write: no such file"),
            "{err}"
        );
        assert_eq!(std::fs::read(&table).unwrap(), b"table 1");
        assert_eq!(std::fs::read(&sidecar).unwrap(), b"sidecar 1");
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            2,
            "no temporary left"
        );
    }

    #[test]
    fn a_written_file_replaces_the_old_one_with_ordinary_permissions() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.csv");
        write_bytes(&path, b"old").unwrap();
        write_bytes(&path, b"new").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = std::fs::metadata(&path).unwrap().permissions().mode();
            assert_ne!(mode & 0o044, 0, "readable beyond the owner: {mode:o}");
        }
    }
}
