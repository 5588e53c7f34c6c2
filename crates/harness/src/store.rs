//! The crash-safe results store: `trials.jsonl`, one JSON object per line.
//!
//! Layout of `<out>/trials.jsonl`:
//!
//! 1. A header line `{"type":"header", ...}` holding the format version, the experiment name,
//!    the spec fingerprint (hash of the canonicalised spec, see [`crate::spec::Spec::fingerprint`]),
//!    the canonical spec itself and the machine of the first session.
//! 2. One `{"type":"session", ...}` line per start (machine, threads, trials already present),
//!    so resumed runs on other machines stay visible.
//! 3. One `{"type":"trial", ...}` line per finished trial ([`TrialRecord`]).
//!
//! Each line is serialised completely in memory and then written with a single `write_all` and
//! flushed while holding a mutex, so a kill can at worst leave one torn line at the very end.
//! On open, an existing file with the same fingerprint is resumed: a torn tail (bytes after the
//! last newline, or an unparsable last line) is copied to `trials.jsonl.torn-<unix time>` and
//! truncated away; finished trials are returned so the runner skips them. A file with a different
//! fingerprint is refused ([`StoreError::FingerprintMismatch`]); `fresh` renames it to
//! `trials.jsonl.old-<unix time>` (never deletes it) and starts a new one.
//!
//! Derived files (summary, statistics, plots) are written with [`write_atomic`]: a temporary file
//! in the same directory, fsync, then rename, so a reader never sees half a file.
//!
//! One writer at a time: [`ResultStore::open`] takes an advisory lock on `<out>/.lock` (which
//! holds the writer's PID) for as long as the store lives, so a second run on the same folder
//! fails at once with [`StoreError::Locked`] naming the holder instead of interleaving lines.
//! Trial lines are written through a file opened in append mode.
//!
//! Packed results: the repository commits results as `trials.jsonl.gz`. [`read_results`] reads
//! the packed file when the plain one is absent, and [`ResultStore::open`] unpacks it into
//! `trials.jsonl` (keeping the packed copy) before resuming, so nobody has to unpack by hand.

use std::collections::BTreeMap;
use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use serde::{Deserialize, Serialize};
use sls::{Budget, TrialResult};

use crate::machine::{MachineInfo, unix_now};

/// Version of the `trials.jsonl` layout.
pub const FORMAT_VERSION: u32 = 1;

/// Name of the results file inside the output directory.
pub const TRIALS_FILE: &str = "trials.jsonl";

/// Name of the packed (gzip) results file, as committed to the repository.
pub const PACKED_TRIALS_FILE: &str = "trials.jsonl.gz";

/// Name of the lock file inside the output directory (holds the writer's PID).
pub const LOCK_FILE: &str = ".lock";

/// Largest results file read back (unpacked), against a corrupt or hostile `.gz`.
pub const MAX_RESULTS_BYTES: u64 = 8 << 30;

