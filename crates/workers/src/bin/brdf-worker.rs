//! A worker process for the built-in kinds: [`brdf_workers::serve`] on standard input and
//! output. The Python package's worker is `python -m brdf_sls worker`; this one runs trials of
//! Rust algorithms in a process of their own (the tests compare its results with in-process
//! ones).

fn main() -> std::process::ExitCode {
    let input = std::io::BufReader::new(std::io::stdin());
    match brdf_workers::serve(input, std::io::stdout()) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: worker: {e}");
            std::process::ExitCode::from(1)
        }
    }
}
