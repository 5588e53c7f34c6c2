//! What a results folder holds for a comparison ([`Entry`]: one instance and configuration with
//! its trials) and the conditions two entries must share to be compared ([`Conditions`]).

use serde_json::Value;

use crate::analysis::Analysis;
use crate::folder::Folder;
use crate::stats::{ConfigStats, Measure, MeasureSummary, Outcome, outcome};
use brdf_experiment::store::TrialRecord;

/// Relative difference under which two targets are the same target: a relative target is a
/// best-known RMSE times `1 + r`, and re-computing the best-known RMSE after a change of
/// round-off moves it in its last bits (1e-16 relative), not to another optimum. A trial could
/// not tell such targets apart; a best-known RMSE that moved further (another optimum found)
/// makes the targets different.
pub const TARGET_ROUND_OFF: f64 = 1e-12;

/// Whether `a` and `b` are the same target up to [`TARGET_ROUND_OFF`].
pub fn same_target(a: f64, b: f64) -> bool {
    a == b || (a - b).abs() <= TARGET_ROUND_OFF * a.abs().max(b.abs())
}

/// What must agree between A and B for their results to be compared.
#[derive(Clone, Debug, PartialEq)]
pub struct Conditions {
    /// Hash of the instance's data (`None` in results files that predate data hashes).
    pub data_hash: Option<String>,
    /// Where the data come from (the spec's canonical source).
    pub source: Value,
    /// The model: lobes, exponent coordinate, start distribution, fixed values, bounds.
    pub model: Value,
    /// The RMSE at which trials stop.
    pub run_target: f64,
    /// The per-trial budget (cutoff).
    pub budget: sls::Budget,
    /// The algorithm's settings (and its descent model).
    pub algorithm: Value,
    /// The results format, which fixes how sample-evaluations are counted and stored.
    pub counting: u32,
}

/// One (instance, configuration) of a results folder.
#[derive(Clone, Debug)]
pub struct Entry {
    /// Instance name.
    pub instance: String,
    /// Configuration label.
    pub config: String,
    /// The instance's targets.
    pub targets: Vec<f64>,
    /// The conditions its trials ran under.
    pub conditions: Conditions,
    /// Its trials.
    pub records: Vec<TrialRecord>,
    /// Its statistics per target from its folder's analysis (empty: computed when compared).
    pub stats: Vec<ConfigStats>,
}

impl Entry {
    /// The trials' outcomes for `target` in `measure`.
    pub fn outcomes(&self, target: f64, measure: Measure) -> Vec<Outcome> {
        self.records
            .iter()
            .map(|r| outcome(r, target, measure))
            .collect()
    }

    /// Its summary for `target` in `measure` from its folder's analysis, if it has one.
    pub fn summary(&self, target: f64, measure: Measure) -> Option<MeasureSummary> {
        let s = self.stats.iter().find(|s| s.target == target)?;
        Some(match measure {
            Measure::CpuSeconds => s.cpu.clone(),
            Measure::Evaluations => s.evaluations.clone(),
        })
    }
}

/// Every (instance, configuration) of a folder's plan, in the spec's order, with its
/// statistics from the folder's `analysis`.
pub fn entries(folder: &Folder, analysis: &Analysis) -> Vec<Entry> {
    let spec = &folder.spec;
    let header = &folder.contents.header;
    let records = folder.records();
    let mut out = Vec::new();
    for inst in &spec.instances {
        for c in &spec.configurations {
            out.push(Entry {
                instance: inst.name.clone(),
                config: c.label.clone(),
                targets: inst.targets.clone(),
                conditions: Conditions {
                    data_hash: header.data_hashes.get(&inst.name).cloned(),
                    source: serde_json::to_value(&inst.source).unwrap_or(Value::Null),
                    model: serde_json::to_value(&inst.model).unwrap_or(Value::Null),
                    run_target: inst.run_target(),
                    budget: spec.budget,
                    algorithm: serde_json::json!({"algorithm": c.algorithm, "descent": c.descent}),
                    counting: header.format,
                },
                records: records
                    .iter()
                    .filter(|r| r.instance == inst.name && r.config == c.label)
                    .cloned()
                    .collect(),
                stats: analysis
                    .stats
                    .configs
                    .iter()
                    .filter(|s| s.instance == inst.name && s.config == c.label)
                    .cloned()
                    .collect(),
            });
        }
    }
    out
}

