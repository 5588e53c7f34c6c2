//! Export of a results folder to IOHprofiler's data format, which IOHanalyzer and the
//! `iohinspector` Python package load.
//!
//! # Layout
//!
//! One folder per configuration (its label as a file name), and in it, per instance:
//!
//! ```text
//! <out>/<configuration>/IOHprofiler_f<K>_<instance>.json              meta data
//! <out>/<configuration>/data_f<K>_<instance>/IOHprofiler_f<K>_DIM<D>.dat   the runs
//! ```
//!
//! - A *function* is an instance of the experiment (`function_id` K is its position in the
//!   spec, from 1; `function_name` its name), minimised (`"maximization": false`); the
//!   *algorithm* is a configuration (`info` holds its parameters as JSON); the *dimension* D
//!   is the number of free parameters; each trial is one *run* on IOH instance 1 (every trial
//!   of an instance fits the same data).
//! - Each run in the `.dat` file starts with the header line `evaluations raw_y` followed by
//!   one line per improvement of the best full-data RMSE (the trial's anytime trace), and a
//!   last line at the evaluations the trial ended with. `evaluations` counts
//!   sample-evaluations in the paper's way (residual + Jacobian + whole full-data RMSE rows),
//!   so budgets in IOHanalyzer are sample-evaluations, not calls. `raw_y` is the best RMSE.
//! - IOHprofiler's readers tell runs apart by a line with `evaluations` = 1 (iohinspector
//!   splits on it), but our first RMSE is known only after a whole full-data evaluation. Each
//!   run therefore starts with a line `1 <first RMSE>`: the first recorded RMSE is moved back to
//!   evaluation 1. Everything from the first real trace point on is exact.
//! - The meta file's `runs` list each trial's total evaluations and best point (`y` the best
//!   RMSE, `x` the best parameters in the optimiser's coordinates, `evals` when it was found).
//!   `experiment_attributes` state the exponent coordinate, the start distribution and the
//!   counting rule, so comparisons in IOHanalyzer can be checked for fairness.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use brdf_graphics::chart::slug;

use brdf_experiment::spec::{InstanceSpec, Spec};
use brdf_experiment::store::{TrialRecord, write_atomic};

/// The IOHprofiler logger format version the files follow.
pub const IOH_FORMAT_VERSION: &str = "0.3.17";

/// Errors exporting.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// A file could not be written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// Two configuration labels or instance names map to the same file name.
    #[error("`{a}` and `{b}` give the same file name `{slug}`; rename one in the spec")]
    NameClash {
        /// One name.
        a: String,
        /// The other.
        b: String,
        /// The shared file name.
        slug: String,
    },
}

/// What [`export_ioh`] wrote.
#[derive(Clone, Debug, Default)]
pub struct Exported {
    /// Files written.
    pub files: Vec<PathBuf>,
    /// Runs written, per (configuration, instance).
    pub runs: BTreeMap<(String, String), usize>,
    /// Runs that never evaluated a point (best RMSE infinite): written with `y` =
    /// `f64::MAX`, because JSON has no infinity.
    pub unevaluated: usize,
}

/// Writes `records` (of `spec`'s plan) to `out` in IOHprofiler's format (see the module docs).
pub fn export_ioh(
    spec: &Spec,
    records: &[&TrialRecord],
    out: &Path,
) -> Result<Exported, ExportError> {
    let configs = unique_slugs(spec.config_labels())?;
    let instances = unique_slugs(spec.instance_names())?;
    let mut done = Exported::default();
    for (cfg, cslug) in spec.configurations.iter().zip(&configs) {
        for (k, (inst, islug)) in spec.instances.iter().zip(&instances).enumerate() {
            let mut runs: Vec<&TrialRecord> = records
                .iter()
                .copied()
                .filter(|r| r.config == cfg.label && r.instance == inst.name)
                .collect();
            if runs.is_empty() {
                continue;
            }
            runs.sort_by_key(|r| r.trial);
            let dir = out.join(cslug);
            let fid = k + 1;
            let dim = runs
                .iter()
                .map(|r| r.result.best_x.len())
                .max()
                .unwrap_or(0);
            let dat_rel = format!("data_f{fid}_{islug}/IOHprofiler_f{fid}_DIM{dim}.dat");
            let dat = dat_text(&runs);
            let mut info = serde_json::to_value(&cfg.algorithm).unwrap_or_default();
            if cfg.descent != sls::DescentModel::Default
                && let Some(map) = info.as_object_mut()
            {
                map.insert("descent".into(), serde_json::json!(cfg.descent));
            }
            let algorithm_info = info.to_string();
            let meta = meta_json(
                spec,
                inst,
                fid,
                &cfg.label,
                &algorithm_info,
                dim,
                &dat_rel,
                &runs,
            );
            write(&dir.join(&dat_rel), dat.as_bytes(), &mut done.files)?;
            let json_path = dir.join(format!("IOHprofiler_f{fid}_{islug}.json"));
            let text = serde_json::to_string_pretty(&meta).unwrap_or_default();
            write(&json_path, text.as_bytes(), &mut done.files)?;
            done.unevaluated += runs
                .iter()
                .filter(|r| !r.result.best_rmse.is_finite())
                .count();
            done.runs
                .insert((cfg.label.clone(), inst.name.clone()), runs.len());
        }
    }
    Ok(done)
}

/// File names for `names`, refusing two names with the same file name.
fn unique_slugs(names: Vec<String>) -> Result<Vec<String>, ExportError> {
    let mut seen: BTreeMap<String, String> = BTreeMap::new();
    let mut out = Vec::new();
    for n in names {
        let s = slug(&n);
        if let Some(prev) = seen.insert(s.clone(), n.clone()) {
            return Err(ExportError::NameClash {
                a: prev,
                b: n,
                slug: s,
            });
        }
        out.push(s);
    }
    Ok(out)
}