/// Errors of the results store.
#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    /// An I/O operation failed.
    #[error("{path}: {source}")]
    Io {
        /// The file or directory involved.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// Appending a line failed; the file was cut back to its last complete line, so every
    /// trial written before is kept and a later run resumes from there.
    #[error(
        "{path}: {source} (the file was cut back to its last complete line; run again to resume)"
    )]
    AppendFailed {
        /// The results file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The results file was written for a different spec.
    #[error(
        "{path} holds results of a different spec (stored fingerprint {found}, this spec {expected}).\n\
         Refusing to mix them. Either write elsewhere with --out DIR, or start over with --fresh \
         (the old file is renamed to {}.old-<time>, never deleted).",
        TRIALS_FILE
    )]
    FingerprintMismatch {
        /// The results file.
        path: PathBuf,
        /// Fingerprint stored in its header.
        found: String,
        /// Fingerprint of the current spec.
        expected: String,
    },
    /// A complete line in the middle of the file does not parse.
    #[error("{path}:{line}: corrupt results line ({message}); the file was not modified")]
    Corrupt {
        /// The results file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What failed to parse.
        message: String,
    },
    /// The file has no header line.
    #[error("{path}: missing header line (not a brdf-sls results file?)")]
    MissingHeader {
        /// The results file.
        path: PathBuf,
    },
    /// Another process is writing to the same results folder.
    #[error(
        "{dir} is in use by another brdf-sls process{}: wait for it to finish, or write elsewhere with --out DIR",
        pid.map(|p| format!(" (PID {p})")).unwrap_or_default()
    )]
    Locked {
        /// The results folder.
        dir: PathBuf,
        /// The holder's PID, when its lock file could be read.
        pid: Option<u32>,
    },
    /// The data of an instance differ from the data the results were started on.
    #[error(
        "{path}: instance `{instance}` has different data now (hash {now}) than when these results \
         were started ({stored}); the data file or its filters changed. Write elsewhere with --out \
         DIR, or start over with --fresh (the old file is moved aside, never deleted)."
    )]
    DataChanged {
        /// The results file.
        path: PathBuf,
        /// The instance.
        instance: String,
        /// Hash stored in the header.
        stored: String,
        /// Hash of the data now.
        now: String,
    },
    /// A record could not be serialised (the trial is not lost silently: the run stops).
    #[error("{path}: cannot serialise a results line: {message}")]
    Serialize {
        /// The results file.
        path: PathBuf,
        /// serde_json's message.
        message: String,
    },
    /// The packed results are larger than [`MAX_RESULTS_BYTES`] once unpacked.
    #[error("{path}: unpacks to more than {MAX_RESULTS_BYTES} bytes; refusing to read it")]
    TooLarge {
        /// The packed file.
        path: PathBuf,
    },
    /// A folder holds both `trials.jsonl` and `trials.jsonl.gz`, and the plain file was not
    /// unpacked from the packed one: which one holds the results is unknown, so neither is read.
    #[error(
        "{dir} holds both {TRIALS_FILE} and {PACKED_TRIALS_FILE}, and the plain file does not \
         start with the packed one's results; refusing to guess which holds the results: \
         remove (or move away) {PACKED_TRIALS_FILE} to use the plain file, or {TRIALS_FILE} \
         to use the packed one"
    )]
    BothPresent {
        /// The results folder.
        dir: PathBuf,
    },
    /// The file has a newer format version.
    #[error(
        "{path}: results format version {found} is not supported (this build reads {FORMAT_VERSION})"
    )]
    Version {
        /// The results file.
        path: PathBuf,
        /// Version found in the header.
        found: u32,
    },
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> StoreError + '_ {
    move |source| StoreError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// First line of a results file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Header {
    /// Layout version ([`FORMAT_VERSION`]).
    pub format: u32,
    /// Experiment name.
    pub experiment: String,
    /// Fingerprint of the canonical spec: results are only resumed under the same fingerprint.
    pub fingerprint: String,
    /// When the file was created (Unix seconds).
    pub created_unix: u64,
    /// Machine of the first session.
    pub machine: MachineInfo,
    /// The canonical spec the fingerprint was computed from.
    pub spec: serde_json::Value,
    /// The spec's TOML text as given (lets `plot` and `stats` work from the results alone).
    #[serde(default)]
    pub spec_text: String,
    /// Version of the program that created the file ([`crate::PROGRAM_VERSION`]: the crate
    /// version and the git commit of the build; the crate version only in files before
    /// 2026-12-02, empty in older ones).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub program_version: String,
    /// The evaluation kernel of the first session (empty in older files).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub kernel: String,
    /// Instance name -> hash of its data ([`crate::seed::data_hash`]); a resume on different
    /// data is refused. Empty in older files (then nothing is checked).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub data_hashes: BTreeMap<String, String>,
    /// The shard of the plan this file holds (`brdf-sls run --shard K/N`); `None` for a whole
    /// plan, a merged folder, and older files.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<crate::shard::Shard>,
    /// Instance name -> best-known RMSE when the file was created ([`crate::best_known`]).
    /// Empty in older files.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub best_known: BTreeMap<String, crate::best_known::BestKnown>,
}

