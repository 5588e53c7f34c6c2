//! The commands: one file each, and [`shared`] for what several of them need. Each command
//! takes its parsed flags and returns `anyhow::Result`; [`exit_code`] turns the outcome into a
//! Unix exit status.

use std::io::Write;

use crate::cli::Command;

mod bench;
mod check;
mod compare;
mod completions;
mod data;
mod export;
mod fit;
mod merge;
mod polar;
mod python;
mod render;
mod report;
mod results;
mod run;
pub mod shared;
mod slurm;
mod stress;
mod trial;
mod tune;

/// The `brdf-sls` program: parses the command line, runs the command and returns its exit
/// status (0 success or a closed output pipe, 2 bad input, 1 a failure while running, 3
/// `compare`'s verdict that B is significantly slower).
pub fn main() -> std::process::ExitCode {
    use clap::Parser;
    use std::process::ExitCode;
    brdf_experiment::signals::ignore_file_size_signal();
    let cli = match crate::cli::Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // Help and version go to stdout with status 0; usage errors to stderr with 2.
            let _ = e.print();
            return ExitCode::from(if e.use_stderr() { 2 } else { 0 });
        }
    };
    let writes = writes_results(&cli.command);
    match dispatch(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let code = exit_code(&e);
            if code != 0 {
                let text = if writes {
                    with_out_hint(&e)
                } else {
                    message(&e)
                };
                let text = brdf_experiment::terminal::safe(&text);
                let _ = writeln!(std::io::stderr().lock(), "error: {text}");
            }
            ExitCode::from(code)
        }
    }
}

/// The commands that write into a results folder (or beside it) unless `--out` says where.
fn writes_results(command: &Command) -> bool {
    matches!(
        command,
        Command::Run(_) | Command::Stats(_) | Command::Plot(_) | Command::Report(_)
    )
}

/// The message of an error of a command that writes results ([`writes_results`]), with the
/// hint to use `--out` when the cause is a folder that may not be written (permission denied,
/// read-only file system) and the message does not give it already
/// ([`brdf_experiment::store::StoreError::NotWritable`] does): a user in a read-only working
/// folder otherwise learns only that writing failed, not that `--out` avoids it.
pub fn with_out_hint(e: &anyhow::Error) -> String {
    use brdf_experiment::store::{WRITE_ELSEWHERE, is_not_writable};
    let text = message(e);
    let denied = e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(is_not_writable)
    });
    // Reading the spec or an instance's data is not writing: --out would not help there.
    let reading_input = e.chain().any(|c| {
        c.is::<brdf_experiment::spec::SpecError>()
            || c.is::<brdf_experiment::instance::InstanceError>()
    });
    if denied && !reading_input && !text.contains(WRITE_ELSEWHERE) {
        format!("{text}; {WRITE_ELSEWHERE}")
    } else {
        text
    }
}

/// Runs one command.
pub fn dispatch(command: Command) -> anyhow::Result<()> {
    if reads_python_specs(&command) {
        // Specs and results with algorithms written in Python are read like any other (the
        // kind's schema); only running them needs Python (`run` runs them in worker processes
        // of the Python package).
        brdf_experiment::python_kind::register_schema();
    }
    if reads_results_only(&command) {
        // A results folder written by a program with kinds of its own is read all the same:
        // their settings are kept as written.
        sls::registry::read_unknown_kinds_as_opaque();
    }
    match command {
        Command::Run(a) => run::run(a),
        Command::Check(a) => check::check(a),
        Command::Plot(a) => results::results(a, true),
        Command::Stats(a) => results::results(a, false),
        Command::Export(a) => export::export(a),
        Command::Fit(a) => fit::fit(a),
        Command::Gen(a) => data::generate(a),
        Command::Eval(a) => data::eval(a),
        Command::Info(a) => data::info(a),
        Command::Render(a) => render::render(a),
        Command::Polar(a) => polar::polar(a),
        Command::Merge(a) => merge::merge(a),
        Command::Slurm(a) => slurm::slurm(a),
        Command::Trial(a) => trial::trial(a),
        Command::Tune(a) => tune::tune(a),
        Command::Stress(a) => stress::stress(a),
        Command::Bench(a) => bench::bench(a),
        Command::Report(a) => report::report(a),
        Command::Compare(a) => compare::compare(a),
        Command::Completions(a) => completions::completions(a),
        Command::Man(a) => completions::man(a),
    }
}

