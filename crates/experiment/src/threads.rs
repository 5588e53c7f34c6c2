//! How many worker threads a run may ask for, and how many can help.

/// Most worker threads accepted (`--threads`, a spec's `threads`): far above the cores of any
/// machine this runs on, far below the thousands that overload one.
pub const MAX_THREADS: usize = 1024;

/// Checks a requested thread count: from 1 to [`MAX_THREADS`]. The error names `what` (the
/// flag or key) and the limit.
pub fn check(requested: usize, what: &str) -> Result<(), String> {
    if (1..=MAX_THREADS).contains(&requested) {
        Ok(())
    } else {
        Err(format!(
            "{what} must be from 1 to {MAX_THREADS}, found {requested}"
        ))
    }
}

/// The threads that can help: the request, capped at the `trials` to run (a thread runs one
/// trial at a time) and at the logical `cpus` (trials are CPU-bound: more threads only share
/// the CPUs). With a note saying so when capped.
pub fn useful(requested: usize, trials: usize, cpus: usize) -> (usize, Option<String>) {
    let cap = trials.max(1).min(cpus.max(1));
    if requested <= cap {
        return (requested, None);
    }
    let why = if trials.max(1) <= cpus.max(1) {
        format!("{trials} trial(s) to run")
    } else {
        format!("{cpus} logical CPU(s)")
    };
    let note = format!("using {cap} worker thread(s), not the {requested} asked for: {why}");
    (cap, Some(note))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn absurd_counts_are_refused_with_the_limit() {
        assert!(check(1, "--threads").is_ok());
        assert!(check(MAX_THREADS, "--threads").is_ok());
        assert_eq!(
            check(10_001, "--threads").unwrap_err(),
            "--threads must be from 1 to 1024, found 10001"
        );
        assert!(check(0, "`threads`").is_err());
    }

    #[test]
    fn the_pool_is_capped_at_trials_and_cpus() {
        assert_eq!(useful(4, 100, 8), (4, None));
        let (n, note) = useful(1000, 3, 8);
        assert_eq!(n, 3);
        assert!(note.unwrap().ends_with("3 trial(s) to run"));
        let (n, note) = useful(1000, 100, 8);
        assert_eq!(n, 8);
        assert!(note.unwrap().ends_with("8 logical CPU(s)"));
        assert_eq!(
            useful(2, 0, 8),
            (
                1,
                Some("using 1 worker thread(s), not the 2 asked for: 0 trial(s) to run".into())
            )
        );
    }
}