/// A budget as text, e.g. `10 CPU s` or `400000 sample-evaluations`.
pub fn budget_text(b: &sls::Budget) -> String {
    let mut parts = Vec::new();
    if let Some(s) = b.cpu_seconds {
        parts.push(format!("{s} CPU s"));
    }
    if let Some(e) = b.sample_evaluations {
        parts.push(format!("{e} sample-evaluations"));
    }
    if parts.is_empty() {
        "none".into()
    } else {
        parts.join(" and ")
    }
}

/// Why A's and B's conditions make their results incomparable (empty when they agree).
pub fn differences(a: &Conditions, b: &Conditions) -> Vec<String> {
    let mut out = Vec::new();
    match (&a.data_hash, &b.data_hash) {
        (Some(x), Some(y)) if x != y => {
            out.push(format!("different instance data (hash {x} vs {y})"));
        }
        (Some(_), Some(_)) => {}
        _ if a.source != b.source => out.push(format!(
            "different data source ({})",
            json_diff(&a.source, &b.source)
        )),
        _ => {}
    }
    if a.model != b.model {
        out.push(format!(
            "different model ({})",
            json_diff(&a.model, &b.model)
        ));
    }
    if !same_target(a.run_target, b.run_target) {
        out.push(format!(
            "different target (trials stop at RMSE {} vs {})",
            a.run_target, b.run_target
        ));
    }
    if a.budget != b.budget {
        out.push(format!(
            "different budget/cutoff ({} vs {})",
            budget_text(&a.budget),
            budget_text(&b.budget)
        ));
    }
    if a.algorithm != b.algorithm {
        out.push(format!(
            "different algorithm settings ({})",
            json_diff(&a.algorithm, &b.algorithm)
        ));
    }
    if a.counting != b.counting {
        out.push(format!(
            "different counting rule (results format {} vs {})",
            a.counting, b.counting
        ));
    }
    out
}

/// The leaves of a JSON value as `path = value`.
fn leaves(v: &Value, path: &str, out: &mut Vec<(String, String)>) {
    let join = |k: &str| {
        if path.is_empty() {
            k.to_string()
        } else {
            format!("{path}.{k}")
        }
    };
    match v {
        Value::Object(m) => m.iter().for_each(|(k, x)| leaves(x, &join(k), out)),
        Value::Array(a) => a
            .iter()
            .enumerate()
            .for_each(|(i, x)| leaves(x, &join(&i.to_string()), out)),
        other => out.push((path.to_string(), other.to_string())),
    }
}

/// The first few leaves where `a` and `b` differ, as `path: A vs B`.
pub fn json_diff(a: &Value, b: &Value) -> String {
    let (mut la, mut lb) = (Vec::new(), Vec::new());
    leaves(a, "", &mut la);
    leaves(b, "", &mut lb);
    let value = |l: &[(String, String)], k: &str| {
        l.iter()
            .find(|(p, _)| p == k)
            .map_or_else(|| "absent".to_string(), |(_, v)| v.clone())
    };
    let mut keys: Vec<&String> = la.iter().chain(&lb).map(|(k, _)| k).collect();
    keys.sort();
    keys.dedup();
    let diffs: Vec<String> = keys
        .into_iter()
        .filter(|k| value(&la, k) != value(&lb, k))
        .map(|k| format!("{k}: {} vs {}", value(&la, k), value(&lb, k)))
        .collect();
    const SHOWN: usize = 3;
    let more = diffs.len().saturating_sub(SHOWN);
    let mut text = diffs.into_iter().take(SHOWN).collect::<Vec<_>>().join(", ");
    if more > 0 {
        text.push_str(&format!(" and {more} more"));
    }
    text
}
