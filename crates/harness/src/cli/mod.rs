//! The command line: every flag of every command, and nothing else. The work lives in
//! [`crate::cmd`]; this module only declares arguments (clap derive) and the parsers of their
//! values ([`values`]).

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

mod cluster;
mod data;
mod graphics;
mod model;
mod report;
mod tune;
pub mod values;

pub use cluster::{MergeArgs, SlurmArgs};
pub use data::DataArgs;
pub use graphics::{PolarArgs, RenderArgs};
pub use model::{FitArgs, ParamArgs};
pub use report::{CompareArgs, CompletionsArgs, ManArgs, ReportArgs, VerdictMeasure};
pub use tune::{TrialArgs, TuneArgs};

use brdf_experiment::progress::ProgressMode;

/// `brdf-sls`: the top level.
#[derive(Parser)]
#[command(
    name = "brdf-sls",
    version = brdf_experiment::PROGRAM_VERSION,
    about = "Stochastic local search for Lafortune BRDF fitting: experiments, statistics, plots",
    long_about = "Stochastic local search for Lafortune BRDF fitting (Backer, Kimberley and \
Skrypnyk).\n\nStart with `brdf-sls run`: it runs the built-in default experiment (the paper's \
tuning instance, AED vs AERS vs RPLS, under a minute on 2 cores) and writes results, \
statistics, plots and report.html to runs/default/.\n\nEnvironment: BRDF_SLS_THREADS sets the \
default worker thread count of `run` (a --threads flag wins over it, it wins over the spec's \
`threads`).\n\nExit codes: 0 success (also when the output pipe \
closes early), 2 usage, spec or data errors, 1 runtime failures."
)]
pub struct Cli {
    /// The command to run.
    #[command(subcommand)]
    pub command: Command,
}

/// The commands.
#[derive(Subcommand)]
pub enum Command {
    /// Run (or resume) an experiment; without SPEC, the built-in default experiment.
    Run(RunArgs),
    /// Validate a spec and print the expanded plan without running anything.
    Check(CheckArgs),
    /// Redraw the plots (and statistics) from stored results without re-running trials.
    Plot(ResultsArgs),
    /// Recompute and print the statistics of stored results.
    Stats(ResultsArgs),
    /// Export stored results to another tool's format (`--format ioh`: IOHprofiler's JSON and
    /// .dat files, which IOHanalyzer and iohinspector load).
    Export(ExportArgs),
    /// Fit one data set with one algorithm and print the fitted parameters, RMSE and time.
    Fit(FitArgs),
    /// Write a synthetic instance to CSV (a named instance or parameters given as flags).
    Gen(GenArgs),
    /// Print the RMSE of given parameters on a data set.
    Eval(EvalArgs),
    /// Summarise a data set: count, value range, angle coverage, what the filters dropped.
    Info(InfoArgs),
    /// Render a BRDF on a flat square lit by a point light to a PNG (the paper's Figures 8, 12).
    Render(RenderArgs),
    /// Polar plots of measured data and fitted models in the plane of incidence (Figure 18).
    Polar(PolarArgs),
    /// Merge shard results folders (`run --shard K/N`) into one results folder.
    Merge(MergeArgs),
    /// Write (and with --submit, submit) Slurm job array scripts running an experiment as
    /// shards, and a merge job that runs after them.
    Slurm(SlurmArgs),
    /// One trial of one configuration on one instance with one seed; prints its cost (irace's
    /// target-runner).
    Trial(TrialArgs),
    /// Tune a configuration with irace and write a validation spec for its elites.
    Tune(TuneArgs),
    /// Numerical-stability stress test: kernels against a double-double reference, the solver
    /// on problems with known answers, diagnostics of fits; exits 1 when a check fails.
    Stress(StressArgs),
    /// Speed report: each kernel's ns per lobe-sample against the machine's arithmetic peak,
    /// and AED, AERS and RPLS to target on the paper's tuning and cross instances.
    Bench(BenchArgs),
    /// Write one self-contained HTML page of results folders: the plan, provenance, tables,
    /// RTDs, error-time curves, traces, sweeps and the best fit.
    Report(ReportArgs),
    /// Compare two results folders (before and after): a verdict per instance, configuration
    /// and target, and an HTML page; exits 3 when B is significantly slower anywhere (1: a
    /// failure, 2: bad input).
    Compare(CompareArgs),
    /// Print a shell completion script (bash, zsh, fish, powershell, elvish).
    Completions(CompletionsArgs),
    /// Write the man pages (roff), generated from the same definitions as --help.
    Man(ManArgs),
}

/// `brdf-sls run`.
#[derive(Args)]
pub struct RunArgs {
    /// Experiment spec (TOML), or `suite:NAME` for a suite's built-in experiment (`suite:`
    /// alone lists the suites). Omit to run the built-in default experiment.
    pub spec: Option<PathBuf>,
    /// Output directory (default: runs/<spec file stem>/).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Worker threads (default: $BRDF_SLS_THREADS, else the spec's `threads`, else all CPUs).
    #[arg(long, env = "BRDF_SLS_THREADS")]
    pub threads: Option<usize>,
    /// Move an existing results file aside (renamed, never deleted) and start over.
    #[arg(long)]
    pub fresh: bool,
    /// Run at most N new trials, then stop (resume later by running again).
    #[arg(long, value_name = "N")]
    pub limit: Option<usize>,
    /// Run only shard K of N (K from 1) of the trial plan: trial t of instance i and
    /// configuration c (from 0) when (t + i + c) mod N = K-1, each with the seed it has in a
    /// whole run; default output runs/<stem>/shard-K-of-N/. Merge with `brdf-sls merge`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<brdf_experiment::shard::Shard>,
    /// Skip the plots and report.html (statistics are still written).
    #[arg(long)]
    pub no_plots: bool,
    /// Evaluation kernel: auto, avx512, avx2, portable or scalar (default: the spec's
    /// `kernel`, else auto = the fastest the CPU has). Recorded with the results.
    #[arg(long)]
    pub kernel: Option<brdf_model::Kernel>,
    /// Progress display: auto (bars on a terminal unless CI=true, else plain lines), bars,
    /// plain, quiet.
    #[arg(long, value_parser = values::choice::<ProgressMode>(ProgressMode::NAMES), default_value = "auto")]
    pub progress: ProgressMode,
}

