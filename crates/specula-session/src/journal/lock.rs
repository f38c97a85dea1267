//! One writer at a time: the advisory lock on the lock file beside the journal's canonical
//! path, and on Unix the lock on the journal file itself (see the module documentation of
//! [`super`]).

use super::{check, JournalError};
use std::fs::File;
use std::path::{Path, PathBuf};

/// The lock file beside the journal, locked exclusively for as long as it is open (the OS
/// releases it when the process dies, however it dies).
/// A lock taken on a file that [`Journal::close`] removed meanwhile is no lock: the file is
/// opened again until the locked file is the one at the path.
pub(super) fn take_lock(path: &Path) -> Result<File, JournalError> {
    let lock_path = lock_path(path).map_err(|cause| JournalError::Lock {
        path: path.display().to_string(),
        cause,
    })?;
    let open = || {
        File::options()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&lock_path)
            .map_err(|cause| JournalError::Lock {
                path: path.display().to_string(),
                cause,
            })
    };
    let mut file = open()?;
    // A few tries: a child process forked by another thread of this process holds a copy
    // of a just-closed lock until it execs (the descriptor is close-on-exec).
    for _ in 0..LOCK_TRIES {
        match file.try_lock() {
            Ok(()) if is_at_path(&file, &lock_path) => return Ok(file),
            Ok(()) => file = open()?,
            Err(std::fs::TryLockError::WouldBlock) => std::thread::sleep(LOCK_PAUSE),
            Err(std::fs::TryLockError::Error(cause)) => {
                return Err(JournalError::Lock {
                    path: path.display().to_string(),
                    cause,
                })
            }
        }
    }
    Err(JournalError::Locked {
        path: path.display().to_string(),
        lock: lock_path.display().to_string(),
    })
}

/// Locks the journal file itself, whatever its name (`flock` on Unix: SQLite's own locks
/// are POSIX record locks, which it does not conflict with); `None` when there is no file yet
/// (or elsewhere than Unix, where the file's own lock would bar SQLite's reads).
pub(super) fn lock_identity(path: &Path) -> Result<Option<File>, JournalError> {
    if !cfg!(unix) || !path.exists() {
        return Ok(None);
    }
    let file = File::open(path).map_err(|cause| JournalError::Lock {
        path: path.display().to_string(),
        cause,
    })?;
    for _ in 0..LOCK_TRIES {
        match file.try_lock() {
            Ok(()) => return Ok(Some(file)),
            Err(std::fs::TryLockError::WouldBlock) => std::thread::sleep(LOCK_PAUSE),
            Err(std::fs::TryLockError::Error(cause)) => {
                return Err(JournalError::Lock {
                    path: path.display().to_string(),
                    cause,
                })
            }
        }
    }
    Err(JournalError::InUse {
        path: path.display().to_string(),
    })
}

/// `S.sqlite.lock` beside the journal `S.sqlite`, named after its canonical path (so that
/// two spellings of one journal take one lock).
pub(super) fn lock_path(path: &Path) -> std::io::Result<PathBuf> {
    let mut lock_path = check::canonical_path(path)?.into_os_string();
    lock_path.push(".lock");
    Ok(PathBuf::from(lock_path))
}

/// Whether the open `file` is still the file at `path` (not removed or replaced).
fn is_at_path(file: &File, path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (file.metadata(), std::fs::metadata(path)) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = file;
        path.exists()
    }
}

const LOCK_TRIES: usize = 10;
const LOCK_PAUSE: std::time::Duration = std::time::Duration::from_millis(25);
