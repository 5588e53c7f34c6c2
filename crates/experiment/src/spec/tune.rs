//! The spec's optional `[tune]` table (automatic tuning with irace, `brdf-sls tune`): the
//! table as written and validated against the spec's configurations and instances, and the
//! cost of one trial as irace's target-runner reports it.
//!
//! # The `[tune]` table
//!
//! ```toml
//! [tune]
//! algorithm = "AED"              # label of the configuration to tune (default: the first)
//! train = ["t2-s11", "t2-s12"]   # instance names irace tunes on
//! test = ["t2-s21", "t2-s22"]    # held-out instance names the validation spec compares on
//! budget = 300                   # irace's maxExperiments (trials in total)
//! cost = "evaluations"           # "time" | "evaluations" | "rmse"
//! cutoff = 2e7                   # per trial: CPU s (time, rmse) or sample-evaluations
//!                                # (evaluations); default: from [budget]
//! penalty = 10                   # censored runs cost penalty * cutoff (PAR10)
//! seed = 1                       # irace's seed
//! parallel = 2                   # trials irace runs at once (default: threads, else CPUs)
//! elites = 3                     # elites written to the validation spec (at most)
//! validation_trials = 100        # trials per configuration there (default: `trials`)
//!
//! [[tune.parameter]]             # one or more; names are fields of the algorithm
//! name = "phi"
//! type = "real"                  # "int" | "real" | "categorical" | "ordinal"
//! range = [1.05, 3.0]            # int and real
//! log = false                    # sample on a log scale (int and real; range > 0)
//! # values = ["a", "b"]          # categorical and ordinal
//! # condition = 'rho0 > 10'      # irace condition (an R expression over other parameters)
//! ```
//!
//! The cost of a trial (what `brdf-sls trial` prints) is, for `time`, the CPU seconds to the
//! instance's lowest target, for `evaluations` the sample-evaluations to it (both with the
//! cutoff, and `penalty * cutoff` for a run that missed it: PARk), and for `rmse` the best
//! full-data RMSE when the CPU-time cutoff is spent.

use serde::Deserialize;
use sls::{AlgorithmConfig, Budget, TrialResult};

/// Largest `budget` (irace experiments) a spec may ask for.
pub const MAX_BUDGET: u64 = 1_000_000;

/// What a trial's cost measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CostKind {
    /// CPU seconds to the target; censored runs cost `penalty * cutoff`.
    Time,
    /// Sample-evaluations to the target; censored runs cost `penalty * cutoff`.
    Evaluations,
    /// Best full-data RMSE when the CPU-second cutoff is spent.
    Rmse,
}

crate::choice::named_choices!(CostKind {
    Time => "time",
    Evaluations => "evaluations",
    Rmse => "rmse",
});

impl CostKind {
    /// The unit of the cutoff.
    pub fn cutoff_unit(self) -> &'static str {
        match self {
            CostKind::Evaluations => "sample-evaluations",
            CostKind::Time | CostKind::Rmse => "CPU seconds",
        }
    }

    /// The cutoff `[budget]` gives when `tune.cutoff` is missing.
    pub fn default_cutoff(self, budget: &Budget) -> Option<f64> {
        match self {
            CostKind::Evaluations => budget.sample_evaluations.map(|e| e as f64),
            CostKind::Time | CostKind::Rmse => budget.cpu_seconds,
        }
    }

    /// The trial budget a cutoff means.
    pub fn budget(self, cutoff: f64) -> Budget {
        match self {
            CostKind::Evaluations => Budget {
                cpu_seconds: None,
                sample_evaluations: Some(cutoff as u64),
            },
            CostKind::Time | CostKind::Rmse => Budget {
                cpu_seconds: Some(cutoff),
                sample_evaluations: None,
            },
        }
    }

    /// The target a trial runs to: the instance's for run times, none (0) for `rmse`.
    pub fn run_target(self, instance_target: f64) -> f64 {
        match self {
            CostKind::Rmse => 0.0,
            CostKind::Time | CostKind::Evaluations => instance_target,
        }
    }
}

