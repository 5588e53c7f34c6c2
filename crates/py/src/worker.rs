//! `python -m brdf_sls worker`: a worker process of a run ([`brdf_workers`]): runs the trials
//! its parent sends (algorithms written in Python among them) on this interpreter's main
//! thread, so that each Python trial has an interpreter, and a core, of its own.

use std::io::BufReader;

use pyo3::prelude::*;

use crate::support::run_err;

/// Serves the run that started this process: reads its messages on standard input and writes
/// the replies on what was standard output, which from then on is standard error (so an
/// algorithm's prints cannot break the replies). Returns when the run closes the input.
#[pyfunction]
pub fn worker_main(py: Python<'_>) -> PyResult<()> {
    let replies = replies_channel().map_err(|e| run_err(format!("worker: {e}")))?;
    let input = BufReader::new(std::io::stdin());
    py.detach(|| brdf_workers::serve(input, replies))
        .map_err(|e| run_err(format!("worker: {e}")))
}

/// A copy of standard output for the replies; standard output itself becomes standard error.
#[cfg(unix)]
fn replies_channel() -> std::io::Result<std::fs::File> {
    use std::os::fd::FromRawFd as _;
    // SAFETY: plain descriptor calls; the copy is owned by the returned File alone.
    unsafe {
        let copy = libc::dup(1);
        if copy < 0 || libc::dup2(2, 1) < 0 {
            return Err(std::io::Error::last_os_error());
        }
        Ok(std::fs::File::from_raw_fd(copy))
    }
}

#[cfg(not(unix))]
fn replies_channel() -> std::io::Result<std::io::Stdout> {
    Ok(std::io::stdout())
}
