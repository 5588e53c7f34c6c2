//! Signal dispositions the program sets at start.

/// Ignores `SIGXFSZ`, the signal a write past the file-size limit (`ulimit -f`) raises. Its
/// default action kills the process in the middle of a write, leaving a torn last line; ignored,
/// the write fails with `EFBIG` instead, and the store cuts the file back to its last complete
/// line and reports the error (see [`crate::store::StoreError::AppendFailed`]).
pub fn ignore_file_size_signal() {
    #[cfg(unix)]
    // SAFETY: setting a signal's disposition to SIG_IGN installs no handler code, and is done
    // once at start before any thread is spawned.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
}
