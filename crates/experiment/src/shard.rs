//! Shards: a deterministic split of an experiment's trial plan into `N` disjoint parts, so one
//! experiment can run as `N` independent processes (e.g. a Slurm job array) and be merged back
//! (the `brdf-merge` crate) into exactly the results of a single run.
//!
//! Shards are numbered from 1: shard `K/N` (`1 <= K <= N`) holds trial `t` of instance `i` and
//! configuration `c` (indices from 0, as in [`crate::spec::PlannedTrial`]) when
//! `(t + i + c) mod N == K - 1`. So the trials of every (instance, configuration) are dealt round
//! robin over the shards, each starting at a different shard: every shard gets an even share of
//! every configuration (also when `N` divides the number of configurations, where plain round
//! robin over plan positions would give each shard a single configuration), and raising `trials`
//! later never moves a trial to another shard. A trial keeps the seed it has in a single run:
//! shards only choose *which* trials a process runs, never what a trial does.
//!
//! Numbering from 1 matches a Slurm array declared as `--array=1-N`, so an array task passes
//! `--shard $SLURM_ARRAY_TASK_ID/N` unchanged.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::spec::PlannedTrial;

/// Largest shard count accepted (a typo guard; a Slurm array is usually limited far below).
pub const MAX_SHARDS: u32 = 100_000;

/// One part `index`/`count` of a trial plan (1-based `index`, see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Shard {
    /// Which part, `1..=count`.
    pub index: u32,
    /// How many parts.
    pub count: u32,
}

/// A `K/N` text that is not a valid shard.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("shard `{text}`: {reason} (expected K/N with 1 <= K <= N, e.g. 2/4)")]
pub struct ShardParseError {
    /// The text given.
    pub text: String,
    /// What is wrong with it.
    pub reason: String,
}

impl Shard {
    /// Shard `index`/`count`, or an error when `index` is not in `1..=count` or `count` is 0
    /// or above [`MAX_SHARDS`].
    pub fn new(index: u32, count: u32) -> Result<Self, ShardParseError> {
        let err = |reason: String| ShardParseError {
            text: format!("{index}/{count}"),
            reason,
        };
        if count == 0 {
            return Err(err("N must be at least 1".into()));
        }
        if count > MAX_SHARDS {
            return Err(err(format!("N must be at most {MAX_SHARDS}")));
        }
        if index == 0 || index > count {
            return Err(err(format!("K must be between 1 and {count}")));
        }
        Ok(Shard { index, count })
    }

    /// True when `trial` belongs to this shard.
    pub fn contains(&self, trial: &PlannedTrial) -> bool {
        Self::owner(trial, self.count) == self.index
    }

    /// The shard (1-based index) among `count` shards that owns `trial`.
    pub fn owner(trial: &PlannedTrial, count: u32) -> u32 {
        let sum = u64::from(trial.trial) + trial.instance as u64 + trial.config as u64;
        (sum % u64::from(count.max(1))) as u32 + 1
    }

    /// This shard's trials of `plan` (the full plan, in plan order), in plan order.
    pub fn select(&self, plan: Vec<PlannedTrial>) -> Vec<PlannedTrial> {
        plan.into_iter().filter(|t| self.contains(t)).collect()
    }

    /// The folder name of this shard's results: `shard-K-of-N`.
    pub fn dir_name(&self) -> String {
        format!("shard-{}-of-{}", self.index, self.count)
    }

    /// All `count` shards, `1/count` to `count/count`.
    pub fn all(count: u32) -> Result<Vec<Shard>, ShardParseError> {
        (1..=count.max(1)).map(|k| Shard::new(k, count)).collect()
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for Shard {
    type Err = ShardParseError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let err = |reason: &str| ShardParseError {
            text: s.to_string(),
            reason: reason.to_string(),
        };
        let (k, n) = s.trim().split_once('/').ok_or_else(|| err("no `/`"))?;
        let k: u32 = k
            .trim()
            .parse()
            .map_err(|_| err("K is not a non-negative integer"))?;
        let n: u32 = n
            .trim()
            .parse()
            .map_err(|_| err("N is not a non-negative integer"))?;
        Shard::new(k, n).map_err(|e| ShardParseError {
            text: s.to_string(),
            reason: e.reason,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_and_display() {
        let s: Shard = "2/4".parse().unwrap();
        assert_eq!(s, Shard { index: 2, count: 4 });
        assert_eq!(s.to_string(), "2/4");
        assert_eq!(s.dir_name(), "shard-2-of-4");
        for bad in ["0/4", "5/4", "1/0", "x/2", "3", "1/2/3", "-1/2"] {
            let e = bad.parse::<Shard>().unwrap_err();
            assert!(e.to_string().contains(bad), "{e}");
        }
    }

    fn planned(instance: usize, config: usize, trial: u32) -> PlannedTrial {
        PlannedTrial {
            instance,
            config,
            trial,
            seed: 0,
            key: format!("{instance}/{config}/{trial}"),
        }
    }

    #[test]
    fn shards_partition_trials_and_balance_configurations() {
        for n in 1..7u32 {
            let shards = Shard::all(n).unwrap();
            // 2 instances x 3 configurations x 12 trials.
            let mut per_shard_config = vec![vec![0; 6]; n as usize];
            for i in 0..2 {
                for c in 0..3 {
                    for t in 0..12 {
                        let p = planned(i, c, t);
                        let owners: Vec<_> = shards.iter().filter(|s| s.contains(&p)).collect();
                        assert_eq!(owners.len(), 1, "{} of {n}", p.key);
                        assert_eq!(owners[0].index, Shard::owner(&p, n));
                        per_shard_config[owners[0].index as usize - 1][i * 3 + c] += 1;
                    }
                }
            }
            // 12 trials per group: each shard gets floor or ceil of 12 / n of every group.
            for counts in &per_shard_config {
                for &k in counts {
                    assert!(k == 12 / n || k == 12_u32.div_ceil(n), "{counts:?} for {n}");
                }
            }
        }
    }
}
