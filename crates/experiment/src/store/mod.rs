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
//! One writer at a time: [`LockedFolder::lock`] takes an advisory lock on `<out>/.lock` (which
//! holds the writer's PID) and only then reads the results file, once; the store opened on it
//! ([`ResultStore::open_locked`], or [`ResultStore::open`] doing both) keeps the lock for as
//! long as it lives, so a second run on the same folder fails at once with
//! [`StoreError::Locked`] naming the holder instead of interleaving lines. Trial lines are
//! written through a file opened in append mode.
//!
//! Packed results: the repository commits results as `trials.jsonl.gz`. [`read_results`] reads
//! the packed file when the plain one is absent, and [`ResultStore::open`] unpacks it into
//! `trials.jsonl` (keeping the packed copy) before resuming, so nobody has to unpack by hand.
//! When both exist, the plain file is the results if it starts with the packed file's complete
//! lines (a torn last line of the packed file is not results: the resume cut it off); otherwise
//! every command refuses the folder ([`StoreError::BothPresent`]).

use std::collections::BTreeMap;
use std::io::Read;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use sls::{Budget, TrialResult};

use crate::machine::MachineInfo;

/// Version of the `trials.jsonl` layout.
pub const FORMAT_VERSION: u32 = 1;

/// Name of the results file inside the output directory.
pub const TRIALS_FILE: &str = "trials.jsonl";

/// Name of the packed (gzip) results file, as committed to the repository.
pub const PACKED_TRIALS_FILE: &str = "trials.jsonl.gz";

/// Name of the lock file inside the output directory (holds the writer's PID).
pub const LOCK_FILE: &str = ".lock";

/// Largest results file read back (unpacked), against a corrupt or hostile `.gz` and to bound
/// memory: 4 GiB. Files are parsed as they are read; what stays in memory is the parsed
/// trials, about half the file's size (docs/results-format.md has measurements).
pub const MAX_RESULTS_BYTES: u64 = 4 << 30;

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
    /// The results folder, or a file in it, cannot be created or written for want of
    /// permission (a read-only folder or file system): the message says where else to write,
    /// since a user in a read-only working folder otherwise gets only the system's error.
    #[error("{path}: {source}; {WRITE_ELSEWHERE}")]
    NotWritable {
        /// The file or directory involved.
        path: PathBuf,
        /// The underlying error (permission denied, read-only file system).
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
    /// A trial line parses but holds a value no run writes (a negative time).
    #[error("{path}:{line}: trial `{key}`: {message}; the file was not modified")]
    Invalid {
        /// The results file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// The trial's key.
        key: String,
        /// Which value, and what was expected.
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
    /// The results are larger than [`MAX_RESULTS_BYTES`] (once unpacked).
    #[error(
        "{path}: holds more than {MAX_RESULTS_BYTES} bytes of results (MAX_RESULTS_BYTES, once \
         unpacked); refusing to read it (split the experiment into shards, see docs/cluster.md)"
    )]
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

/// The hint of [`StoreError::NotWritable`].
pub const WRITE_ELSEWHERE: &str =
    "cannot write here (a read-only folder?): use --out DIR to write elsewhere";

/// True when `e` says the path may not be written (permission denied, read-only file system).
pub fn is_not_writable(e: &std::io::Error) -> bool {
    matches!(
        e.kind(),
        std::io::ErrorKind::PermissionDenied | std::io::ErrorKind::ReadOnlyFilesystem
    )
}