/// Whether `command` reads specs or results that may name algorithms written in Python:
/// those that run no trial, `run` and `slurm` (whose shards run them in worker processes of
/// the Python package), and `trial` and `tune`, which refuse them with a message.
fn reads_python_specs(command: &Command) -> bool {
    matches!(
        command,
        Command::Run(_)
            | Command::Check(_)
            | Command::Plot(_)
            | Command::Stats(_)
            | Command::Export(_)
            | Command::Merge(_)
            | Command::Report(_)
            | Command::Compare(_)
            | Command::Polar(_)
            | Command::Slurm(_)
            | Command::Trial(_)
            | Command::Tune(_)
    )
}

/// Whether `command` only reads results folders (and so may meet kinds it does not know).
fn reads_results_only(command: &Command) -> bool {
    matches!(
        command,
        Command::Plot(_)
            | Command::Stats(_)
            | Command::Export(_)
            | Command::Merge(_)
            | Command::Report(_)
            | Command::Compare(_)
            | Command::Polar(_)
    )
}

/// Bad input from the user (flags, a spec, a data file): exit status 2.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct InputError(pub String);

/// An [`InputError`] as an `anyhow::Error`.
pub fn input_error(message: impl Into<String>) -> anyhow::Error {
    InputError(message.into()).into()
}

/// The error and its causes joined by ": ", each cause printed once: the message the Python
/// package raises too ([`brdf_analysis::errors::message`]).
pub fn message(e: &anyhow::Error) -> String {
    brdf_analysis::errors::message(e)
}

pub use brdf_analysis::pipeline::written_summary;

/// True when the error (or one of its causes) is a closed pipe on our output.
pub fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// True when the error comes from the user's input rather than from running: the
/// classification the Python package uses too ([`brdf_analysis::errors`]), plus the errors of
/// the crates only the command line calls (its own flags, `fit`, `merge`).
fn is_input_error(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.is::<InputError>()
            || brdf_analysis::errors::is_input_cause(c)
            || c.downcast_ref::<brdf_fit::FitError>()
                .is_some_and(|f| f.is_input_error())
            || c.downcast_ref::<brdf_merge::MergeError>()
                .is_some_and(|m| m.is_input_error())
    })
}

/// `compare`'s verdict that B is significantly slower: its own exit status, so that a CI job
/// tells a performance regression from an I/O failure (1) or bad input (2).
pub const SLOWER_STATUS: u8 = 3;

/// The exit status of a failed command: 0 for a closed output pipe (the reader has what it
/// wanted), 2 for bad input, [`SLOWER_STATUS`] for `compare`'s verdict "B is slower", 1 for
/// failures while running.
pub fn exit_code(e: &anyhow::Error) -> u8 {
    if is_broken_pipe(e) {
        0
    } else if is_input_error(e) {
        2
    } else if e.chain().any(|c| c.is::<compare::Slower>()) {
        SLOWER_STATUS
    } else {
        1
    }
}

/// Returns an [`InputError`] (exit status 2) built like `format!`.
macro_rules! bail_input {
    ($($arg:tt)*) => {
        return Err($crate::cmd::input_error(format!($($arg)*)))
    };
}
pub(crate) use bail_input;

/// Writes a line to standard output (control characters escaped,
/// [`brdf_experiment::terminal::safe`]), returning the error (a closed pipe ends the command
/// quietly, see [`exit_code`]) instead of panicking as `println!` does.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let text = format!($($arg)*);
        writeln!(
            std::io::stdout().lock(),
            "{}",
            brdf_experiment::terminal::safe(&text)
        )
            .map_err(|e| anyhow::Error::new(e).context("writing to standard output"))?
    }};
}
pub(crate) use say;

