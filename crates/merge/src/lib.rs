//! Merging results folders (typically the shards of one experiment, see [`brdf_experiment::shard`]) into
//! one normal results folder.
//!
//! [`merge`] reads every input (a folder or a `trials.jsonl[.gz]` file) and the output folder's
//! own results when it already has some, refuses inputs of a different spec (fingerprint) or
//! different data (data hashes), keeps the first copy of every trial key (inputs in the order
//! given, the output's existing results first) and reports the other copies, lists the trials of
//! the plan that no input holds, and writes the output's `trials.jsonl` in one atomic
//! replacement under the folder's lock ([`brdf_experiment::store::write_results`]).
//!
//! The written file is a function of the set of trials and sessions only: the header is the
//! first input's (without its shard), sessions are deduplicated and sorted by start time, trials
//! are in plan order. So merging twice, or merging a merged folder again, writes the same bytes.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};

use brdf_experiment::shard::Shard;
use brdf_experiment::spec::{Spec, SpecError};
use brdf_experiment::store::{
    Contents, DirLock, Header, LOCK_FILE, Session, StoreError, TrialRecord, read_results,
    results_file, write_results,
};

/// Errors of a merge.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    /// No input was given.
    #[error("nothing to merge: give at least one shard folder")]
    NoInputs,
    /// An input (or the output's existing results) could not be read.
    #[error("reading {path}: {source}")]
    Read {
        /// The input.
        path: PathBuf,
        /// The store's error.
        source: StoreError,
    },
    /// The output folder could not be locked or written.
    #[error(transparent)]
    Store(#[from] StoreError),
    /// An input holds results of a different spec.
    #[error(
        "{path} holds results of a different spec (fingerprint {found}) than {first} ({expected}); \
         refusing to merge them"
    )]
    FingerprintMismatch {
        /// The offending input.
        path: PathBuf,
        /// Its fingerprint.
        found: String,
        /// The first input.
        first: PathBuf,
        /// The first input's fingerprint.
        expected: String,
    },
    /// Two inputs ran an instance on different data.
    #[error(
        "{path}: instance `{instance}` was run on different data (hash {found}) than in {first} \
         ({expected}); refusing to merge them"
    )]
    DataMismatch {
        /// The offending input.
        path: PathBuf,
        /// The instance.
        instance: String,
        /// Its data hash there.
        found: String,
        /// The first input that recorded this instance.
        first: PathBuf,
        /// The hash there.
        expected: String,
    },
    /// An input's trial has another seed than the plan's for its key.
    #[error(transparent)]
    Seed(#[from] brdf_experiment::seed_check::SeedMismatch),
    /// The stored spec text is missing or does not parse.
    #[error("{path}: the stored spec cannot be used: {message}")]
    Spec {
        /// The input whose spec text was used.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

impl MergeError {
    /// True when the error comes from the inputs given (wrong folders), not from running.
    pub fn is_input_error(&self) -> bool {
        matches!(
            self,
            MergeError::NoInputs
                | MergeError::FingerprintMismatch { .. }
                | MergeError::DataMismatch { .. }
                | MergeError::Spec { .. }
                | MergeError::Seed(_)
                | MergeError::Read {
                    source: StoreError::Io { .. }
                        | StoreError::MissingHeader { .. }
                        | StoreError::Invalid { .. }
                        | StoreError::Version { .. },
                    ..
                }
        )
    }
}

/// One input as read.
#[derive(Clone, Debug)]
pub struct Input {
    /// The folder or file given (or the output folder for its existing results).
    pub path: PathBuf,
    /// The shard its header records, if any.
    pub shard: Option<Shard>,
    /// Trial lines read from it (first copy of each key within the file).
    pub trials: usize,
    /// True for the output folder's own results (present before this merge).
    pub existing_output: bool,
}

/// A trial key found more than once; the first copy was kept.
#[derive(Clone, Debug, PartialEq)]
pub struct Duplicate {
    /// The trial key.
    pub key: String,
    /// Where the kept copy came from.
    pub kept_from: PathBuf,
    /// Where the dropped copy came from.
    pub dropped_from: PathBuf,
    /// True when both copies have the same outcome (seed, stop reason, best RMSE bits,
    /// evaluations); false when they differ (e.g. under a CPU-time budget).
    pub same_outcome: bool,
}

/// A trial of the plan that no input holds.
#[derive(Clone, Debug, PartialEq)]
pub struct Missing {
    /// The trial key.
    pub key: String,
    /// The trial's seed.
    pub seed: u64,
    /// The shard that should have run it, when the inputs are shards (of one shard count).
    pub shard: Option<Shard>,
}

/// What a merge found and did.
#[derive(Debug)]
pub struct MergeOutcome {
    /// The spec of the merged results (the latest session's spec text).
    pub spec: Spec,
    /// The merged header.
    pub header: Header,
    /// The merged sessions (deduplicated, by start time).
    pub sessions: Vec<Session>,
    /// The merged trials, in plan order.
    pub records: Vec<TrialRecord>,
    /// The inputs, in the order read.
    pub inputs: Vec<Input>,
    /// Copies dropped (a trial key seen again in another input or in the same one).
    pub duplicates: Vec<Duplicate>,
    /// Trials of the plan that no input holds.
    pub missing: Vec<Missing>,
    /// Trials of the inputs that are not in the plan (dropped).
    pub outside_plan: usize,
    /// Warnings worth showing (shards still being written, different kernels or versions).
    pub notes: Vec<String>,
    /// The results file written, or `None` when trials were missing and partial merges were
    /// not allowed (nothing was written then).
    pub written: Option<PathBuf>,
}

impl MergeOutcome {
    /// Duplicates of trials the output already held before this merge (a repeated merge).
    pub fn already_present(&self) -> usize {
        let existing: BTreeSet<&Path> = self
            .inputs
            .iter()
            .filter(|i| i.existing_output)
            .map(|i| i.path.as_path())
            .collect();
        self.duplicates
            .iter()
            .filter(|d| existing.contains(d.kept_from.as_path()))
            .count()
    }
}

fn same_outcome(a: &TrialRecord, b: &TrialRecord) -> bool {
    a.seed == b.seed
        && a.result.stop == b.result.stop
        && a.result.best_rmse.to_bits() == b.result.best_rmse.to_bits()
        && a.result.ended_at.evaluations == b.result.ended_at.evaluations
        && a.result.reached_at.map(|s| s.evaluations) == b.result.reached_at.map(|s| s.evaluations)
}

fn same_dir(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// Warns when an input folder is locked by a running process (its results may grow).
fn still_running(dir: &Path) -> Option<String> {
    if !dir.is_dir() || !dir.join(LOCK_FILE).exists() {
        return None;
    }
    match DirLock::acquire(dir) {
        Err(StoreError::Locked { pid, .. }) => Some(format!(
            "{} is still being written{}; its later trials are not in this merge",
            dir.display(),
            pid.map(|p| format!(" by PID {p}")).unwrap_or_default()
        )),
        _ => None,
    }
}

/// Merges `inputs` (and `out`'s existing results, if any) into `out`. Writes nothing when a
/// trial of the plan is missing unless `allow_partial`; see the module docs.
pub fn merge(
    out: &Path,
    inputs: &[PathBuf],
    allow_partial: bool,
) -> Result<MergeOutcome, MergeError> {
    if inputs.is_empty() {
        return Err(MergeError::NoInputs);
    }
    std::fs::create_dir_all(out).map_err(|source| StoreError::Io {
        path: out.to_path_buf(),
        source,
    })?;
    let lock = DirLock::acquire(out)?;
    let mut notes = Vec::new();
    let mut sources: Vec<(Input, Contents)> = Vec::new();
    let read = |path: &Path| {
        read_results(path).map_err(|source| MergeError::Read {
            path: path.to_path_buf(),
            source,
        })
    };
    if results_file(out).exists() {
        let c = read(out)?;
        sources.push((
            Input {
                path: out.to_path_buf(),
                shard: c.header.shard,
                trials: c.records.len(),
                existing_output: true,
            },
            c,
        ));
    }
    for path in inputs {
        if same_dir(path, out) {
            // The output's own results were read above (or there are none).
            continue;
        }
        if let Some(n) = still_running(path) {
            notes.push(n);
        }
        let c = read(path)?;
        if let Some(t) = &c.torn {
            notes.push(format!(
                "{}: ignored a torn last line ({} bytes)",
                path.display(),
                t.len()
            ));
        }
        sources.push((
            Input {
                path: path.clone(),
                shard: c.header.shard,
                trials: c.records.len(),
                existing_output: false,
            },
            c,
        ));
    }
    if sources.is_empty() {
        return Err(MergeError::NoInputs);
    }

    // Same spec and same data everywhere.
    let (first_input, first) = &sources[0];
    let mut data_hashes: BTreeMap<String, (String, PathBuf)> = BTreeMap::new();
    for (input, c) in &sources {
        if c.header.fingerprint != first.header.fingerprint {
            return Err(MergeError::FingerprintMismatch {
                path: input.path.clone(),
                found: c.header.fingerprint.clone(),
                first: first_input.path.clone(),
                expected: first.header.fingerprint.clone(),
            });
        }
        for (instance, hash) in &c.header.data_hashes {
            match data_hashes.get(instance) {
                Some((h, p)) if h != hash => {
                    return Err(MergeError::DataMismatch {
                        path: input.path.clone(),
                        instance: instance.clone(),
                        found: hash.clone(),
                        first: p.clone(),
                        expected: h.clone(),
                    });
                }
                Some(_) => {}
                None => {
                    data_hashes.insert(instance.clone(), (hash.clone(), input.path.clone()));
                }
            }
        }
    }
    let kernels: BTreeSet<&str> = sources
        .iter()
        .flat_map(|(_, c)| {
            std::iter::once(c.header.kernel.as_str())
                .chain(c.sessions.iter().map(|s| s.kernel.as_str()))
        })
        .filter(|k| !k.is_empty())
        .collect();
    if kernels.len() > 1 {
        notes.push(format!(
            "the inputs were evaluated with different kernels ({}); results agree to rounding, not bit for bit",
            kernels.into_iter().collect::<Vec<_>>().join(", ")
        ));
    }
    let versions: BTreeSet<&str> = sources
        .iter()
        .map(|(_, c)| c.header.program_version.as_str())
        .filter(|v| !v.is_empty())
        .collect();
    if versions.len() > 1 {
        notes.push(format!(
            "the inputs were written by different program versions ({})",
            versions.into_iter().collect::<Vec<_>>().join(", ")
        ));
    }

    // Sessions: deduplicated, by start time (stable), so the merged file does not depend on
    // the order of the inputs and a re-merge adds nothing.
    let mut sessions: Vec<Session> = Vec::new();
    for (_, c) in &sources {
        for s in &c.sessions {
            if !sessions.contains(s) {
                sessions.push(s.clone());
            }
        }
    }
    sessions.sort_by_key(|s| s.started_unix);

    // The spec: the latest session's text (what `stats` on the merged folder will use).
    let mut header = first.header.clone();
    header.shard = None;
    header.data_hashes = data_hashes.into_iter().map(|(k, (h, _))| (k, h)).collect();
    let spec_text = sessions
        .iter()
        .rev()
        .map(|s| s.spec_text.as_str())
        .find(|t| !t.is_empty())
        .unwrap_or(&header.spec_text)
        .to_string();
    let spec_origin = &first_input.path;
    if spec_text.is_empty() {
        return Err(MergeError::Spec {
            path: spec_origin.clone(),
            message: "the results hold no spec text (written by a very old version)".into(),
        });
    }
    let base_dir = if spec_origin.is_dir() {
        spec_origin.clone()
    } else {
        spec_origin
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default()
    };
    let spec = Spec::parse(
        &spec_text,
        &format!("{} (stored spec)", spec_origin.display()),
        &header.experiment,
        &base_dir,
    )
    .map_err(|e: SpecError| MergeError::Spec {
        path: spec_origin.clone(),
        message: e.to_string(),
    })?;

    // Trials: first copy of each key, in plan order.
    let plan = spec.trials_plan();
    // Every input's trials carry the plan's seeds, as a resume requires (targets are checked
    // by the commands that resolve them: a relative target needs the best-known RMSE).
    for (input, c) in &sources {
        let file = if input.path.is_dir() {
            results_file(&input.path)
        } else {
            input.path.clone()
        };
        brdf_experiment::seed_check::check_seeds_at(&file, &c.records, &c.lines, &plan)?;
    }
    let position: HashMap<&str, usize> = plan
        .iter()
        .enumerate()
        .map(|(i, t)| (t.key.as_str(), i))
        .collect();
    let mut kept: HashMap<String, (TrialRecord, PathBuf)> = HashMap::new();
    let mut duplicates = Vec::new();
    let mut outside_plan = 0;
    for (input, c) in &sources {
        for r in &c.records {
            if !position.contains_key(r.key.as_str()) {
                outside_plan += 1;
                continue;
            }
            match kept.get(&r.key) {
                Some((k, from)) => duplicates.push(Duplicate {
                    key: r.key.clone(),
                    kept_from: from.clone(),
                    dropped_from: input.path.clone(),
                    same_outcome: same_outcome(k, r),
                }),
                None => {
                    kept.insert(r.key.clone(), (r.clone(), input.path.clone()));
                }
            }
        }
        // A file's own repeated keys were dropped when reading it; report them too.
        for key in &c.duplicates {
            duplicates.push(Duplicate {
                key: key.clone(),
                kept_from: input.path.clone(),
                dropped_from: input.path.clone(),
                same_outcome: true,
            });
        }
    }
    let mut records: Vec<TrialRecord> = kept.into_values().map(|(r, _)| r).collect();
    records.sort_by_key(|r| position[r.key.as_str()]);

    // Missing trials, attributed to a shard when all shard inputs agree on the count.
    let counts: BTreeSet<u32> = sources
        .iter()
        .filter_map(|(i, _)| i.shard.map(|s| s.count))
        .collect();
    let count = (counts.len() == 1)
        .then(|| counts.into_iter().next())
        .flatten();
    let present: BTreeSet<&str> = records.iter().map(|r| r.key.as_str()).collect();
    let missing: Vec<Missing> = plan
        .iter()
        .filter(|t| !present.contains(t.key.as_str()))
        .map(|t| Missing {
            key: t.key.clone(),
            seed: t.seed,
            shard: count.map(|n| Shard {
                index: Shard::owner(t, n),
                count: n,
            }),
        })
        .collect();

    let inputs_read: Vec<Input> = sources.into_iter().map(|(i, _)| i).collect();
    let written = if missing.is_empty() || allow_partial {
        Some(write_results(out, &lock, &header, &sessions, &records)?)
    } else {
        None
    };
    drop(lock);
    Ok(MergeOutcome {
        spec,
        header,
        sessions,
        records,
        inputs: inputs_read,
        duplicates,
        missing,
        outside_plan,
        notes,
        written,
    })
}
