//! Flags of the cluster commands: `merge` (shard folders into one results folder) and `slurm`
//! (job array scripts for a sharded run). See docs/cluster.md.

use std::path::PathBuf;

use clap::Args;

/// `brdf-sls merge`.
#[derive(Args)]
pub struct MergeArgs {
    /// Output results folder (created if needed). Results already in it are kept and merged
    /// with the inputs, so merging again is harmless.
    pub out: PathBuf,
    /// Shard results folders (or trials.jsonl[.gz] files) to merge, e.g. runs/x/shard-*-of-4.
    #[arg(required = true, value_name = "SHARD_DIR")]
    pub shards: Vec<PathBuf>,
    /// Write the merge even when trials of the plan are missing (they are still listed, and
    /// the statistics say the results are partial). Without it, missing trials are an error
    /// (exit status 1) and nothing is written.
    #[arg(long)]
    pub allow_partial: bool,
    /// Skip the plots (statistics are still written).
    #[arg(long)]
    pub no_plots: bool,
}

/// `brdf-sls slurm`.
#[derive(Args)]
pub struct SlurmArgs {
    /// Experiment spec (TOML).
    pub spec: PathBuf,
    /// Number of shards = array tasks (each runs `run --shard K/N`, K = SLURM_ARRAY_TASK_ID).
    #[arg(long, value_name = "N")]
    pub shards: u32,
    /// Slurm partition (default: the cluster's default partition).
    #[arg(long)]
    pub partition: Option<String>,
    /// Wall-time limit per array task, in any form sbatch accepts (e.g. 30, 2:00:00, 1-0).
    /// Default: the partition's.
    #[arg(long)]
    pub time: Option<String>,
    /// CPUs per array task; the task runs that many worker threads.
    #[arg(long, default_value_t = 1, value_name = "C")]
    pub cpus_per_task: u32,
    /// Memory per array task, in any form sbatch accepts (e.g. 2G). Default: the partition's.
    #[arg(long, value_name = "M")]
    pub mem: Option<String>,
    /// Results folder: shards go to DIR/shard-K-of-N/, the merge to DIR, the scripts and
    /// logs to DIR/slurm/ (default: runs/<spec file stem>/).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Submit the array and the merge job (sbatch --parsable) and print their job IDs.
    /// Without it, only the scripts are written.
    #[arg(long)]
    pub submit: bool,
}