/// Writes a line to standard error (control characters escaped), ignoring failures: diagnostics must never stop the work.
macro_rules! note {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let text = format!($($arg)*);
        let _ = writeln!(
            std::io::stderr().lock(),
            "{}",
            brdf_experiment::terminal::safe(&text)
        );
    }};
}
pub(crate) use note;

/// Flushes standard output (buffered writers report a closed pipe only here).
pub fn flush_stdout() -> anyhow::Result<()> {
    std::io::stdout()
        .flush()
        .map_err(|e| anyhow::Error::new(e).context("writing to standard output"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cause_already_in_its_parents_message_is_printed_once() {
        let io = std::io::Error::new(std::io::ErrorKind::StorageFull, "No space left on device");
        let store = brdf_experiment::store::StoreError::Io {
            path: "runs/x/trials.jsonl".into(),
            source: io,
        };
        let e = anyhow::Error::new(store).context("running experiment `default`");
        assert_eq!(
            message(&e),
            "running experiment `default`: runs/x/trials.jsonl: No space left on device"
        );
    }

    #[test]
    fn a_path_that_ends_the_parent_and_starts_the_cause_is_printed_once() {
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "No such file or directory");
        let store = brdf_experiment::store::StoreError::Io {
            path: "runs/x/trials.jsonl".into(),
            source: io,
        };
        let e = anyhow::Error::new(store).context("reading runs/x/trials.jsonl");
        assert_eq!(
            message(&e),
            "reading runs/x/trials.jsonl: No such file or directory"
        );
        // A different path is not a repetition.
        let e = anyhow::anyhow!("b.toml: bad").context("reading a.toml");
        assert_eq!(message(&e), "reading a.toml: b.toml: bad");
    }

    /// A folder that may not be written gets the hint to use --out, once, whichever layer
    /// reported it; other I/O errors, and a spec that may not be read, get none.
    #[test]
    fn a_read_only_folder_gets_the_hint_to_use_out_once() {
        use brdf_experiment::store::{WRITE_ELSEWHERE, write_error};
        use std::io::{Error, ErrorKind};
        let denied = || {
            Error::new(
                ErrorKind::PermissionDenied,
                "Permission denied (os error 13)",
            )
        };
        let plain = anyhow::Error::new(denied()).context("writing r/stats.json");
        assert_eq!(
            with_out_hint(&plain),
            format!("writing r/stats.json: Permission denied (os error 13); {WRITE_ELSEWHERE}")
        );
        let rofs = Error::new(ErrorKind::ReadOnlyFilesystem, "Read-only file system");
        let rofs = anyhow::Error::new(rofs).context("creating r");
        assert!(with_out_hint(&rofs).ends_with(WRITE_ELSEWHERE));
        let store = anyhow::Error::new(write_error("r/.lock".as_ref(), denied()))
            .context("running experiment `x`");
        let text = with_out_hint(&store);
        assert_eq!(text.matches(WRITE_ELSEWHERE).count(), 1, "{text}");
        assert!(text.contains("r/.lock"), "{text}");
        // An unreadable spec is not a folder to write elsewhere.
        let spec = brdf_experiment::spec::SpecError::Io {
            path: "a.toml".into(),
            source: denied(),
        };
        assert!(!with_out_hint(&anyhow::Error::new(spec)).contains("--out"));
        let full = Error::new(ErrorKind::StorageFull, "No space left on device");
        let full = anyhow::Error::new(write_error("r/trials.jsonl".as_ref(), full));
        assert!(!with_out_hint(&full).contains("--out"));
    }

    #[test]
    fn the_written_line_names_plots_only_when_drawn() {
        let out = std::path::Path::new("runs/x");
        assert_eq!(
            written_summary(3, out, true, false),
            "wrote 3 files to runs/x (statistics: stats.csv, tests.csv; plots: plots/)"
        );
        assert_eq!(
            written_summary(3, out, false, false),
            "wrote 3 files to runs/x (statistics: stats.csv, tests.csv)"
        );
    }

    #[test]
    fn causes_not_in_the_message_are_all_kept() {
        let e = anyhow::anyhow!("inner").context("middle").context("outer");
        assert_eq!(message(&e), "outer: middle: inner");
    }
}
