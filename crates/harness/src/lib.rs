//! Experiment specs, trial runner, results store, statistics and plots (work in progress).