/// `brdf-sls check`.
#[derive(Args)]
pub struct CheckArgs {
    /// Experiment spec (TOML), or `suite:NAME` for a suite's built-in experiment (`suite:`
    /// alone lists the suites).
    pub spec: PathBuf,
    /// Threads to estimate wall time for (default: $BRDF_SLS_THREADS, else the spec's, else
    /// all CPUs).
    #[arg(long, env = "BRDF_SLS_THREADS")]
    pub threads: Option<usize>,
    /// Compute every instance's best-known RMSE, however large (by default only instances of
    /// at most 20000 samples; `run` computes the others).
    #[arg(long)]
    pub best_known: bool,
}

/// `brdf-sls plot` and `brdf-sls stats`.
#[derive(Args)]
pub struct ResultsArgs {
    /// A spec (TOML; results read from --out or runs/<stem>/), a results directory, or a
    /// trials.jsonl(.gz) file (the spec stored with the results is used). Default: runs/default/.
    pub target: Option<PathBuf>,
    /// With a spec as TARGET: its results folder (default: runs/<stem>/), where the files are
    /// written too. With a results folder or file: the folder to write the statistics or
    /// plots into (default: the results folder).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// `stats` only: print the statistics without writing any file (e.g. a read-only folder).
    #[arg(long)]
    pub print_only: bool,
}

/// Export formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ExportFormat {
    /// IOHprofiler's format: one JSON meta file per (configuration, instance) and .dat files
    /// of the runs (see `brdf_analysis::export`).
    Ioh,
}

/// `brdf-sls export`.
#[derive(Args)]
pub struct ExportArgs {
    /// A results directory, or a trials.jsonl(.gz) file (the spec stored with the results is
    /// used).
    pub dir: PathBuf,
    /// Output format.
    #[arg(long, value_enum)]
    pub format: ExportFormat,
    /// Output directory (default: <DIR>/ioh/).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// `brdf-sls bench`.
#[derive(Args)]
pub struct BenchArgs {
    /// Trials (seeds) per algorithm and instance. The defaults (20 seeds, 2 s) are those of
    /// results/bench and take about 4 minutes, most of it AED and AERS on the cross instance,
    /// where most trials run to the cutoff.
    #[arg(long, default_value_t = 20)]
    pub seeds: u64,
    /// CPU-time cutoff per trial in seconds.
    #[arg(long, default_value_t = 2.0)]
    pub cutoff: f64,
    /// Output folder for bench.md and bench.json (default: runs/bench/).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Progress display of the searches: auto (bars on a terminal unless CI=true, else plain
    /// lines), bars, plain, quiet.
    #[arg(long, value_parser = values::choice::<ProgressMode>(ProgressMode::NAMES), default_value = "auto")]
    pub progress: ProgressMode,
    /// Rewrite bench.html from OUT/bench.json without measuring (after a change of the page's
    /// layout).
    #[arg(long)]
    pub rewrite_page: bool,
}

/// `brdf-sls stress`.
#[derive(Args)]
pub struct StressArgs {
    /// Smaller sample counts (under a minute on 2 cores); the full run takes longer.
    #[arg(long)]
    pub quick: bool,
    /// Output folder for stress.md, stress.json and plots/ (default: runs/stress/).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// A measured data file to fit and diagnose (Cornell .brdf, CSV or MERL, read with the
    /// default data policy); repeatable.
    #[arg(long = "data", value_name = "FILE")]
    pub data: Vec<PathBuf>,
    /// Master seed of every random draw.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads (default: $BRDF_SLS_THREADS, else all CPUs).
    #[arg(long, env = "BRDF_SLS_THREADS")]
    pub threads: Option<usize>,
    /// Rewrite stress.html and plots/ from OUT/stress.json without running the checks (after a
    /// change of the page's layout).
    #[arg(long)]
    pub rewrite_page: bool,
}

/// `brdf-sls gen`.
#[derive(Args)]
pub struct GenArgs {
    /// The parameters to generate from.
    #[command(flatten)]
    pub params: ParamArgs,
    /// Number of samples.
    #[arg(long, default_value_t = 10_000)]
    pub samples: usize,
    /// Gaussian noise standard deviation.
    #[arg(long, default_value_t = 0.0)]
    pub sigma: f64,
    /// Instance seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Output CSV file (default: standard output).
    #[arg(long, short)]
    pub out: Option<PathBuf>,
}

/// `brdf-sls eval`.
#[derive(Args)]
pub struct EvalArgs {
    /// The data set.
    #[command(flatten)]
    pub data: DataArgs,
    /// The parameters to evaluate.
    #[command(flatten)]
    pub params: ParamArgs,
    /// Significant digits of the RMSE (default 17: enough to tell any two f64 apart).
    #[arg(long, default_value_t = 17, value_parser = clap::value_parser!(u8).range(1..=17))]
    pub digits: u8,
}

/// `brdf-sls info`.
#[derive(Args)]
pub struct InfoArgs {
    /// The data set.
    #[command(flatten)]
    pub data: DataArgs,
}
