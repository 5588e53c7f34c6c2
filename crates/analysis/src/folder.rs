//! A results folder read whole for a page or a comparison: its stored records, the spec it was
//! last run with (targets resolved against the recorded best-known RMSEs) and what a reader
//! should be told about it (a torn line, missing trials).

use std::path::{Path, PathBuf};

use crate::analysis::{Analysis, ChartSet, plan_records};
use crate::report::{StoredSpecError, stored_spec};
use brdf_experiment::spec::Spec;
use brdf_experiment::store::{Contents, StoreError, TrialRecord, read_results, results_file};

/// Why a results folder could not be read.
#[derive(Debug, thiserror::Error)]
pub enum FolderError {
    /// No results file where one was expected (bad input).
    #[error(
        "{0}: no results here (expected a folder with trials.jsonl or trials.jsonl.gz, or such a file)"
    )]
    Missing(PathBuf),
    /// The results file could not be read or parsed.
    #[error(transparent)]
    Store(#[from] StoreError),
    /// The stored spec is missing or no longer valid (bad input).
    #[error("{dir}: {source}")]
    Spec {
        /// The folder.
        dir: PathBuf,
        /// Why.
        source: StoredSpecError,
    },
    /// A stored trial has another seed or target than the plan's (bad input).
    #[error(transparent)]
    Seed(#[from] brdf_experiment::seed_check::SeedMismatch),
    /// The best-known RMSE of a relative target could not be found.
    #[error("{dir}: finding the best-known RMSEs: {message}")]
    BestKnown {
        /// The folder.
        dir: PathBuf,
        /// Why.
        message: String,
    },
}

impl FolderError {
    /// True when the user named something that is not a usable results folder (exit status 2)
    /// rather than a failure while reading one.
    pub fn is_input_error(&self) -> bool {
        match self {
            FolderError::Missing(_) | FolderError::Spec { .. } | FolderError::Seed(_) => true,
            FolderError::Store(e) => matches!(
                e,
                StoreError::Corrupt { .. }
                    | StoreError::Invalid { .. }
                    | StoreError::BothPresent { .. }
            ),
            FolderError::BestKnown { .. } => false,
        }
    }
}

/// A results folder as read from disk.
#[derive(Clone, Debug)]
pub struct Folder {
    /// The folder (or results file) as given.
    pub dir: PathBuf,
    /// The spec the results were last run with, targets resolved.
    pub spec: Spec,
    /// Everything in the results file.
    pub contents: Contents,
    /// What the reader should know (torn line, partial results, notes on best-known RMSEs).
    pub notes: Vec<String>,
}

impl Folder {
    /// Reads `path`: a results folder or a `trials.jsonl(.gz)` file.
    pub fn read(path: &Path) -> Result<Folder, FolderError> {
        let file = if path.is_dir() {
            results_file(path)
        } else {
            path.to_path_buf()
        };
        if !file.is_file() {
            return Err(FolderError::Missing(path.to_path_buf()));
        }
        let contents = read_results(&file)?;
        let mut spec = stored_spec(&contents, path).map_err(|source| FolderError::Spec {
            dir: path.to_path_buf(),
            source,
        })?;
        let resolved = brdf_best_known::resolve(&mut spec, contents.best_known()).map_err(|e| {
            FolderError::BestKnown {
                dir: path.to_path_buf(),
                message: e.to_string(),
            }
        })?;
        brdf_experiment::seed_check::check_stored(
            &file,
            &contents.records,
            &contents.lines,
            &spec,
        )?;
        Ok(Folder::new(path, spec, contents, resolved.notes))
    }

    /// The folder a run just wrote, from what the run holds in memory (the results file is not
    /// read again): its header, sessions and the plan's records.
    pub fn from_run(dir: &Path, spec: Spec, outcome: &brdf_experiment::run::RunOutcome) -> Folder {
        let contents = Contents {
            header: outcome.header.clone(),
            sessions: outcome.sessions.clone(),
            records: outcome.records.clone(),
            lines: Vec::new(),
            good_len: 0,
            torn: None,
            duplicates: Vec::new(),
        };
        Folder::new(dir, spec, contents, Vec::new())
    }

    /// A folder of results already in memory (e.g. just written by a run with `spec`), with
    /// `notes` and those on a torn line and missing trials.
    pub fn new(dir: &Path, spec: Spec, contents: Contents, mut notes: Vec<String>) -> Folder {
        if let Some(t) = &contents.torn {
            notes.push(format!("a torn last line ({} bytes) was ignored", t.len()));
        }
        let mut folder = Folder {
            dir: dir.to_path_buf(),
            spec,
            contents,
            notes,
        };
        if let Some(p) = folder.partial_note() {
            folder.notes.push(p);
        }
        folder
    }

    /// The records of the spec's plan.
    pub fn records(&self) -> Vec<TrialRecord> {
        plan_records(&self.spec, &self.contents.records)
            .into_iter()
            .cloned()
            .collect()
    }

    /// The analysis of the folder's records with the charts its page shows.
    pub fn analysis(&self) -> Analysis {
        Analysis::new(&self.spec, &self.contents.records, ChartSet::Page)
    }

    /// The analysis of the folder's records without charts (statistics only).
    pub fn statistics(&self) -> Analysis {
        Analysis::new(&self.spec, &self.contents.records, ChartSet::None)
    }

    /// Trials present and planned.
    pub fn progress(&self) -> (usize, usize) {
        let present = plan_records(&self.spec, &self.contents.records).len();
        (present, self.spec.trials_plan().len())
    }

    /// "partial results: ..." when trials of the plan are missing.
    pub fn partial_note(&self) -> Option<String> {
        let (present, planned) = self.progress();
        (present < planned).then(|| {
            format!(
                "partial results: {present} of {planned} trials present (run the spec again to resume)"
            )
        })
    }
}