/// One start of a run against a results file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Session {
    /// Start time (Unix seconds).
    pub started_unix: u64,
    /// Machine and thread count of this session.
    pub machine: MachineInfo,
    /// Finished trials already in the file at the start.
    pub trials_present: usize,
    /// The spec's TOML text of this session (it may raise `trials` over the header's), so that
    /// `stats` and `plot` on the folder alone use the latest plan. Empty in older files.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub spec_text: String,
    /// Version of the program that ran this session (as in [`Header::program_version`]).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub program_version: String,
    /// The evaluation kernel of this session (empty in older files).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub kernel: String,
    /// Instance name -> best-known RMSE this session used (empty in older files).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub best_known: BTreeMap<String, crate::best_known::BestKnown>,
}

/// One finished trial.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrialRecord {
    /// Unique key `instance/configuration/trial`.
    pub key: String,
    /// Instance name.
    pub instance: String,
    /// Configuration label.
    pub config: String,
    /// Trial index within (instance, configuration), from 0.
    pub trial: u32,
    /// The trial's seed ([`crate::seed::trial_seed`]).
    pub seed: u64,
    /// The RMSE the trial ran to (the instance's lowest target).
    pub target: f64,
    /// The budget the trial had.
    pub budget: Budget,
    /// What the trial returned (times, evaluations, anytime trace).
    pub result: TrialResult,
}

impl TrialRecord {
    /// The key of a trial.
    pub fn make_key(instance: &str, config: &str, trial: u32) -> String {
        format!("{instance}/{config}/{trial}")
    }
}

#[derive(Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
enum Line {
    Header(Header),
    Session(Session),
    Trial(TrialRecord),
}

/// Parses one line. serde_json writes non-finite floats as `null`; a trial that never evaluated
/// a point has `best_rmse = +inf`, so `null` there is read back as +inf.
fn decode_line(text: &str) -> Result<Line, serde_json::Error> {
    let mut v: serde_json::Value = serde_json::from_str(text)?;
    let mut infinite_best = false;
    if let Some(best) = v
        .get_mut("result")
        .and_then(|r| r.get_mut("best_rmse"))
        .filter(|b| b.is_null())
    {
        *best = serde_json::json!(0.0);
        infinite_best = true;
    }
    let mut line: Line = serde_json::from_value(v)?;
    if let (true, Line::Trial(rec)) = (infinite_best, &mut line) {
        rec.result.best_rmse = f64::INFINITY;
    }
    Ok(line)
}