/// How a trial is turned into one number.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CostRule {
    /// What is measured.
    pub kind: CostKind,
    /// Per-trial cutoff (CPU seconds or sample-evaluations, see [`CostKind::cutoff_unit`]).
    pub cutoff: f64,
    /// Censored runs cost `penalty * cutoff`.
    pub penalty: f64,
}

impl CostRule {
    /// Checks the numbers; the message names the offending one.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.cutoff.is_finite() && self.cutoff > 0.0) {
            return Err(format!(
                "cutoff must be a positive number of {}, found {}",
                self.kind.cutoff_unit(),
                self.cutoff
            ));
        }
        if self.kind == CostKind::Evaluations && self.cutoff < 1.0 {
            return Err(format!(
                "cutoff must be at least 1 sample-evaluation, found {}",
                self.cutoff
            ));
        }
        // The spec's own limits on a trial's budget: above them a cutoff is a typo, and a trial
        // given it would run until killed.
        let max = match self.kind {
            CostKind::Time | CostKind::Rmse => super::limits::MAX_CPU_SECONDS,
            CostKind::Evaluations => u64::MAX as f64,
        };
        if self.cutoff > max {
            return Err(format!(
                "cutoff must be at most {max:e} {} (the limit of `budget.{}` in a spec), found {}",
                self.kind.cutoff_unit(),
                match self.kind {
                    CostKind::Evaluations => "evaluations",
                    CostKind::Time | CostKind::Rmse => "cpu_seconds",
                },
                self.cutoff
            ));
        }
        if !(self.penalty.is_finite() && self.penalty >= 1.0) {
            return Err(format!(
                "penalty must be a number >= 1 (10 gives PAR10), found {}",
                self.penalty
            ));
        }
        Ok(())
    }

    /// The cost of a finished trial. A run time counts only when the target was reached within
    /// the cutoff; anything else (censored by the cutoff, or ended by itself) costs
    /// `penalty * cutoff`.
    pub fn cost(&self, r: &TrialResult) -> f64 {
        let censored = self.penalty * self.cutoff;
        match self.kind {
            CostKind::Time => match r.reached_at {
                Some(at) if at.cpu_seconds <= self.cutoff => at.cpu_seconds,
                _ => censored,
            },
            CostKind::Evaluations => match r.reached_at {
                Some(at) if (at.evaluations.total() as f64) <= self.cutoff => {
                    at.evaluations.total() as f64
                }
                _ => censored,
            },
            CostKind::Rmse => r.best_rmse,
        }
    }
}

/// Parameter types irace knows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ParamType {
    /// Integer in a range (irace `i`).
    Int,
    /// Real in a range (irace `r`).
    Real,
    /// Unordered values (irace `c`).
    Categorical,
    /// Ordered values (irace `o`).
    Ordinal,
}

impl ParamType {
    /// Whether the parameter has a numeric range (else a list of values).
    pub fn is_numeric(self) -> bool {
        matches!(self, ParamType::Int | ParamType::Real)
    }
}

/// One `[[tune.parameter]]` as written.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParsedParameter {
    /// The algorithm's field name.
    pub name: String,
    /// Its type.
    #[serde(rename = "type")]
    pub kind: ParamType,
    /// `[low, high]` of int and real parameters.
    pub range: Option<[f64; 2]>,
    /// Values of categorical and ordinal parameters.
    pub values: Option<Vec<toml::Value>>,
    /// Log scale (int and real).
    #[serde(default)]
    pub log: bool,
    /// irace condition: the parameter is only set when it holds.
    pub condition: Option<String>,
}

