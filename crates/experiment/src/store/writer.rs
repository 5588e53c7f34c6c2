//! The append-only store that resumes, refuses or starts a results file in a locked folder
//! (see the parent module), and the atomic rewrite `merge` uses.

use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use super::folder::{DirLock, Found, LockedFolder};
use super::{
    Contents, Header, Line, PACKED_TRIALS_FILE, Session, StoreError, TRIALS_FILE, TrialRecord,
    encode_line, io_err, write_atomic,
};
use crate::machine::unix_now;

/// Refuses to resume when an instance's data hash differs from the stored one (files written
/// before hashes were recorded have none, and are not checked).
fn check_same_data(path: &Path, stored: &Header, now: &Header) -> Result<(), StoreError> {
    for (instance, hash) in &stored.data_hashes {
        if let Some(current) = now.data_hashes.get(instance)
            && current != hash
        {
            return Err(StoreError::DataChanged {
                path: path.to_path_buf(),
                instance: instance.clone(),
                stored: hash.clone(),
                now: current.clone(),
            });
        }
    }
    Ok(())
}

/// What [`ResultStore::open`] found.
#[derive(Debug)]
pub struct Opened {
    /// The store, positioned for appending.
    pub store: ResultStore,
    /// Trials already finished (resumed), in file order.
    pub records: Vec<TrialRecord>,
    /// The file's sessions, this one last (as reading the file back would give them).
    pub sessions: Vec<Session>,
    /// Human-readable notes (torn line saved, old file moved aside, duplicates).
    pub notes: Vec<String>,
}

/// An append-only results file shared by worker threads; holds the folder's lock while alive.
#[derive(Debug)]
pub struct ResultStore {
    path: PathBuf,
    file: Mutex<File>,
    _lock: DirLock,
}

/// A path `base.<suffix>-<unix time>[-k]` that does not exist yet.
fn aside_path(base: &Path, suffix: &str) -> PathBuf {
    let stamp = unix_now();
    let name = base
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut k = 0;
    loop {
        let candidate = if k == 0 {
            base.with_file_name(format!("{name}.{suffix}-{stamp}"))
        } else {
            base.with_file_name(format!("{name}.{suffix}-{stamp}-{k}"))
        };
        if !candidate.exists() {
            return candidate;
        }
        k += 1;
    }
}

/// `--fresh`: renames the plain and packed results files aside (never deletes them).
fn move_old_aside(dir: &Path, notes: &mut Vec<String>) -> Result<(), StoreError> {
    for p in [dir.join(TRIALS_FILE), dir.join(PACKED_TRIALS_FILE)] {
        if p.exists() {
            let aside = aside_path(&p, "old");
            std::fs::rename(&p, &aside).map_err(io_err(&p))?;
            notes.push(format!("moved the old results to {}", aside.display()));
        }
    }
    Ok(())
}

/// Resumes the results `c` read from the folder of `path` for `header`'s spec: refuses another
/// spec or other data, unpacks a packed-only folder, cuts a torn last line off (saved aside),
/// and returns the file opened for appending.
fn resume(
    path: &Path,
    header: &Header,
    c: &Contents,
    unpacked: Option<Vec<u8>>,
    notes: &mut Vec<String>,
) -> Result<File, StoreError> {
    if c.header.fingerprint != header.fingerprint {
        return Err(StoreError::FingerprintMismatch {
            path: path.to_path_buf(),
            found: c.header.fingerprint.clone(),
            expected: header.fingerprint.clone(),
        });
    }
    check_same_data(path, &c.header, header)?;
    if let Some(bytes) = unpacked {
        write_atomic(path, &bytes).map_err(io_err(path))?;
        notes.push(format!(
            "unpacked {} into {} to resume (the packed copy is kept)",
            path.with_file_name(PACKED_TRIALS_FILE).display(),
            path.display()
        ));
    }
    // Append mode: every write lands at the current end of the file.
    let file = OpenOptions::new()
        .append(true)
        .open(path)
        .map_err(io_err(path))?;
    if let Some(torn) = &c.torn {
        let aside = aside_path(path, "torn");
        std::fs::write(&aside, torn).map_err(io_err(&aside))?;
        file.set_len(c.good_len).map_err(io_err(path))?;
        notes.push(format!(
            "ignored a torn last line ({} bytes, from an interrupted run); saved to {}",
            torn.len(),
            aside.display()
        ));
    }
    if !c.duplicates.is_empty() {
        notes.push(format!(
            "{} duplicate trial lines ignored (first copy kept)",
            c.duplicates.len()
        ));
    }
    file.sync_data().map_err(io_err(path))?;
    Ok(file)
}