fn write(path: &Path, bytes: &[u8], files: &mut Vec<PathBuf>) -> Result<(), ExportError> {
    let io = |source| ExportError::Io {
        path: path.to_path_buf(),
        source,
    };
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).map_err(io)?;
    }
    write_atomic(path, bytes).map_err(io)?;
    files.push(path.to_path_buf());
    Ok(())
}

/// A finite stand-in for an RMSE that JSON and IOHprofiler's readers can hold.
fn finite(y: f64) -> f64 {
    if y.is_finite() { y } else { f64::MAX }
}

/// The `.dat` text of one (configuration, instance): every run, in trial order.
fn dat_text(runs: &[&TrialRecord]) -> String {
    let mut s = String::new();
    for r in runs {
        s.push_str("evaluations raw_y\n");
        let trace = &r.result.trace;
        let first_evals = trace.first().map(|p| p.at.evaluations.total());
        let first_y = trace.first().map_or(r.result.best_rmse, |p| p.rmse);
        // The reader's run separator (see the module docs).
        if first_evals != Some(1) {
            let _ = writeln!(s, "1 {}", finite(first_y));
        }
        let mut last = 1;
        for p in trace {
            let e = p.at.evaluations.total().max(1);
            let _ = writeln!(s, "{e} {}", finite(p.rmse));
            last = e;
        }
        let end = r.result.ended_at.evaluations.total();
        if end > last {
            let _ = writeln!(s, "{end} {}", finite(r.result.best_rmse));
        }
    }
    s
}

/// The meta file of one (configuration, instance).
#[allow(clippy::too_many_arguments)]
fn meta_json(
    spec: &Spec,
    inst: &InstanceSpec,
    fid: usize,
    label: &str,
    algorithm_info: &str,
    dim: usize,
    dat_rel: &str,
    runs: &[&TrialRecord],
) -> serde_json::Value {
    let runs: Vec<serde_json::Value> = runs
        .iter()
        .map(|r| {
            let best_evals = r
                .result
                .trace
                .last()
                .map_or(0, |p| p.at.evaluations.total());
            serde_json::json!({
                "instance": 1,
                "evals": r.result.ended_at.evaluations.total().max(1),
                "best": {
                    "evals": best_evals.max(1),
                    "y": finite(r.result.best_rmse),
                    "x": r.result.best_x,
                },
            })
        })
        .collect();
    let coordinate = format!("{:?}", inst.model.exponent).to_lowercase();
    let starts = inst.model.starts.resolve(inst.model.exponent).name();
    serde_json::json!({
        "version": IOH_FORMAT_VERSION,
        "suite": format!("brdf-sls {}", spec.name),
        "function_id": fid,
        "function_name": inst.name,
        "maximization": false,
        "algorithm": { "name": label, "info": algorithm_info },
        "experiment_attributes": [
            { "exponent": coordinate },
            { "starts": starts },
            { "counting": "sample-evaluations" },
            { "target": inst.run_target().to_string() },
        ],
        "attributes": ["evaluations", "raw_y"],
        "scenarios": [{ "dimension": dim, "path": dat_rel, "runs": runs }],
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use sls::{Budget, EvalCounts, Stamp, StopReason, TracePoint, TrialResult};

    fn stamp(evals: u64) -> Stamp {
        Stamp {
            cpu_seconds: 0.0,
            wall_seconds: 0.0,
            evaluations: EvalCounts {
                residual_rows: evals,
                ..EvalCounts::default()
            },
        }
    }

    fn record(trial: u32, trace: &[(u64, f64)], end: u64) -> TrialRecord {
        TrialRecord {
            key: format!("i/c/{trial}"),
            instance: "i".into(),
            config: "c".into(),
            trial,
            seed: 1,
            target: 0.1,
            budget: Budget::default(),
            result: TrialResult {
                stop: StopReason::CpuBudget,
                reached_at: None,
                ended_at: stamp(end),
                best_rmse: trace.last().map_or(f64::INFINITY, |p| p.1),
                best_x: vec![0.5; 3],
                trace: trace
                    .iter()
                    .map(|&(e, y)| TracePoint {
                        at: stamp(e),
                        rmse: y,
                    })
                    .collect(),
                counters: vec![],
                failure: None,
            },
        }
    }

    #[test]
    fn every_run_starts_at_evaluation_one_and_ends_at_its_last_evaluation() {
        let a = record(0, &[(100, 0.5), (250, 0.2)], 400);
        let b = record(1, &[(1, 0.7)], 1);
        let text = dat_text(&[&a, &b]);
        assert_eq!(
            text,
            "evaluations raw_y\n1 0.5\n100 0.5\n250 0.2\n400 0.2\n\
             evaluations raw_y\n1 0.7\n"
        );
        // A run that never evaluated anything still appears, with a finite stand-in.
        let c = record(2, &[], 0);
        assert_eq!(
            dat_text(&[&c]),
            format!("evaluations raw_y\n1 {}\n", f64::MAX)
        );
    }

    #[test]
    fn clashing_file_names_are_refused() {
        // `=` and `-` both become `-` in file names.
        let e = unique_slugs(vec!["AED phi=1".into(), "AED phi-1".into()]).unwrap_err();
        assert!(e.to_string().contains("AED_phi-1"), "{e}");
        let ok = unique_slugs(vec!["AED phi=1".into(), "AED phi=2".into()]).unwrap();
        assert_eq!(ok, vec!["AED_phi-1", "AED_phi-2"]);
    }
}
