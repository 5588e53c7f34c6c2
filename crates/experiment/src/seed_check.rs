//! On resume, every stored trial must carry the seed the plan derives for its key: a trial run
//! (or edited) with another seed would be mixed silently into results that claim to be seeded.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::spec::PlannedTrial;
use crate::store::TrialRecord;

/// A stored trial whose seed is not the plan's seed for its key.
#[derive(Debug, thiserror::Error)]
#[error(
    "{path}{}: trial `{key}` has seed {stored}, but the plan's seed for it is {planned}; \
     the results were edited or written by another plan. Refusing to resume: restore the line, \
     remove it (the trial is then run again), or start over with --fresh",
    line.map(|l| format!(":{l}")).unwrap_or_default()
)]
pub struct SeedMismatch {
    /// The results file.
    pub path: PathBuf,
    /// 1-based line of the trial, when it could be found again.
    pub line: Option<usize>,
    /// The trial's key.
    pub key: String,
    /// The seed stored with it.
    pub stored: u64,
    /// The seed the plan derives.
    pub planned: u64,
}

/// Checks each stored record of a planned key against the plan's seed.
pub fn check_seeds(
    path: &Path,
    records: &[TrialRecord],
    plan: &[PlannedTrial],
) -> Result<(), SeedMismatch> {
    let seeds: HashMap<&str, u64> = plan.iter().map(|t| (t.key.as_str(), t.seed)).collect();
    for r in records {
        if let Some(&planned) = seeds.get(r.key.as_str())
            && planned != r.seed
        {
            return Err(SeedMismatch {
                path: path.to_path_buf(),
                line: line_of_trial(path, &r.key),
                key: r.key.clone(),
                stored: r.seed,
                planned,
            });
        }
    }
    Ok(())
}

/// The 1-based line of the first trial line with `key` (read again only to name it in the
/// error; `None` when the file cannot be read).
fn line_of_trial(path: &Path, key: &str) -> Option<usize> {
    let bytes =
        crate::input_file::read_regular(path, crate::store::MAX_RESULTS_BYTES, "results").ok()?;
    bytes
        .split(|&b| b == b'\n')
        .position(|line| {
            serde_json::from_slice::<serde_json::Value>(line).is_ok_and(|v| {
                v.get("type").and_then(|t| t.as_str()) == Some("trial")
                    && v.get("key").and_then(|k| k.as_str()) == Some(key)
            })
        })
        .map(|i| i + 1)
}