impl ResultStore {
    /// Opens `<dir>/trials.jsonl` for `header`'s spec: creates it, resumes it (same
    /// fingerprint), or refuses it (different fingerprint) unless `fresh` moves it aside.
    /// Writes a session line for this start. [`LockedFolder::lock`] then
    /// [`ResultStore::open_locked`].
    pub fn open(dir: &Path, header: Header, fresh: bool) -> Result<Opened, StoreError> {
        Self::open_locked(LockedFolder::lock(dir)?, header, fresh)
    }

    /// [`ResultStore::open`] on a folder already locked and read: the file is not read again.
    pub fn open_locked(
        folder: LockedFolder,
        header: Header,
        fresh: bool,
    ) -> Result<Opened, StoreError> {
        let (dir, lock, found) = folder.into_parts();
        let path = dir.join(TRIALS_FILE);
        let mut notes = Vec::new();
        let (file, resumed) = if fresh {
            move_old_aside(&dir, &mut notes)?;
            (Self::create(&path, &header)?, None)
        } else {
            match found {
                Found::Nothing => (Self::create(&path, &header)?, None),
                Found::Failed(e) => return Err(e),
                Found::TornHeader => {
                    let aside = aside_path(&path, "torn");
                    std::fs::rename(&path, &aside).map_err(io_err(&path))?;
                    notes.push(format!(
                        "results file had only a torn header; moved to {}",
                        aside.display()
                    ));
                    (Self::create(&path, &header)?, None)
                }
                Found::Parsed { contents, unpacked } => {
                    let file = resume(&path, &header, &contents, unpacked, &mut notes)?;
                    (file, Some(*contents))
                }
            }
        };
        let store = ResultStore {
            path,
            file: Mutex::new(file),
            _lock: lock,
        };
        let (mut sessions, records) =
            resumed.map_or_else(Default::default, |c| (c.sessions, c.records));
        let session = Session {
            started_unix: unix_now(),
            machine: header.machine.clone(),
            trials_present: records.len(),
            spec_text: header.spec_text.clone(),
            program_version: crate::PROGRAM_VERSION.to_string(),
            kernel: header.kernel.clone(),
            solver_kernel: header.solver_kernel.clone(),
            best_known: header.best_known.clone(),
            program: header.program.clone(),
            schemas: header.schemas.clone(),
        };
        store.write_line(&Line::Session(session.clone()))?;
        sessions.push(session);
        Ok(Opened {
            store,
            records,
            sessions,
            notes,
        })
    }

    fn create(path: &Path, header: &Header) -> Result<File, StoreError> {
        let text = encode_line(path, &Line::Header(header.clone()))?;
        let mut file = OpenOptions::new()
            .create_new(true)
            .append(true)
            .open(path)
            .map_err(io_err(path))?;
        if let Err(e) = file
            .write_all(text.as_bytes())
            .and_then(|_| file.sync_data())
        {
            // A file holding part of a header is of no use and would only be moved aside by
            // the next run: leave nothing behind.
            drop(file);
            let _ = std::fs::remove_file(path);
            return Err(io_err(path)(e));
        }
        Ok(file)
    }

    fn write_line(&self, line: &Line) -> Result<(), StoreError> {
        let text = encode_line(&self.path, line)?;
        // A poisoned lock only means another worker panicked mid-trial; the file is still fine.
        let mut file = self.file.lock().unwrap_or_else(|e| e.into_inner());
        let complete = file.metadata().map_err(io_err(&self.path))?.len();
        let written = file.write_all(text.as_bytes()).and_then(|_| file.flush());
        written.map_err(|e| {
            // A failed write (a full disk, say) may have left part of the line: cut the file
            // back to its last complete line, so it stays whole for a later resume.
            match file.set_len(complete) {
                Ok(()) => StoreError::AppendFailed {
                    path: self.path.clone(),
                    source: e,
                },
                Err(_) => io_err(&self.path)(e),
            }
        })
    }

    /// Appends one finished trial (one write + flush under the lock).
    pub fn append(&self, record: &TrialRecord) -> Result<(), StoreError> {
        self.write_line(&Line::Trial(record.clone()))
    }

    /// Path of the results file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// Replaces `<dir>/trials.jsonl` by a complete file (header, sessions, trials) in one atomic
/// write (temporary file, fsync, rename): a reader sees the old file or the new one, never a
/// mix. The caller proves it holds `dir`'s lock by passing it. Used by `merge`.
pub fn write_results(
    dir: &Path,
    _lock: &DirLock,
    header: &Header,
    sessions: &[Session],
    records: &[TrialRecord],
) -> Result<PathBuf, StoreError> {
    let path = dir.join(TRIALS_FILE);
    let mut text = encode_line(&path, &Line::Header(header.clone()))?;
    for s in sessions {
        text.push_str(&encode_line(&path, &Line::Session(s.clone()))?);
    }
    for r in records {
        text.push_str(&encode_line(&path, &Line::Trial(r.clone()))?);
    }
    write_atomic(&path, text.as_bytes()).map_err(io_err(&path))?;
    Ok(path)
}
