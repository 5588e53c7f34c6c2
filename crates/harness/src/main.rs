//! `brdf-sls`: run BRDF-fitting experiments (TOML specs), re-plot and summarise stored results,
//! fit a data set once, and generate, evaluate or describe data sets.
//!
//! This file only wires: [`cli`] declares the flags, [`cmd`] does the work, and `main` turns
//! the outcome into an exit status (0 success or a closed output pipe, 2 bad input, 1 a
//! failure while running).

use std::process::ExitCode;

use clap::Parser;

mod cli;
mod cmd;

fn main() -> ExitCode {
    harness::signals::ignore_file_size_signal();
    let cli = match cli::Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // Help and version go to stdout with status 0; usage errors to stderr with 2.
            let _ = e.print();
            return ExitCode::from(if e.use_stderr() { 2 } else { 0 });
        }
    };
    match cmd::dispatch(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let code = cmd::exit_code(&e);
            if code != 0 {
                use std::io::Write as _;
                let _ = writeln!(std::io::stderr().lock(), "error: {}", cmd::message(&e));
            }
            ExitCode::from(code)
        }
    }
}