fn encode_line(path: &Path, line: &Line) -> Result<String, StoreError> {
    let mut s = serde_json::to_string(line).map_err(|e| StoreError::Serialize {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    s.push('\n');
    Ok(s)
}

/// Contents of a results file as read back.
#[derive(Clone, Debug)]
pub struct Contents {
    /// The header.
    pub header: Header,
    /// Sessions in file order.
    pub sessions: Vec<Session>,
    /// Finished trials (first occurrence of each key), in file order.
    pub records: Vec<TrialRecord>,
    /// Byte length of the well-formed prefix (everything up to the last good line).
    pub good_len: u64,
    /// Torn bytes after the good prefix, if any.
    pub torn: Option<Vec<u8>>,
    /// Keys that appeared more than once (later copies ignored).
    pub duplicates: Vec<String>,
}

impl Contents {
    /// The spec text of the latest session that recorded one, else the header's: the plan the
    /// folder was last run with.
    pub fn current_spec_text(&self) -> &str {
        self.sessions
            .iter()
            .rev()
            .map(|s| s.spec_text.as_str())
            .find(|t| !t.is_empty())
            .unwrap_or(&self.header.spec_text)
    }

    /// The best-known RMSEs of the latest session that recorded them, else the header's
    /// (empty for files written before they were recorded).
    pub fn best_known(&self) -> &BTreeMap<String, crate::best_known::BestKnown> {
        self.sessions
            .iter()
            .rev()
            .map(|s| &s.best_known)
            .find(|b| !b.is_empty())
            .unwrap_or(&self.header.best_known)
    }
}

/// Parses a results file's bytes. A torn tail is reported, not an error; a corrupt line before
/// the last one is.
pub fn parse_contents(path: &Path, bytes: &[u8]) -> Result<Contents, StoreError> {
    let mut header = None;
    let mut sessions = Vec::new();
    let mut records = Vec::new();
    let mut duplicates = Vec::new();
    let mut seen = std::collections::HashSet::new();
    let mut pos = 0usize;
    let mut good_len = 0usize;
    let mut line_no = 0usize;
    let mut torn = None;
    while pos < bytes.len() {
        line_no += 1;
        let Some(nl) = bytes[pos..].iter().position(|&b| b == b'\n') else {
            // No newline: the write of this line was interrupted.
            torn = Some(bytes[pos..].to_vec());
            break;
        };
        let end = pos + nl;
        let is_last = end + 1 >= bytes.len();
        let text = String::from_utf8_lossy(&bytes[pos..end]);
        if text.trim().is_empty() {
            pos = end + 1;
            good_len = pos;
            continue;
        }
        match decode_line(&text) {
            Ok(Line::Header(h)) if header.is_none() => {
                if h.format > FORMAT_VERSION {
                    return Err(StoreError::Version {
                        path: path.to_path_buf(),
                        found: h.format,
                    });
                }
                header = Some(h)
            }
            Ok(_) if header.is_none() => {
                return Err(StoreError::MissingHeader {
                    path: path.to_path_buf(),
                });
            }
            Ok(Line::Header(_)) => {
                return Err(StoreError::Corrupt {
                    path: path.to_path_buf(),
                    line: line_no,
                    message: "a second header line".into(),
                });
            }
            Ok(Line::Session(s)) => sessions.push(s),
            Ok(Line::Trial(r)) => {
                if seen.insert(r.key.clone()) {
                    records.push(r);
                } else {
                    duplicates.push(r.key);
                }
            }
            Err(e) if is_last => {
                // A complete but unparsable last line can only come from an interrupted write
                // that happened to end at a newline: treat it as torn.
                let _ = e;
                torn = Some(bytes[pos..].to_vec());
                break;
            }
            Err(e) => {
                return Err(StoreError::Corrupt {
                    path: path.to_path_buf(),
                    line: line_no,
                    message: e.to_string(),
                });
            }
        }
        pos = end + 1;
        good_len = pos;
    }
    let header = header.ok_or_else(|| StoreError::MissingHeader {
        path: path.to_path_buf(),
    })?;
    Ok(Contents {
        header,
        sessions,
        records,
        good_len: good_len as u64,
        torn,
        duplicates,
    })
}

/// The results file of a folder: `trials.jsonl`, or the packed `trials.jsonl.gz` when only that
/// exists.
pub fn results_file(dir: &Path) -> PathBuf {
    let plain = dir.join(TRIALS_FILE);
    let packed = dir.join(PACKED_TRIALS_FILE);
    if !plain.exists() && packed.exists() {
        packed
    } else {
        plain
    }
}

fn is_packed(path: &Path) -> bool {
    path.extension().is_some_and(|e| e == "gz")
}

/// The results file of a folder as [`results_file`]. When both the plain and the packed file
/// exist, the plain one is used only if it starts with the packed one's content (a `run`
/// unpacked it and appended); otherwise the packed file holds results the plain one lacks, and
/// the folder is refused ([`StoreError::BothPresent`]) rather than one of them ignored.
pub fn results_file_checked(dir: &Path) -> Result<PathBuf, StoreError> {
    let plain = dir.join(TRIALS_FILE);
    let packed = dir.join(PACKED_TRIALS_FILE);
    if !(plain.exists() && packed.exists()) {
        return Ok(results_file(dir));
    }
    let unpacked = read_maybe_packed(&packed)?;
    let mut start = Vec::new();
    crate::input_file::open_regular(&plain, MAX_RESULTS_BYTES, RESULTS)
        .and_then(|f| f.take(unpacked.len() as u64).read_to_end(&mut start))
        .map_err(io_err(&plain))?;
    if start == unpacked {
        Ok(plain)
    } else {
        Err(StoreError::BothPresent {
            dir: dir.to_path_buf(),
        })
    }
}

const RESULTS: &str = "a results file (trials.jsonl)";

/// Reads a file, unpacking it when its name ends in `.gz`. Only regular files are read, each
/// up to [`MAX_RESULTS_BYTES`] (see [`crate::input_file`]).
fn read_maybe_packed(path: &Path) -> Result<Vec<u8>, StoreError> {
    use crate::input_file::{open_regular, read_regular};
    if !is_packed(path) {
        return read_regular(path, MAX_RESULTS_BYTES, RESULTS).map_err(io_err(path));
    }
    let file = open_regular(path, MAX_RESULTS_BYTES, RESULTS).map_err(io_err(path))?;
    let mut bytes = Vec::new();
    flate2::read::GzDecoder::new(std::io::BufReader::new(file))
        .take(MAX_RESULTS_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(io_err(path))?;
    if bytes.len() as u64 > MAX_RESULTS_BYTES {
        return Err(StoreError::TooLarge {
            path: path.to_path_buf(),
        });
    }
    Ok(bytes)
}

/// Reads a results file, `<dir>/trials.jsonl`, or (when only that exists) the packed
/// `<dir>/trials.jsonl.gz`, without modifying anything; a torn tail is ignored.
pub fn read_results(path: &Path) -> Result<Contents, StoreError> {
    let file = if path.is_dir() {
        results_file_checked(path)?
    } else {
        path.to_path_buf()
    };
    let bytes = read_maybe_packed(&file)?;
    parse_contents(&file, &bytes)
}

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
            .map_err(io_err(&path))?;
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

impl ResultStore {
    /// Opens `<dir>/trials.jsonl` for `header`'s spec: creates it, resumes it (same
    /// fingerprint), or refuses it (different fingerprint) unless `fresh` moves it aside.
    /// Writes a session line for this start.
    pub fn open(dir: &Path, header: Header, fresh: bool) -> Result<Opened, StoreError> {
        std::fs::create_dir_all(dir).map_err(io_err(dir))?;
        let lock = DirLock::acquire(dir)?;
        let path = dir.join(TRIALS_FILE);
        let packed = dir.join(PACKED_TRIALS_FILE);
        for p in [&path, &packed] {
            crate::input_file::check_regular_if_present(p, RESULTS).map_err(io_err(p))?;
        }
        if !fresh {
            results_file_checked(dir)?;
        }
        let mut notes = Vec::new();
        let mut records = Vec::new();
        if fresh {
            for p in [&path, &packed] {
                if p.exists() {
                    let aside = aside_path(p, "old");
                    std::fs::rename(p, &aside).map_err(io_err(p))?;
                    notes.push(format!("moved the old results to {}", aside.display()));
                }
            }
        } else if !path.exists() && packed.exists() {
            let bytes = read_maybe_packed(&packed)?;
            write_atomic(&path, &bytes).map_err(io_err(&path))?;
            notes.push(format!(
                "unpacked {} into {} to resume (the packed copy is kept)",
                packed.display(),
                path.display()
            ));
        }
        let file = if path.exists() {
            let mut file = OpenOptions::new()
                .read(true)
                .write(true)
                .open(&path)
                .map_err(io_err(&path))?;
            let mut bytes = Vec::new();
            file.read_to_end(&mut bytes).map_err(io_err(&path))?;
            let contents = match parse_contents(&path, &bytes) {
                Err(StoreError::MissingHeader { .. }) if !bytes.contains(&b'\n') => {
                    // Killed while writing the header: nothing of value; keep the bytes anyway.
                    None
                }
                other => Some(other?),
            };
            match contents {
                None => {
                    drop(file);
                    let aside = aside_path(&path, "torn");
                    std::fs::rename(&path, &aside).map_err(io_err(&path))?;
                    notes.push(format!(
                        "results file had only a torn header; moved to {}",
                        aside.display()
                    ));
                    Self::create(&path, &header)?
                }
                Some(c) => {
                    if c.header.fingerprint != header.fingerprint {
                        return Err(StoreError::FingerprintMismatch {
                            path,
                            found: c.header.fingerprint,
                            expected: header.fingerprint,
                        });
                    }
                    check_same_data(&path, &c.header, &header)?;
                    if let Some(torn) = &c.torn {
                        let aside = aside_path(&path, "torn");
                        std::fs::write(&aside, torn).map_err(io_err(&aside))?;
                        file.set_len(c.good_len).map_err(io_err(&path))?;
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
                    file.sync_data().map_err(io_err(&path))?;
                    drop(file);
                    records = c.records;
                    // Append mode: every write lands at the current end of the file.
                    OpenOptions::new()
                        .append(true)
                        .open(&path)
                        .map_err(io_err(&path))?
                }
            }
        } else {
            Self::create(&path, &header)?
        };
        let store = ResultStore {
            path,
            file: Mutex::new(file),
            _lock: lock,
        };
        store.write_line(&Line::Session(Session {
            started_unix: unix_now(),
            machine: header.machine.clone(),
            trials_present: records.len(),
            spec_text: header.spec_text.clone(),
            program_version: crate::PROGRAM_VERSION.to_string(),
            kernel: header.kernel.clone(),
            best_known: header.best_known.clone(),
        }))?;
        Ok(Opened {
            store,
            records,
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

pub use brdf_graphics::files::write_atomic;

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

#[cfg(test)]
mod tests {
    use super::*;
    use sls::{EvalCounts, Stamp, StopReason, TracePoint};

    fn header(fp: &str) -> Header {
        Header {
            format: FORMAT_VERSION,
            experiment: "t".into(),
            fingerprint: fp.into(),
            created_unix: 0,
            machine: MachineInfo::current(1),
            spec: serde_json::json!({"a": 1}),
            spec_text: String::new(),
            program_version: String::new(),
            kernel: String::new(),
            data_hashes: BTreeMap::new(),
            shard: None,
            best_known: BTreeMap::new(),
        }
    }

    fn record(i: u32, best: f64) -> TrialRecord {
        let at = Stamp {
            cpu_seconds: 0.5 + f64::from(i),
            wall_seconds: 0.6,
            evaluations: EvalCounts {
                residual_rows: 10,
                jacobian_rows: 20,
                rmse_rows: 30,
                ..EvalCounts::default()
            },
        };
        TrialRecord {
            key: TrialRecord::make_key("inst", "A", i),
            instance: "inst".into(),
            config: "A".into(),
            trial: i,
            seed: 42 + u64::from(i),
            target: 0.1,
            budget: Budget {
                cpu_seconds: Some(2.0),
                sample_evaluations: None,
            },
            result: TrialResult {
                stop: StopReason::Target,
                reached_at: Some(at),
                ended_at: at,
                best_rmse: best,
                best_x: vec![1.0, 2.0],
                trace: vec![TracePoint { at, rmse: 0.09 }],
                counters: vec![("restarts".into(), 3)],
            },
        }
    }

    #[test]
    fn round_trip_resume_torn_and_mismatch() {
        let dir = tempfile::tempdir().unwrap();
        let o = ResultStore::open(dir.path(), header("f1"), false).unwrap();
        assert!(o.records.is_empty());
        o.store.append(&record(0, 0.09)).unwrap();
        o.store.append(&record(1, f64::INFINITY)).unwrap();
        drop(o);
        // Simulate a kill in the middle of a third line.
        let path = dir.path().join(TRIALS_FILE);
        let full = encode_line(&path, &Line::Trial(record(2, 0.09))).unwrap();
        let mut f = OpenOptions::new().append(true).open(&path).unwrap();
        f.write_all(&full.as_bytes()[..full.len() / 2]).unwrap();
        drop(f);
        let c = read_results(dir.path()).unwrap();
        assert_eq!(c.records.len(), 2);
        assert!(c.torn.is_some());
        assert_eq!(c.records[0], record(0, 0.09));
        assert!(c.records[1].result.best_rmse.is_infinite());

        let o = ResultStore::open(dir.path(), header("f1"), false).unwrap();
        assert_eq!(o.records.len(), 2);
        assert!(o.notes.iter().any(|n| n.contains("torn")), "{:?}", o.notes);
        o.store.append(&record(2, 0.09)).unwrap();
        drop(o);
        let c = read_results(dir.path()).unwrap();
        assert_eq!(c.records.len(), 3);
        assert!(c.torn.is_none());
        assert_eq!(c.sessions.len(), 2);

        let err = ResultStore::open(dir.path(), header("f2"), false).unwrap_err();
        let msg = err.to_string();
        assert!(msg.contains("--fresh") && msg.contains("--out"), "{msg}");
        let o = ResultStore::open(dir.path(), header("f2"), true).unwrap();
        assert!(o.records.is_empty());
        let moved: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().contains(".old-"))
            .collect();
        assert_eq!(moved.len(), 1);
    }

    #[test]
    fn corrupt_middle_line_is_an_error() {
        let dir = tempfile::tempdir().unwrap();
        let o = ResultStore::open(dir.path(), header("f1"), false).unwrap();
        o.store.append(&record(0, 0.09)).unwrap();
        drop(o);
        let path = dir.path().join(TRIALS_FILE);
        let mut text = std::fs::read_to_string(&path).unwrap();
        text.push_str("{garbage\n");
        text.push_str(&encode_line(&path, &Line::Trial(record(1, 0.09))).unwrap());
        std::fs::write(&path, text).unwrap();
        let err = read_results(&path).unwrap_err();
        assert!(matches!(err, StoreError::Corrupt { line: 4, .. }), "{err}");
    }

    #[test]
    fn a_second_writer_is_refused_with_the_holders_pid() {
        let dir = tempfile::tempdir().unwrap();
        let first = ResultStore::open(dir.path(), header("f1"), false).unwrap();
        let err = ResultStore::open(dir.path(), header("f1"), false).unwrap_err();
        match &err {
            StoreError::Locked { pid, .. } => assert_eq!(*pid, Some(std::process::id())),
            other => panic!("expected Locked, got {other}"),
        }
        assert!(err.to_string().contains("in use"), "{err}");
        drop(first);
        ResultStore::open(dir.path(), header("f1"), false).unwrap();
    }

    #[test]
    fn packed_results_are_read_and_resumed_transparently() {
        let dir = tempfile::tempdir().unwrap();
        let o = ResultStore::open(dir.path(), header("f1"), false).unwrap();
        o.store.append(&record(0, 0.09)).unwrap();
        drop(o);
        let plain = dir.path().join(TRIALS_FILE);
        let packed = dir.path().join(PACKED_TRIALS_FILE);
        let mut gz = flate2::write::GzEncoder::new(
            File::create(&packed).unwrap(),
            flate2::Compression::default(),
        );
        gz.write_all(&std::fs::read(&plain).unwrap()).unwrap();
        gz.finish().unwrap();
        std::fs::remove_file(&plain).unwrap();

        let c = read_results(dir.path()).unwrap();
        assert_eq!(c.records, vec![record(0, 0.09)]);
        assert!(!plain.exists(), "reading must not unpack");

        let o = ResultStore::open(dir.path(), header("f1"), false).unwrap();
        assert_eq!(o.records, vec![record(0, 0.09)]);
        assert!(
            o.notes.iter().any(|n| n.contains("unpacked")),
            "{:?}",
            o.notes
        );
        o.store.append(&record(1, 0.09)).unwrap();
        drop(o);
        assert_eq!(read_results(dir.path()).unwrap().records.len(), 2);
        assert!(packed.exists(), "the packed copy is kept");
    }
}
