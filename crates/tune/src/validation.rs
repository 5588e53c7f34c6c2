//! The validation experiment written after tuning: the tuning spec without its `[tune]`
//! table, restricted to the held-out instances (`tune.test`), with the tuned configuration at
//! its defaults beside irace's elites, ready for `brdf-sls run`.

use std::path::Path;

use brdf_experiment::spec::Spec;
use brdf_experiment::spec::tune::{TuneSpec, base_table, with_values};
use sls::{AlgorithmConfig, DescentModel};

use super::irace::Elite;

/// What the validation spec takes from the tuning spec (see [`TuningSource::of`]).
#[derive(Clone, Copy, Debug)]
pub struct TuningSource<'a> {
    /// The tuning experiment's name.
    pub name: &'a str,
    /// Its trials per (instance, configuration): the validation's default trial count.
    pub trials: u32,
    /// The directory its relative data paths resolve against.
    pub base_dir: &'a Path,
    /// The tuned configuration (`tune.algorithm`) with its defaults.
    pub algorithm: &'a AlgorithmConfig,
    /// The tuned configuration's descent model.
    pub descent: DescentModel,
}

impl<'a> TuningSource<'a> {
    /// What the validation spec after tuning takes from `spec`: its name, trials, base
    /// directory and the configuration labelled `label` (`None` when there is none).
    pub fn of(spec: &'a Spec, label: &str) -> Option<Self> {
        let c = spec.configurations.iter().find(|c| c.label == label)?;
        Some(TuningSource {
            name: &spec.name,
            trials: spec.trials,
            base_dir: &spec.base_dir,
            algorithm: &c.algorithm,
            descent: c.descent,
        })
    }
}

/// The label of the untuned configuration in the validation spec.
pub fn default_label(tuned: &str) -> String {
    format!("{tuned} default")
}

/// The label of the elite of rank `rank` (1 = best) in the validation spec.
pub fn elite_label(tuned: &str, rank: usize) -> String {
    format!("{tuned} irace-{rank}")
}

/// Writes the validation spec's TOML text. `text` is the tuning spec as written and `spec` what
/// its validated form gives the validation, `elites` irace's elites (best first; at most `tune.elites` are
/// used), `name` the new experiment's name. Relative data file paths are made absolute, so
/// the new file may live anywhere.
pub fn validation_spec(
    text: &str,
    spec: &TuningSource<'_>,
    tune: &TuneSpec,
    elites: &[Elite],
    name: &str,
) -> Result<String, String> {
    let mut doc: toml::Table =
        toml::from_str(text).map_err(|e| format!("re-reading the spec: {e}"))?;
    doc.remove("tune");
    doc.insert("name".into(), toml::Value::String(name.into()));
    doc.insert(
        "description".into(),
        toml::Value::String(format!(
            "Validation of irace's elites for `{}` against its defaults on held-out instances \
             (written by brdf-sls tune from `{}`)",
            tune.algorithm, spec.name
        )),
    );
    doc.insert(
        "trials".into(),
        toml::Value::Integer(i64::from(tune.validation_trials.unwrap_or(spec.trials))),
    );
    let instances = match doc.remove("instance") {
        Some(toml::Value::Array(a)) => a,
        _ => return Err("the spec has no [[instance]] array".into()),
    };
    let mut kept = Vec::new();
    for mut inst in instances {
        let Some(t) = inst.as_table_mut() else {
            continue;
        };
        let keep = t
            .get("name")
            .and_then(toml::Value::as_str)
            .is_some_and(|n| tune.test.iter().any(|x| x == n));
        if !keep {
            continue;
        }
        if let Some(toml::Value::Table(file)) = t.get_mut("file")
            && let Some(toml::Value::String(p)) = file.get_mut("path")
            && Path::new(p.as_str()).is_relative()
        {
            let joined = spec.base_dir.join(p.as_str());
            let abs = joined.canonicalize().unwrap_or(joined);
            *p = abs.display().to_string();
        }
        kept.push(inst);
    }
    doc.insert("instance".into(), toml::Value::Array(kept));
    let entry = |label: String, config: &AlgorithmConfig| -> Result<toml::Value, String> {
        let mut t = toml::Table::new();
        t.insert("label".into(), toml::Value::String(label));
        t.extend(base_table(config)?);
        if spec.descent != DescentModel::Default {
            t.insert(
                "descent".into(),
                toml::Value::String(spec.descent.to_string()),
            );
        }
        Ok(toml::Value::Table(t))
    };
    let mut algorithms = vec![entry(default_label(&tune.algorithm), spec.algorithm)?];
    for (rank, e) in elites.iter().take(tune.elites).enumerate() {
        let config = with_values(spec.algorithm, &e.values)
            .map_err(|m| format!("irace's elite {}: {m}", e.id))?;
        algorithms.push(entry(elite_label(&tune.algorithm, rank + 1), &config)?);
    }
    doc.insert("algorithm".into(), toml::Value::Array(algorithms));
    let mut out = format!(
        "# Validation spec written by `brdf-sls tune` from `{}`.\n\
         # Held-out instances: {}. Elites (irace id: values), best first:\n",
        spec.name,
        tune.test.join(", ")
    );
    for (rank, e) in elites.iter().take(tune.elites).enumerate() {
        let v: Vec<String> = e.values.iter().map(|(n, v)| format!("{n} = {v}")).collect();
        out.push_str(&format!(
            "#   {}: irace configuration {}: {}\n",
            elite_label(&tune.algorithm, rank + 1),
            e.id,
            v.join(", ")
        ));
    }
    out.push_str("# Run it with: brdf-sls run THIS_FILE\n\n");
    out.push_str(&toml::to_string(&doc).map_err(|e| format!("writing TOML: {e}"))?);
    Ok(out)
}