/// The error of creating or writing `path`: [`StoreError::NotWritable`] (with the hint to use
/// `--out`) when the path may not be written, else [`StoreError::Io`].
pub fn write_error(path: &Path, source: std::io::Error) -> StoreError {
    let path = path.to_path_buf();
    if is_not_writable(&source) {
        StoreError::NotWritable { path, source }
    } else {
        StoreError::Io { path, source }
    }
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
    /// The solver's kernel of the first session (empty in older files).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub solver_kernel: String,
    /// Instance name -> hash of its data ([`crate::seed::data_hash`]); a resume on different
    /// data is refused. Empty in older files (then nothing is checked).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub data_hashes: BTreeMap<String, String>,
    /// The shard of the plan this file holds (`brdf-sls run --shard K/N`); `None` for a whole
    /// plan, a merged folder, and older files.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<crate::shard::Shard>,
    /// Instance name -> best-known RMSE when the file was created (the `brdf-best-known` crate).
    /// Empty in older files.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub best_known: BTreeMap<String, crate::best_known_record::BestKnown>,
    /// The program that ran the first session when it named itself (a custom binary's name
    /// and version, [`crate::run::set_program`]); empty otherwise.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub program: String,
    /// Kind -> hash of its settings schema, for kinds that are not built in
    /// ([`crate::run::schemas_of`]).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub schemas: BTreeMap<String, String>,
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
    /// The solver's kernel of this session (empty in older files).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub solver_kernel: String,
    /// Instance name -> best-known RMSE this session used (empty in older files).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub best_known: BTreeMap<String, crate::best_known_record::BestKnown>,
    /// The program of this session (as in [`Header::program`]).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub program: String,
    /// The settings schemas of this session (as in [`Header::schemas`]).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub schemas: BTreeMap<String, String>,
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
        crate::trial_key::trial_key(instance, config, trial)
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
    /// The 1-based line of each of `records` (empty for contents not read from a file).
    pub lines: Vec<usize>,
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
    pub fn best_known(&self) -> &BTreeMap<String, crate::best_known_record::BestKnown> {
        self.sessions
            .iter()
            .rev()
            .map(|s| &s.best_known)
            .find(|b| !b.is_empty())
            .unwrap_or(&self.header.best_known)
    }
}

/// The first time of `r` below 0 (a run measures every time from the trial's start), named
/// by its key in the line, with what was expected.
fn negative_time(r: &TrialRecord) -> Option<String> {
    let res = &r.result;
    let stamps = [("result.ended_at", &res.ended_at)]
        .into_iter()
        .chain(res.reached_at.as_ref().map(|s| ("result.reached_at", s)))
        .chain(res.trace.iter().map(|p| ("result.trace[].at", &p.at)));
    for (name, s) in stamps {
        for (field, v) in [
            ("cpu_seconds", s.cpu_seconds),
            ("wall_seconds", s.wall_seconds),
        ] {
            if v < 0.0 {
                return Some(format!(
                    "`{name}.{field}` is {v}, expected a time of at least 0 seconds"
                ));
            }
        }
    }
    let b = &r.budget;
    match b.cpu_seconds {
        Some(v) if v < 0.0 => Some(format!(
            "`budget.cpu_seconds` is {v}, expected a budget of at least 0 seconds"
        )),
        _ => None,
    }
}

/// Parses a results file's bytes. A torn tail is reported, not an error; a corrupt line before
/// the last one is.
pub fn parse_contents(path: &Path, bytes: &[u8]) -> Result<Contents, StoreError> {
    parse_reader(path, bytes)
}