/// The `[tune]` table as written (see the module documentation).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParsedTune {
    /// Label of the configuration to tune.
    pub algorithm: Option<String>,
    /// Training instance names.
    pub train: Vec<String>,
    /// Held-out instance names.
    pub test: Vec<String>,
    /// irace's maxExperiments.
    pub budget: u64,
    /// Cost kind.
    pub cost: CostKind,
    /// Per-trial cutoff.
    pub cutoff: Option<f64>,
    /// PAR factor.
    pub penalty: Option<f64>,
    /// irace's seed.
    pub seed: Option<u64>,
    /// irace's `parallel`.
    pub parallel: Option<usize>,
    /// Elites to validate.
    pub elites: Option<usize>,
    /// Trials per configuration in the validation spec.
    pub validation_trials: Option<u32>,
    /// The parameters.
    #[serde(rename = "parameter")]
    pub parameters: Vec<ParsedParameter>,
}

/// A validated tuned parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct TuneParameter {
    /// The algorithm's field name (also the command-line switch `--NAME`).
    pub name: String,
    /// Its type.
    pub kind: ParamType,
    /// `[low, high]` (int and real).
    pub range: Option<[f64; 2]>,
    /// Values as irace writes them (categorical and ordinal).
    pub values: Vec<String>,
    /// Log scale.
    pub log: bool,
    /// irace condition.
    pub condition: Option<String>,
}

/// A validated `[tune]` table.
#[derive(Clone, Debug, PartialEq)]
pub struct TuneSpec {
    /// Label of the tuned configuration (one of the spec's configurations).
    pub algorithm: String,
    /// The parameters irace sets.
    pub parameters: Vec<TuneParameter>,
    /// Training instance names (irace's instance list).
    pub train: Vec<String>,
    /// Held-out instance names (the validation spec's instances).
    pub test: Vec<String>,
    /// irace's maxExperiments.
    pub budget: u64,
    /// How a trial becomes a cost.
    pub cost: CostRule,
    /// irace's seed.
    pub seed: u64,
    /// Trials irace runs at once (`None`: the spec's threads, else all CPUs).
    pub parallel: Option<usize>,
    /// Elites written to the validation spec (at most).
    pub elites: usize,
    /// Trials per configuration in the validation spec (`None`: the spec's `trials`).
    pub validation_trials: Option<u32>,
}

/// Characters allowed in categorical values (irace output is split on white space).
fn plain_token(s: &str) -> bool {
    !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "_.+-".contains(c))
}

/// Words of an R condition that are not parameter names.
const R_WORDS: [&str; 7] = ["c", "TRUE", "FALSE", "in", "NA", "T", "F"];

/// The identifiers a condition refers to (outside quoted strings and `%op%` operators).
pub fn condition_identifiers(condition: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut chars = condition.chars().peekable();
    let mut word = String::new();
    let flush = |word: &mut String, out: &mut Vec<String>| {
        if !word.is_empty() {
            let starts_alpha = word
                .chars()
                .next()
                .is_some_and(|c| c.is_ascii_alphabetic() || c == '_' || c == '.');
            let numeric = word.parse::<f64>().is_ok();
            if starts_alpha && !numeric && !R_WORDS.contains(&word.as_str()) {
                out.push(word.clone());
            }
            word.clear();
        }
    };
    while let Some(c) = chars.next() {
        match c {
            '"' | '\'' => {
                flush(&mut word, &mut out);
                for d in chars.by_ref() {
                    if d == c {
                        break;
                    }
                }
            }
            '%' => {
                flush(&mut word, &mut out);
                for d in chars.by_ref() {
                    if d == '%' {
                        break;
                    }
                }
            }
            c if c.is_ascii_alphanumeric() || c == '_' || c == '.' => word.push(c),
            _ => flush(&mut word, &mut out),
        }
    }
    flush(&mut word, &mut out);
    out
}

/// A configuration with `name = value` set, deserialised and validated by sls.
pub fn with_values(
    base: &AlgorithmConfig,
    values: &[(String, toml::Value)],
) -> Result<AlgorithmConfig, String> {
    let mut table = base_table(base)?;
    for (name, v) in values {
        if name == "kind" || !table.contains_key(name) {
            let known: Vec<&str> = table
                .keys()
                .map(String::as_str)
                .filter(|k| *k != "kind")
                .collect();
            return Err(format!(
                "`{name}` is not a parameter of {} (its parameters: {})",
                base.kind_name(),
                known.join(", ")
            ));
        }
        table.insert(name.clone(), v.clone());
    }
    let config: AlgorithmConfig = toml::Value::Table(table)
        .try_into()
        .map_err(|e: toml::de::Error| e.message().to_string())?;
    config.validate().map_err(|e| e.to_string())?;
    Ok(config)
}

