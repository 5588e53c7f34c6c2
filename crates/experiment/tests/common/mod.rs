//! Shared helpers of the integration tests (included with `mod common;`).
#![allow(dead_code)]

use std::path::Path;

use brdf_experiment::spec::Spec;
use brdf_experiment::store::TrialRecord;

/// A tiny experiment: 400 noisy samples of the tuning BRDF, AED (two sweep points) and RPLS,
/// an evaluation budget only (so trials are deterministic in their seed, independent of speed).
pub const TINY: &str = r#"
name = "tiny"
seed = 11
trials = 4

[budget]
evaluations = 400000

[[instance]]
name = "tuning"
targets = [0.105, 0.12]
[instance.synthetic]
params = "tuning"
samples = 400
sigma = 0.1
seed = 3

[[algorithm]]
label = "AED"
kind = "aed"
[algorithm.sweep]
phi = [1.2, 1.4]

[[algorithm]]
kind = "rpls"

[plots]
formats = ["png", "svg"]
trace_trials = 2
error_steps = 5

[stats]
bootstrap = 200
"#;

/// Parses spec text with `dir` as the base directory.
pub fn spec(text: &str, dir: &Path) -> Spec {
    Spec::parse(text, "tiny.toml", "tiny", dir).unwrap()
}

/// What must be identical between two runs of the same trial: everything except clocks.
pub fn deterministic_view(r: &TrialRecord) -> String {
    let res = &r.result;
    let trace: Vec<(u64, String)> = res
        .trace
        .iter()
        .map(|p| (p.at.evaluations.total(), format!("{:.15e}", p.rmse)))
        .collect();
    format!(
        "{} seed={} target={} stop={:?} best={:.15e} x={:?} evals={:?} reached={:?} trace={:?} counters={:?}",
        r.key,
        r.seed,
        r.target,
        res.stop,
        res.best_rmse,
        res.best_x,
        res.ended_at.evaluations,
        res.reached_at.map(|s| s.evaluations),
        trace,
        res.counters
    )
}
