//! Every stored trial must carry the seed the plan derives for its key, and the target its
//! instance ran to: a trial run (or edited) with another seed or target would be mixed silently
//! into results that claim to be seeded. A resume checks seeds; every command reading a
//! results folder checks both ([`check_stored`]).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::spec::{PlannedTrial, Spec};
use crate::store::TrialRecord;

/// A stored trial whose seed or target is not the plan's for its key.
#[derive(Debug, thiserror::Error)]
#[error(
    "{path}{}: trial `{key}` has {what} {stored}, but the plan's {what} for it is {planned}; \
     the results were edited or written by another plan. Refusing to use them: restore the \
     line, remove it (a `run` then runs the trial again), or start over with --fresh",
    line.map(|l| format!(":{l}")).unwrap_or_default()
)]
pub struct SeedMismatch {
    /// The results file.
    pub path: PathBuf,
    /// 1-based line of the trial, when it could be found again.
    pub line: Option<usize>,
    /// The trial's key.
    pub key: String,
    /// The key of the line that differs.
    pub what: Mismatched,
    /// The value stored with it.
    pub stored: String,
    /// The value the plan derives.
    pub planned: String,
}

/// Which key of a trial line differs from the plan.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mismatched {
    /// `seed`.
    Seed,
    /// `target`.
    Target,
}

impl std::fmt::Display for Mismatched {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Mismatched::Seed => "seed",
            Mismatched::Target => "target",
        })
    }
}

/// Checks each stored record of a key in `plan` (a shard of `spec`'s plan, or all of it)
/// against the seed it derives and the instance's run target, as [`check_stored`] does: a
/// resume never adds trials to results whose seeds or targets were edited.
pub fn check_resume(
    path: &Path,
    records: &[TrialRecord],
    spec: &Spec,
    plan: &[PlannedTrial],
) -> Result<(), SeedMismatch> {
    check(path, records, &[], &planned_with_targets(spec, plan))
}

/// Checks each stored record of a key in `plan` against the seed it derives, not the target
/// (`merge`, whose spec's relative targets are not resolved: the commands that read the merged
/// folder check them), with the 1-based line of each record when known (as in [`check_stored`]).
pub fn check_seeds_at(
    path: &Path,
    records: &[TrialRecord],
    lines: &[usize],
    plan: &[PlannedTrial],
) -> Result<(), SeedMismatch> {
    let planned: HashMap<&str, (u64, f64)> = plan
        .iter()
        .map(|t| (t.key.as_str(), (t.seed, f64::NAN)))
        .collect();
    check(path, records, lines, &planned)
}

/// Checks each stored record of a key in `spec`'s plan against the plan: the seed it derives
/// and the instance's run target (the lowest target, once relative targets are resolved; not
/// checked while unresolved). `lines[i]` is the 1-based line of `records[i]` when known
/// ([`crate::store::Contents::lines`]); otherwise the file is read again to name the line.
/// `stats`, `plot`, `report`, `compare`, `export` and `merge` read results through this, as a
/// resume checks seeds: results that claim to be seeded are never mixed with edited ones.
pub fn check_stored(
    path: &Path,
    records: &[TrialRecord],
    lines: &[usize],
    spec: &Spec,
) -> Result<(), SeedMismatch> {
    check(
        path,
        records,
        lines,
        &planned_with_targets(spec, &spec.trials_plan()),
    )
}

/// Each planned key's seed and run target (the lowest target, once relative targets are
/// resolved; NaN, which is not checked, while unresolved).
fn planned_with_targets<'a>(spec: &Spec, plan: &'a [PlannedTrial]) -> HashMap<&'a str, (u64, f64)> {
    plan.iter()
        .map(|t| {
            let inst = &spec.instances[t.instance];
            let resolved = inst.relative_targets.is_empty() || inst.best_known.is_some();
            let target = if resolved {
                inst.run_target()
            } else {
                f64::NAN
            };
            (t.key.as_str(), (t.seed, target))
        })
        .collect()
}

/// True when a stored target is the planned one: equal, or equal to 1e-9 relative (a
/// best-known RMSE recomputed for an older folder may differ in its last bits).
fn same_target(stored: f64, planned: f64) -> bool {
    planned.is_nan() || stored == planned || (stored - planned).abs() <= 1e-9 * planned.abs()
}

fn check(
    path: &Path,
    records: &[TrialRecord],
    lines: &[usize],
    planned: &HashMap<&str, (u64, f64)>,
) -> Result<(), SeedMismatch> {
    for (i, r) in records.iter().enumerate() {
        let Some(&(seed, target)) = planned.get(r.key.as_str()) else {
            continue;
        };
        let differs = if seed != r.seed {
            Some((Mismatched::Seed, r.seed.to_string(), seed.to_string()))
        } else if !same_target(r.target, target) {
            Some((Mismatched::Target, r.target.to_string(), target.to_string()))
        } else {
            None
        };
        if let Some((what, stored, planned)) = differs {
            return Err(SeedMismatch {
                path: path.to_path_buf(),
                line: lines
                    .get(i)
                    .copied()
                    .or_else(|| line_of_trial(path, &r.key)),
                key: r.key.clone(),
                what,
                stored,
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
