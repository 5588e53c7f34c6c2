//! Flags of `brdf-sls trial` (irace's target-runner) and `brdf-sls tune`.

use std::path::PathBuf;

use brdf_experiment::spec::tune::CostKind;

/// `brdf-sls trial`: one trial, one number on standard output.
#[derive(clap::Args)]
#[command(
    after_help = "irace calls the target-runner as `<config-id> <instance-id> <seed> <instance> \
                  <switches...>`, e.g. `trial --spec tune.toml 7 2 1234 t2-s11 --phi 1.3 --rho0 25`. \
                  The instance is an instance name of the spec; the configuration is the tuned one \
                  (tune.algorithm, else the first) with the switches applied. Without a [tune] \
                  table, --cost and --cutoff default to `time` and [budget].cpu_seconds."
)]
pub struct TrialArgs {
    /// The experiment spec (TOML) holding the instances and the configuration.
    #[arg(long)]
    pub spec: PathBuf,
    /// What the cost measures (default: the spec's tune.cost, else time).
    #[arg(long, value_parser = crate::cli::values::choice::<CostKind>(CostKind::NAMES))]
    pub cost: Option<CostKind>,
    /// Per-trial cutoff in CPU seconds (time, rmse) or sample-evaluations (evaluations)
    /// (default: tune.cutoff, else from [budget]).
    #[arg(long, value_parser = crate::cli::values::finite)]
    pub cutoff: Option<f64>,
    /// Censored runs cost PENALTY * cutoff (default: tune.penalty, else 10: PAR10).
    #[arg(long, value_parser = crate::cli::values::finite)]
    pub penalty: Option<f64>,
    /// The configuration to start from, by label (default: tune.algorithm, else the first).
    #[arg(long)]
    pub config: Option<String>,
    /// irace's configuration id (recorded in errors only).
    pub config_id: String,
    /// irace's instance id (unused: the instance is named by INSTANCE).
    pub instance_id: String,
    /// The trial's seed.
    pub seed: u64,
    /// The instance's name in the spec.
    pub instance: String,
    /// Parameter switches `--NAME VALUE` (fields of the algorithm's configuration).
    #[arg(
        trailing_var_arg = true,
        allow_hyphen_values = true,
        value_name = "SWITCHES"
    )]
    pub switches: Vec<String>,
}

/// `brdf-sls tune`: tune a configuration with irace, then write a validation spec.
#[derive(clap::Args)]
pub struct TuneArgs {
    /// Experiment spec (TOML) with a [tune] table.
    pub spec: PathBuf,
    /// Output directory (default: runs/<spec file stem>/); irace's files go to its irace/.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Trials irace runs at once (default: tune.parallel, else the spec's threads, else all
    /// CPUs).
    #[arg(long)]
    pub parallel: Option<usize>,
    /// Override tune.budget (irace's maxExperiments).
    #[arg(long)]
    pub budget: Option<u64>,
    /// Write irace's files and print the command, without running irace.
    #[arg(long)]
    pub dry_run: bool,
    /// Read the elites from an existing irace output file instead of running irace.
    #[arg(long, value_name = "IRACE_OUT")]
    pub from_output: Option<PathBuf>,
    /// Copy irace's progress lines to standard error.
    #[arg(long)]
    pub verbose: bool,
}