/// The configuration as a TOML table with every field (and `kind`).
pub fn base_table(base: &AlgorithmConfig) -> Result<toml::Table, String> {
    toml::Table::try_from(base).map_err(|e| format!("serialising the configuration: {e}"))
}

/// A command-line or irace value as TOML: an integer, a float, a boolean, else a string.
pub fn toml_value(s: &str) -> toml::Value {
    let s = s.trim();
    if let Ok(i) = s.parse::<i64>() {
        toml::Value::Integer(i)
    } else if let Ok(f) = s.parse::<f64>() {
        toml::Value::Float(f)
    } else if s == "true" || s == "false" {
        toml::Value::Boolean(s == "true")
    } else {
        toml::Value::String(s.to_string())
    }
}

impl TuneSpec {
    /// Validates the raw table against the spec's instance names, configurations (label and
    /// algorithm) and budget. The error message names the key.
    pub fn from_raw(
        raw: ParsedTune,
        instance_names: &[String],
        configurations: &[(String, AlgorithmConfig)],
        budget: &Budget,
    ) -> Result<TuneSpec, String> {
        let (algorithm, base) = match &raw.algorithm {
            Some(label) => configurations
                .iter()
                .find(|(l, _)| l == label)
                .ok_or_else(|| {
                    let labels: Vec<&str> = configurations.iter().map(|c| c.0.as_str()).collect();
                    format!(
                        "`tune.algorithm`: no configuration labelled `{label}` (labels: {})",
                        labels.join(", ")
                    )
                })?,
            None => configurations
                .first()
                .ok_or("`tune`: the spec has no configuration to tune")?,
        };
        for (key, list) in [("train", &raw.train), ("test", &raw.test)] {
            if list.is_empty() {
                return Err(format!("`tune.{key}` must name at least one instance"));
            }
            for name in list {
                if !instance_names.contains(name) {
                    return Err(format!(
                        "`tune.{key}`: no instance named `{name}` (instances: {})",
                        instance_names.join(", ")
                    ));
                }
                if list.iter().filter(|n| *n == name).count() > 1 {
                    return Err(format!("`tune.{key}`: `{name}` listed twice"));
                }
            }
        }
        if let Some(shared) = raw.test.iter().find(|n| raw.train.contains(n)) {
            return Err(format!(
                "`tune.test`: `{shared}` is also a training instance; held-out instances must \
                 differ (e.g. another instance seed)"
            ));
        }
        if !(1..=MAX_BUDGET).contains(&raw.budget) {
            return Err(format!(
                "`tune.budget` must be from 1 to {MAX_BUDGET} experiments, found {}",
                raw.budget
            ));
        }
        let cutoff = match raw.cutoff.or_else(|| raw.cost.default_cutoff(budget)) {
            Some(c) => c,
            None => {
                return Err(format!(
                    "`tune.cutoff` is needed: cost `{}` counts {} and [budget] sets no such limit",
                    raw.cost.name(),
                    raw.cost.cutoff_unit()
                ));
            }
        };
        let cost = CostRule {
            kind: raw.cost,
            cutoff,
            penalty: raw.penalty.unwrap_or(10.0),
        };
        cost.validate().map_err(|e| format!("`tune`: {e}"))?;
        if raw.parallel == Some(0) {
            return Err("`tune.parallel` must be at least 1".into());
        }
        if raw.elites == Some(0) {
            return Err("`tune.elites` must be at least 1".into());
        }
        if raw.validation_trials == Some(0) {
            return Err("`tune.validation_trials` must be at least 1".into());
        }
        if raw.parameters.is_empty() {
            return Err("`tune` needs at least one [[tune.parameter]]".into());
        }
        let mut parameters = Vec::new();
        for p in raw.parameters {
            let tp = parameter(p, base)?;
            if parameters.iter().any(|q: &TuneParameter| q.name == tp.name) {
                return Err(format!("`tune.parameter`: `{}` listed twice", tp.name));
            }
            parameters.push(tp);
        }
        let names: Vec<&str> = parameters.iter().map(|p| p.name.as_str()).collect();
        for p in &parameters {
            if let Some(c) = &p.condition {
                for id in condition_identifiers(c) {
                    if id == p.name {
                        return Err(format!(
                            "`tune.parameter` `{}`: the condition refers to the parameter itself",
                            p.name
                        ));
                    }
                    if !names.contains(&id.as_str()) {
                        return Err(format!(
                            "`tune.parameter` `{}`: the condition `{c}` refers to `{id}`, which \
                             is not a tuned parameter ({})",
                            p.name,
                            names.join(", ")
                        ));
                    }
                }
            }
        }
        Ok(TuneSpec {
            algorithm: algorithm.clone(),
            parameters,
            train: raw.train,
            test: raw.test,
            budget: raw.budget,
            cost,
            seed: raw.seed.unwrap_or(1),
            parallel: raw.parallel,
            elites: raw.elites.unwrap_or(3),
            validation_trials: raw.validation_trials,
        })
    }
}

