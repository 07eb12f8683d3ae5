//! One writer per output: a long job takes an exclusive lock on a file in
//! its folder for as long as it runs, so a second run started on the same
//! folder stops at once with a clear error instead of writing over the
//! first one's parts and checkpoints.
//!
//! The lock is the operating system's (`File::try_lock`), so a run that is
//! killed releases it: an interrupted job resumes without deleting
//! anything. The file stays behind; only the lock on it counts.

use crate::error::Error;
use std::fs::{File, OpenOptions, TryLockError};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Held while a job writes into a folder; released on drop.
#[derive(Debug)]
pub struct FolderLock {
    _file: File,
    path: PathBuf,
}

impl FolderLock {
    /// Locks `dir/<name>` (creating `dir`), or fails with [`Error::Busy`]
    /// naming the process that holds it.
    pub fn acquire(dir: &Path, name: &str) -> Result<Self, Error> {
        match Self::try_acquire(dir, name)? {
            Ok(lock) => Ok(lock),
            Err(holder) => Err(Error::Busy {
                path: dir.join(name),
                holder,
            }),
        }
    }

    /// Locks `dir/<name>` (creating `dir`); `Ok(Err(holder))` if another
    /// run holds it, for a caller that leaves that work to it.
    pub fn try_acquire(dir: &Path, name: &str) -> Result<Result<Self, String>, Error> {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        let path = dir.join(name);
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)
            .map_err(|e| Error::io(&path, e))?;
        match file.try_lock() {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => {
                let holder = std::fs::read_to_string(&path).unwrap_or_default();
                return Ok(Err(holder.trim().to_string()));
            }
            Err(TryLockError::Error(e)) => return Err(Error::io(&path, e)),
        }
        file.set_len(0).map_err(|e| Error::io(&path, e))?;
        writeln!(file, "process {}", std::process::id()).map_err(|e| Error::io(&path, e))?;
        Ok(Ok(FolderLock { _file: file, path }))
    }

    pub fn path(&self) -> &Path {
        &self.path
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_lock_on_the_same_file_fails_until_the_first_is_dropped() {
        let dir = std::env::temp_dir().join(format!("folder-lock-{}", std::process::id()));
        let first = FolderLock::acquire(&dir, "run.lock").unwrap();
        match FolderLock::acquire(&dir, "run.lock") {
            Err(Error::Busy { path, holder }) => {
                assert_eq!(path, first.path());
                assert_eq!(holder, format!("process {}", std::process::id()));
            }
            other => panic!("expected Busy, got {other:?}"),
        }
        // Another name in the same folder is another lock.
        FolderLock::acquire(&dir, "other.lock").unwrap();
        drop(first);
        FolderLock::acquire(&dir, "run.lock").unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
