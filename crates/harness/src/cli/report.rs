//! Flags of `brdf-sls report` and `brdf-sls compare` (the HTML pages) and of
//! `brdf-sls completions` and `brdf-sls man`.

use std::path::PathBuf;

use clap::Args;

/// `brdf-sls report`.
#[derive(Args)]
pub struct ReportArgs {
    /// Results folders (or trials.jsonl(.gz) files); one section each.
    #[arg(required = true, value_name = "DIR")]
    pub dirs: Vec<PathBuf>,
    /// The HTML file to write (default: <first DIR>/report.html).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// The measure `compare` bases its verdicts on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum VerdictMeasure {
    /// Sample-evaluations (independent of the machine and the kernel).
    Evals,
    /// CPU seconds of the worker thread.
    Cpu,
}

/// `brdf-sls compare`.
#[derive(Args)]
pub struct CompareArgs {
    /// The reference results folder ("before").
    pub a: PathBuf,
    /// The results folder compared with it ("after").
    pub b: PathBuf,
    /// The HTML page to write (default: <B>/compare.html).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Significance level of the Holm-adjusted log-rank p-values.
    #[arg(long, default_value_t = 0.05)]
    pub alpha: f64,
    /// Smallest relative change of the median time-to-target that counts as faster or
    /// slower (0.05 = 5%).
    #[arg(long, default_value_t = 0.05, value_name = "FRACTION")]
    pub min_effect: f64,
    /// The measure of the verdicts (the other is reported beside it).
    #[arg(long, value_enum, default_value = "evals")]
    pub measure: VerdictMeasure,
}

/// `brdf-sls completions`.
#[derive(Args)]
pub struct CompletionsArgs {
    /// The shell to write a completion script for.
    #[arg(value_enum)]
    pub shell: clap_complete::Shell,
}

/// `brdf-sls man`.
#[derive(Args)]
pub struct ManArgs {
    /// Folder for brdf-sls.1 and one page per command (brdf-sls-run.1, ...); without it, the
    /// main page goes to standard output.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}
