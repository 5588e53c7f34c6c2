//! A results folder under its advisory lock, read once: what a run, its best-known RMSEs and
//! its store all work from, so nothing reads the results file before the lock is held.

use std::cell::Cell;
use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use super::{
    Contents, LOCK_FILE, PACKED_TRIALS_FILE, StoreError, TRIALS_FILE, io_err, is_packed,
    parse_contents, read_maybe_packed, write_error,
};

/// The advisory lock of a results folder, held while a store writes to it (released on drop).
#[derive(Debug)]
pub struct DirLock {
    _file: File,
}

impl DirLock {
    /// Takes the lock of `dir` without waiting, or reports who holds it
    /// ([`StoreError::Locked`]).
    pub fn acquire(dir: &Path) -> Result<Self, StoreError> {
        let path = dir.join(LOCK_FILE);
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)
            .map_err(|e| write_error(&path, e))?;
        match file.try_lock() {
            Ok(()) => {}
            Err(std::fs::TryLockError::WouldBlock) => {
                let mut text = String::new();
                let _ = file.read_to_string(&mut text);
                return Err(StoreError::Locked {
                    dir: dir.to_path_buf(),
                    pid: text.trim().parse().ok(),
                });
            }
            Err(std::fs::TryLockError::Error(e)) => return Err(io_err(&path)(e)),
        }
        // Holding the lock: record our PID for the message a second process prints.
        file.set_len(0)
            .and_then(|_| file.seek(SeekFrom::Start(0)))
            .and_then(|_| writeln!(file, "{}", std::process::id()))
            .and_then(|_| file.flush())
            .map_err(io_err(&path))?;
        Ok(DirLock { _file: file })
    }
}

/// What a locked folder's results file held when the lock was taken.
#[derive(Debug)]
pub(super) enum Found {
    /// No results file.
    Nothing,
    /// The plain file holds part of a header line only (a run killed while writing it).
    TornHeader,
    /// The file parsed; `unpacked` holds the bytes of a folder that has only the packed file.
    Parsed {
        /// What the file holds.
        contents: Box<Contents>,
        /// The unpacked bytes, when the file read was `trials.jsonl.gz`.
        unpacked: Option<Vec<u8>>,
    },
    /// Reading or parsing failed: the error opening a store on the folder reports.
    Failed(StoreError),
}

/// A results folder under its lock, with its results file read once (see the module docs).
#[derive(Debug)]
pub struct LockedFolder {
    dir: PathBuf,
    lock: DirLock,
    found: Found,
    // Declared after `lock`, so the lock is released before the guard cleans up.
    _unused: UnusedFolder,
}

/// What a lock created and nothing else used: when a run fails before it writes any results
/// (data that cannot be read, say), the folder it created for them, or the `.lock` it added
/// to an existing folder, is removed again rather than left behind empty.
#[derive(Debug)]
struct UnusedFolder {
    /// The folder, while the guard is armed.
    dir: Option<PathBuf>,
    /// The folder did not exist before the lock.
    created_dir: bool,
    /// `.lock` did not exist before the lock.
    created_lock: bool,
}

impl Drop for UnusedFolder {
    fn drop(&mut self) {
        let Some(dir) = self.dir.take() else {
            return;
        };
        if !self.created_lock {
            return;
        }
        let only_lock = std::fs::read_dir(&dir).is_ok_and(|entries| {
            entries
                .flatten()
                .all(|e| e.file_name() == std::ffi::OsStr::new(LOCK_FILE))
        });
        if only_lock {
            let _ = std::fs::remove_file(dir.join(LOCK_FILE));
            if self.created_dir {
                let _ = std::fs::remove_dir(&dir);
            }
        }
    }
}

impl LockedFolder {
    /// Creates `dir` if needed, takes its lock (or reports who holds it,
    /// [`StoreError::Locked`]), then reads its results file, plain or packed, once.
    pub fn lock(dir: &Path) -> Result<Self, StoreError> {
        let created_dir = std::fs::symlink_metadata(dir).is_err();
        std::fs::create_dir_all(dir).map_err(|e| write_error(dir, e))?;
        let created_lock = std::fs::symlink_metadata(dir.join(LOCK_FILE)).is_err();
        let unused = UnusedFolder {
            dir: Some(dir.to_path_buf()),
            created_dir,
            created_lock,
        };
        let lock = DirLock::acquire(dir)?;
        Ok(LockedFolder {
            dir: dir.to_path_buf(),
            lock,
            found: read_found(dir),
            _unused: unused,
        })
    }

    /// The folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// What the results file held when locked; `None` when there is none or it did not parse
    /// (opening a store on the folder then reports why).
    pub fn contents(&self) -> Option<&Contents> {
        match &self.found {
            Found::Parsed { contents, .. } => Some(contents),
            _ => None,
        }
    }

    pub(super) fn into_parts(mut self) -> (PathBuf, DirLock, Found) {
        // A store opens on the folder: it writes results, so the folder is kept.
        self._unused.dir = None;
        (self.dir, self.lock, self.found)
    }
}

fn read_found(dir: &Path) -> Found {
    for p in [dir.join(TRIALS_FILE), dir.join(PACKED_TRIALS_FILE)] {
        if let Err(e) = crate::input_file::check_regular_if_present(&p, super::RESULTS) {
            return Found::Failed(io_err(&p)(e));
        }
    }
    let path = match super::results_file_checked(dir) {
        Ok(p) => p,
        Err(e) => return Found::Failed(e),
    };
    if !path.exists() {
        return Found::Nothing;
    }
    let bytes = match read_maybe_packed(&path) {
        Ok(b) => b,
        Err(e) => return Found::Failed(e),
    };
    let packed = is_packed(&path);
    match parse_contents(&path, &bytes) {
        Ok(contents) => Found::Parsed {
            contents: Box::new(contents),
            unpacked: packed.then_some(bytes),
        },
        // Killed while writing the header: nothing of value.
        Err(StoreError::MissingHeader { .. }) if !packed && !bytes.contains(&b'\n') => {
            Found::TornHeader
        }
        Err(e) => Found::Failed(e),
    }
}

thread_local! {
    static READS: Cell<usize> = const { Cell::new(0) };
}

/// Counts one read of a results file on this thread ([`results_reads_on_this_thread`]).
pub(super) fn count_read() {
    READS.with(|r| r.set(r.get() + 1));
}

/// How many times this thread has read a results file (plain or packed). A diagnostic: tests
/// pin that a run reads its folder's file once, and only under the lock.
pub fn results_reads_on_this_thread() -> usize {
    READS.with(Cell::get)
}