/// Parses a results file line by line from `reader` (as [`parse_contents`]), holding one line
/// at a time besides what it returns: a large file is never held whole in memory.
pub fn parse_reader(
    path: &Path,
    mut reader: impl std::io::BufRead,
) -> Result<Contents, StoreError> {
    let mut header = None;
    let mut sessions = Vec::new();
    let mut records = Vec::new();
    let mut lines = Vec::new();
    let mut duplicates = Vec::new();
    let mut seen = std::collections::HashSet::new();
    let mut good_len = 0u64;
    let mut line_no = 0usize;
    let mut torn = None;
    let mut buf = Vec::new();
    loop {
        buf.clear();
        let n = reader.read_until(b'\n', &mut buf).map_err(io_err(path))?;
        if n == 0 {
            break;
        }
        line_no += 1;
        if buf.last() != Some(&b'\n') {
            // No newline: the write of this line was interrupted.
            torn = Some(std::mem::take(&mut buf));
            break;
        }
        let is_last = reader.fill_buf().map_err(io_err(path))?.is_empty();
        let text = String::from_utf8_lossy(&buf[..n - 1]);
        if text.trim().is_empty() {
            good_len += n as u64;
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
                if let Some(message) = negative_time(&r) {
                    return Err(StoreError::Invalid {
                        path: path.to_path_buf(),
                        line: line_no,
                        key: r.key,
                        message,
                    });
                }
                if seen.insert(r.key.clone()) {
                    records.push(r);
                    lines.push(line_no);
                } else {
                    duplicates.push(r.key);
                }
            }
            Err(e) if is_last => {
                // A complete but unparsable last line can only come from an interrupted write
                // that happened to end at a newline: treat it as torn.
                let _ = e;
                torn = Some(std::mem::take(&mut buf));
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
        good_len += n as u64;
    }
    let header = header.ok_or_else(|| StoreError::MissingHeader {
        path: path.to_path_buf(),
    })?;
    Ok(Contents {
        header,
        sessions,
        records,
        lines,
        good_len,
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
    let mut unpacked = read_maybe_packed(&packed)?;
    // Only the packed file's complete lines are results: a `run` on a packed file with a torn
    // last line unpacks it and cuts that line off before appending (issue 45, item 4).
    let good = complete_prefix_len(&unpacked);
    unpacked.truncate(good);
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

/// Length of the part of a results file a resume keeps: everything before a torn last line
/// (bytes after the last newline, or a last line that does not parse), as [`parse_contents`]
/// reports it in [`Contents::good_len`].
fn complete_prefix_len(bytes: &[u8]) -> usize {
    let Some(last_nl) = bytes.iter().rposition(|&b| b == b'\n') else {
        return 0;
    };
    if last_nl + 1 < bytes.len() {
        // Bytes after the last newline: an interrupted write.
        return last_nl + 1;
    }
    let body = &bytes[..last_nl];
    let start = body.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
    let last = String::from_utf8_lossy(&body[start..]);
    if last.trim().is_empty() || decode_line(&last).is_ok() {
        last_nl + 1
    } else {
        start
    }
}

const RESULTS: &str = "a results file (trials.jsonl)";

/// Reads a file, unpacking it when its name ends in `.gz`. Only regular files are read, each
/// up to [`MAX_RESULTS_BYTES`] (see [`crate::input_file`]).
fn read_maybe_packed(path: &Path) -> Result<Vec<u8>, StoreError> {
    use crate::input_file::{open_regular, read_regular};
    folder::count_read();
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
/// `<dir>/trials.jsonl.gz`, without modifying anything; a torn tail is ignored. The file is
/// parsed as it is read (never held whole in memory), up to [`MAX_RESULTS_BYTES`] unpacked.
pub fn read_results(path: &Path) -> Result<Contents, StoreError> {
    let file = if path.is_dir() {
        results_file_checked(path)?
    } else {
        path.to_path_buf()
    };
    stream_results(&file)
}

/// Parses `path` (unpacking a `.gz`) while reading it, refusing more than
/// [`MAX_RESULTS_BYTES`] of unpacked text ([`StoreError::TooLarge`]).
fn stream_results(path: &Path) -> Result<Contents, StoreError> {
    use std::io::BufReader;
    folder::count_read();
    let file =
        crate::input_file::open_regular(path, MAX_RESULTS_BYTES, RESULTS).map_err(io_err(path))?;
    let raw: Box<dyn Read> = if is_packed(path) {
        Box::new(flate2::read::GzDecoder::new(BufReader::new(file)))
    } else {
        Box::new(file)
    };
    let mut limited = BufReader::with_capacity(1 << 16, raw.take(MAX_RESULTS_BYTES + 1));
    let contents = parse_reader(path, &mut limited)?;
    if limited.into_inner().limit() == 0 {
        return Err(StoreError::TooLarge {
            path: path.to_path_buf(),
        });
    }
    Ok(contents)
}

mod folder;
mod writer;

pub use brdf_graphics::files::write_atomic;
pub use folder::{DirLock, LockedFolder, results_reads_on_this_thread};
pub use writer::{Opened, ResultStore, write_results};