/// Validates one parameter against the configuration it tunes.
fn parameter(p: ParsedParameter, base: &AlgorithmConfig) -> Result<TuneParameter, String> {
    let at = |m: String| format!("`tune.parameter` `{}`: {m}", p.name);
    let table = base_table(base)?;
    let Some(default) = table.get(&p.name).filter(|_| p.name != "kind") else {
        let known: Vec<&str> = table
            .keys()
            .map(String::as_str)
            .filter(|k| *k != "kind")
            .collect();
        return Err(at(format!(
            "not a parameter of {} (its parameters: {})",
            base.kind_name(),
            known.join(", ")
        )));
    };
    if let Some(c) = &p.condition
        && (c.trim().is_empty() || c.contains(['\n', '\r', '#']))
    {
        return Err(at(format!(
            "condition `{c}`: expected one line of R without `#`"
        )));
    }
    let mut values = Vec::new();
    let mut range = None;
    if p.kind.is_numeric() {
        if p.values.is_some() {
            return Err(at(
                "`values` is for categorical and ordinal parameters; use `range`".into(),
            ));
        }
        let Some([lo, hi]) = p.range else {
            return Err(at("needs `range = [low, high]`".into()));
        };
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            return Err(at(format!(
                "range [{lo}, {hi}]: expected finite low < high"
            )));
        }
        if p.log && lo <= 0.0 {
            return Err(at(format!("range [{lo}, {hi}]: a log scale needs low > 0")));
        }
        let ends = if p.kind == ParamType::Int {
            if lo.fract() != 0.0 || hi.fract() != 0.0 {
                return Err(at(format!(
                    "range [{lo}, {hi}]: an int range needs integers"
                )));
            }
            if !default.is_integer() {
                return Err(at(format!(
                    "is not an integer field (default {default}); use type = \"real\""
                )));
            }
            [
                toml::Value::Integer(lo as i64),
                toml::Value::Integer(hi as i64),
            ]
        } else {
            if !(default.is_float() || default.is_integer()) {
                return Err(at(format!("is not a number (default {default})")));
            }
            if default.is_integer() {
                return Err(at(format!(
                    "is an integer field (default {default}); use type = \"int\""
                )));
            }
            [toml::Value::Float(lo), toml::Value::Float(hi)]
        };
        for v in ends {
            with_values(base, &[(p.name.clone(), v.clone())])
                .map_err(|e| at(format!("range end {v}: {e}")))?;
        }
        range = Some([lo, hi]);
    } else {
        if p.range.is_some() || p.log {
            return Err(at(
                "`range` and `log` are for int and real parameters; use `values`".into(),
            ));
        }
        let Some(list) = p.values else {
            return Err(at("needs `values = [...]`".into()));
        };
        if list.len() < 2 {
            return Err(at("needs at least two values".into()));
        }
        for v in &list {
            let text = match v {
                toml::Value::String(s) => s.clone(),
                toml::Value::Integer(_) | toml::Value::Float(_) | toml::Value::Boolean(_) => {
                    v.to_string()
                }
                other => return Err(at(format!("value {other}: expected a string or number"))),
            };
            if !plain_token(&text) {
                return Err(at(format!(
                    "value `{text}`: use letters, digits and _ . + - only"
                )));
            }
            if values.contains(&text) {
                return Err(at(format!("value `{text}` listed twice")));
            }
            with_values(base, &[(p.name.clone(), toml_value(&text))])
                .map_err(|e| at(format!("value `{text}`: {e}")))?;
            values.push(text);
        }
    }
    Ok(TuneParameter {
        name: p.name,
        kind: p.kind,
        range,
        values,
        log: p.log,
        condition: p.condition.map(|c| c.trim().to_string()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use sls::{Stamp, StopReason};

    fn result(reached: Option<(f64, u64)>, best: f64) -> TrialResult {
        let stamp = |cpu: f64, ev: u64| Stamp {
            cpu_seconds: cpu,
            wall_seconds: cpu,
            evaluations: sls::EvalCounts {
                residual_rows: ev,
                ..Default::default()
            },
        };
        TrialResult {
            stop: if reached.is_some() {
                StopReason::Target
            } else {
                StopReason::CpuBudget
            },
            reached_at: reached.map(|(c, e)| stamp(c, e)),
            ended_at: reached.map_or(stamp(2.0, 900), |(c, e)| stamp(c, e)),
            best_rmse: best,
            best_x: vec![],
            trace: vec![],
            counters: vec![],
            failure: None,
        }
    }

    #[test]
    fn par10_and_rmse_costs() {
        let time = CostRule {
            kind: CostKind::Time,
            cutoff: 2.0,
            penalty: 10.0,
        };
        assert_eq!(time.cost(&result(Some((0.5, 100)), 0.1)), 0.5);
        assert_eq!(time.cost(&result(None, 0.2)), 20.0);
        let ev = CostRule {
            kind: CostKind::Evaluations,
            cutoff: 1000.0,
            penalty: 10.0,
        };
        assert_eq!(ev.cost(&result(Some((0.5, 100)), 0.1)), 100.0);
        assert_eq!(ev.cost(&result(None, 0.2)), 10_000.0);
        let q = CostRule {
            kind: CostKind::Rmse,
            cutoff: 1.0,
            penalty: 10.0,
        };
        assert_eq!(q.cost(&result(None, 0.125)), 0.125);
        assert!(
            CostRule {
                penalty: 0.5,
                ..time
            }
            .validate()
            .is_err()
        );
        assert!(
            CostRule {
                cutoff: 0.0,
                ..time
            }
            .validate()
            .is_err()
        );
    }

    /// A cutoff above the spec's budget limits would run a trial until killed.
    #[test]
    fn a_cutoff_above_the_spec_limits_is_refused_naming_it() {
        let time = CostRule {
            kind: CostKind::Time,
            cutoff: 1e300,
            penalty: 10.0,
        };
        let e = time.validate().unwrap_err();
        assert!(
            e.contains("at most 1e7 CPU seconds") && e.contains("budget.cpu_seconds"),
            "{e}"
        );
        assert!(
            CostRule {
                cutoff: 1e7,
                ..time
            }
            .validate()
            .is_ok()
        );
        let ev = CostRule {
            kind: CostKind::Evaluations,
            cutoff: 1e300,
            penalty: 10.0,
        };
        let e = ev.validate().unwrap_err();
        assert!(e.contains("budget.evaluations"), "{e}");
    }

    #[test]
    fn condition_words() {
        assert_eq!(
            condition_identifiers("rho0 > 10 & mode %in% c(\"a\", 'b') & x.y == TRUE"),
            vec!["rho0", "mode", "x.y"]
        );
        assert!(condition_identifiers("3 < 4").is_empty());
    }
}
