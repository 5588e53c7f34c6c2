//! `custom-algorithm SPEC [--out DIR] [--threads N] [--shard K/N]`: registers
//! `coordinate-search`, then runs (or resumes) the experiment SPEC, or one shard of its trials,
//! into DIR (default `runs/<SPEC's stem>`) and writes its statistics and plots. Exit codes: 0 done, 2 bad arguments or spec, 1 a failure while running.

use std::path::PathBuf;
use std::process::ExitCode;

use custom_algorithm::{RunSpecError, register, run_spec};
use harness::shard::Shard;

const USAGE: &str = "usage: custom-algorithm SPEC.toml [--out DIR] [--threads N] [--shard K/N]";

/// The parsed command line.
struct Args {
    spec: PathBuf,
    out: PathBuf,
    threads: Option<usize>,
    shard: Option<Shard>,
}

fn parse_args(mut args: impl Iterator<Item = String>) -> Result<Args, String> {
    let (mut spec, mut out, mut threads, mut shard) = (None, None, None, None);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--out" => out = Some(PathBuf::from(args.next().ok_or("--out needs a folder")?)),
            "--threads" => {
                let n = args.next().ok_or("--threads needs a number")?;
                match n.parse::<usize>() {
                    Ok(n) if n > 0 => threads = Some(n),
                    _ => {
                        return Err(format!(
                            "--threads must be a whole number >= 1, found `{n}`"
                        ));
                    }
                }
            }
            "--shard" => {
                let k_of_n = args.next().ok_or("--shard needs K/N")?;
                let parsed = k_of_n.parse::<Shard>();
                shard = Some(parsed.map_err(|e| format!("--shard `{k_of_n}`: {e}"))?);
            }
            flag if flag.starts_with('-') => return Err(format!("unknown option `{flag}`")),
            path if spec.is_none() => spec = Some(PathBuf::from(path)),
            extra => return Err(format!("unexpected argument `{extra}`")),
        }
    }
    let spec = spec.ok_or("missing the spec file")?;
    let stem = spec.file_stem().unwrap_or_default().to_os_string();
    let out = out.unwrap_or_else(|| PathBuf::from("runs").join(stem));
    Ok(Args {
        spec,
        out,
        threads,
        shard,
    })
}

fn main() -> ExitCode {
    let args = match parse_args(std::env::args().skip(1)) {
        Ok(args) => args,
        Err(message) => {
            eprintln!("error: {message}\n{USAGE}");
            return ExitCode::from(2);
        }
    };
    if let Err(e) = register() {
        eprintln!("error: {e}");
        return ExitCode::from(1);
    }
    match run_spec(&args.spec, &args.out, args.threads, args.shard) {
        Ok(summary) => {
            println!("{}", summary.table);
            println!(
                "{} new trials ({} resumed); wrote {} files to {}",
                summary.new_trials,
                summary.resumed,
                summary.files,
                args.out.display()
            );
            ExitCode::SUCCESS
        }
        Err(RunSpecError::Spec(e)) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
        Err(RunSpecError::Run(e)) => {
            eprintln!("error: {e:#}");
            ExitCode::from(1)
        }
    }
}
