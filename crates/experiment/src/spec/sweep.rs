//! Stage 3 of reading a spec: each `[[algorithm]]` entry, with its optional `[algorithm.sweep]`,
//! expanded into labelled [`Configuration`]s (the cartesian product of the swept values, the
//! first swept key varying slowest), each deserialised into an `sls::AlgorithmConfig` and
//! validated by sls.

use std::collections::BTreeMap;

use serde::Deserialize;
use sls::AlgorithmConfig;
use toml::Spanned;

use super::limits::{MAX_CONFIGURATIONS, MAX_SWEEP_STEPS};
use super::parsed::{algorithm_key_lines, line_of};
use super::validate::Ctx;
use super::{Configuration, SpecError, known_kinds};

/// A sweep entry given as a range.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ParsedRange {
    from: toml::Value,
    to: toml::Value,
    steps: usize,
    #[serde(default)]
    scale: Scale,
}

#[derive(Deserialize, Default, Clone, Copy, PartialEq)]
#[serde(rename_all = "lowercase")]
enum Scale {
    #[default]
    Linear,
    Log,
}

/// Where each key of one `[[algorithm]]` entry is, for errors.
struct EntryLines {
    entry: usize,
    keys: BTreeMap<String, usize>,
}

impl EntryLines {
    fn at(&self, key: &str) -> Option<usize> {
        Some(self.keys.get(key).copied().unwrap_or(self.entry))
    }
}

/// Every configuration of the spec, in order; labels must be unique.
pub(super) fn configurations(
    cx: &Ctx<'_>,
    algorithms: Vec<Spanned<toml::Table>>,
) -> Result<Vec<Configuration>, SpecError> {
    if algorithms.is_empty() {
        return Err(cx.invalid(None, "at least one [[algorithm]] is needed".into()));
    }
    let key_lines = algorithm_key_lines(cx.text);
    let mut out: Vec<Configuration> = Vec::new();
    for (ai, entry) in algorithms.into_iter().enumerate() {
        let lines = EntryLines {
            entry: line_of(cx.text, entry.span().start),
            keys: key_lines.get(ai).cloned().unwrap_or_default(),
        };
        for c in entry_configurations(cx, entry.into_inner(), &lines)? {
            if out.iter().any(|x| x.label == c.label) {
                return Err(cx.invalid(
                    Some(lines.entry),
                    format!(
                        "duplicate configuration label `{}` (give each [[algorithm]] its own `label`)",
                        c.label
                    ),
                ));
            }
            if out.len() >= MAX_CONFIGURATIONS {
                return Err(cx.invalid(
                    Some(lines.entry),
                    format!("more than {MAX_CONFIGURATIONS} configurations; sweep fewer values"),
                ));
            }
            out.push(c);
        }
    }
    Ok(out)
}

/// The configurations of one `[[algorithm]]` entry: one, or one per swept combination.
fn entry_configurations(
    cx: &Ctx<'_>,
    mut table: toml::Table,
    lines: &EntryLines,
) -> Result<Vec<Configuration>, SpecError> {
    let kind = kind_of(cx, &table, lines)?;
    let label = label_of(cx, &mut table, &kind, lines)?;
    let sweep = sweep_of(cx, &mut table, &label, lines)?;
    let descent = descent_of(cx, &mut table, &label, lines)?;
    // The base configuration must be valid by itself (swept keys may be absent).
    let base = algorithm_from_table(cx, &table, &label, &|k| lines.at(k))?;
    if sweep.is_empty() {
        return Ok(vec![Configuration {
            label: label.clone(),
            algorithm_label: label,
            swept: Vec::new(),
            algorithm: base,
            descent,
        }]);
    }
    let labelled: Vec<(String, Vec<(toml::Value, String)>)> = sweep
        .into_iter()
        .map(|(k, values)| {
            let labels = super::labels::distinct_labels(&values);
            (k, values.into_iter().zip(labels).collect())
        })
        .collect();
    let combos = cartesian(cx, &labelled, lines)?;
    combos
        .into_iter()
        .map(|combo| swept_configuration(cx, &table, &label, descent, combo, lines))
        .collect()
}

/// The entry's `descent` key (the solver configuration of its descents), removed from the
/// table because it is not an algorithm parameter.
fn descent_of(
    cx: &Ctx<'_>,
    table: &mut toml::Table,
    label: &str,
    lines: &EntryLines,
) -> Result<sls::DescentModel, SpecError> {
    let names = || sls::DescentModel::ALL.map(|m| format!("`{m}`")).join(", ");
    match table.remove("descent") {
        None => Ok(sls::DescentModel::Default),
        Some(toml::Value::String(name)) => sls::DescentModel::from_name(&name).ok_or_else(|| {
            cx.invalid(
                lines.at("descent"),
                format!(
                    "algorithm `{label}`: unknown `descent` `{name}` (expected one of {})",
                    names()
                ),
            )
        }),
        Some(other) => Err(cx.invalid(
            lines.at("descent"),
            format!(
                "algorithm `{label}`: `descent` must be a string (one of {}), found {}",
                names(),
                other.type_str()
            ),
        )),
    }
}

fn kind_of(cx: &Ctx<'_>, table: &toml::Table, lines: &EntryLines) -> Result<String, SpecError> {
    let kind = match table.get("kind") {
        Some(toml::Value::String(k)) => k.clone(),
        Some(other) => {
            return Err(cx.invalid(
                lines.at("kind"),
                format!(
                    "algorithm: `kind` must be a string, found {}",
                    other.type_str()
                ),
            ));
        }
        None => {
            return Err(cx.invalid(
                Some(lines.entry),
                format!(
                    "algorithm: missing `kind` (one of {})",
                    known_kinds().join(", ")
                ),
            ));
        }
    };
    if AlgorithmConfig::default_for(&kind).is_none() {
        return Err(cx.invalid(
            lines.at("kind"),
            format!(
                "algorithm: unknown `kind` `{kind}` (expected one of {})",
                known_kinds().join(", ")
            ),
        ));
    }
    Ok(kind)
}

fn label_of(
    cx: &Ctx<'_>,
    table: &mut toml::Table,
    kind: &str,
    lines: &EntryLines,
) -> Result<String, SpecError> {
    let label = match table.remove("label") {
        Some(toml::Value::String(l)) => l,
        Some(other) => {
            return Err(cx.invalid(
                lines.at("label"),
                format!(
                    "algorithm: `label` must be a string, found {}",
                    other.type_str()
                ),
            ));
        }
        None => kind.to_uppercase(),
    };
    if label.is_empty() || label.contains('/') {
        return Err(cx.invalid(
            lines.at("label"),
            format!("algorithm `{label}`: `label` must be non-empty and contain no '/'"),
        ));
    }
    Ok(label)
}

/// The `[algorithm.sweep]` table: each key with its list of values.
fn sweep_of(
    cx: &Ctx<'_>,
    table: &mut toml::Table,
    label: &str,
    lines: &EntryLines,
) -> Result<Vec<(String, Vec<toml::Value>)>, SpecError> {
    let t = match table.remove("sweep") {
        None => return Ok(Vec::new()),
        Some(toml::Value::Table(t)) => t,
        Some(other) => {
            return Err(cx.invalid(
                lines.at("sweep"),
                format!(
                    "algorithm `{label}`: `sweep` must be a table, found {}",
                    other.type_str()
                ),
            ));
        }
    };
    let mut sweep = Vec::new();
    for (k, v) in t {
        let at = lines.at(&format!("sweep.{k}"));
        if k == "kind" || k == "label" {
            return Err(cx.invalid(at, format!("algorithm `{label}`: cannot sweep `{k}`")));
        }
        let values = sweep_values(&v).map_err(|m| {
            cx.invalid(
                at,
                format!("algorithm `{label}`: `sweep.{k}`: expected {m}"),
            )
        })?;
        sweep.push((k, values));
    }
    Ok(sweep)
}

/// Every combination of swept values, the first key varying slowest; refused before it is
/// built when it would exceed [`MAX_CONFIGURATIONS`].
fn cartesian<T: Clone>(
    cx: &Ctx<'_>,
    sweep: &[(String, Vec<T>)],
    lines: &EntryLines,
) -> Result<Vec<Vec<(String, T)>>, SpecError> {
    let total = sweep
        .iter()
        .fold(1usize, |n, (_, v)| n.saturating_mul(v.len()));
    if total > MAX_CONFIGURATIONS {
        return Err(cx.invalid(
            Some(lines.entry),
            format!(
                "the sweep has {total} combinations; at most {MAX_CONFIGURATIONS} configurations"
            ),
        ));
    }
    let mut combos: Vec<Vec<(String, T)>> = vec![Vec::new()];
    for (k, values) in sweep {
        combos = combos
            .iter()
            .flat_map(|c| {
                values.iter().map(move |v| {
                    let mut c2 = c.clone();
                    c2.push((k.clone(), v.clone()));
                    c2
                })
            })
            .collect();
    }
    Ok(combos)
}

fn swept_configuration(
    cx: &Ctx<'_>,
    base: &toml::Table,
    label: &str,
    descent: sls::DescentModel,
    combo: Vec<(String, (toml::Value, String))>,
    lines: &EntryLines,
) -> Result<Configuration, SpecError> {
    let mut t = base.clone();
    let mut parts = vec![label.to_string()];
    let mut swept = Vec::new();
    for (k, (v, v_label)) in &combo {
        t.insert(k.clone(), v.clone());
        parts.push(format!("{k}={v_label}"));
        // sweep_values admits numbers only, so this always converts.
        swept.push((k.clone(), as_f64(v).unwrap_or_default()));
    }
    let sweep_at = |key: &str| {
        if combo.iter().any(|(ck, _)| ck == key) {
            lines.at(&format!("sweep.{key}"))
        } else {
            lines.at(key)
        }
    };
    let algorithm = algorithm_from_table(cx, &t, label, &sweep_at)?;
    Ok(Configuration {
        label: parts.join(" "),
        algorithm_label: label.to_string(),
        swept,
        algorithm,
        descent,
    })
}

fn as_f64(v: &toml::Value) -> Option<f64> {
    match v {
        toml::Value::Integer(i) => Some(*i as f64),
        toml::Value::Float(f) if f.is_finite() => Some(*f),
        _ => None,
    }
}

/// Expands one sweep value (a list of numbers, or a range table) into a list of TOML values.
fn sweep_values(value: &toml::Value) -> Result<Vec<toml::Value>, String> {
    match value {
        toml::Value::Array(a) if a.is_empty() => Err("a non-empty list".into()),
        toml::Value::Array(a) if a.len() > MAX_SWEEP_STEPS => Err(format!(
            "at most {MAX_SWEEP_STEPS} values, found {}",
            a.len()
        )),
        toml::Value::Array(a) => match a.iter().find(|v| as_f64(v).is_none()) {
            Some(bad) => Err(format!(
                "finite numbers (swept values label the sweep plots' x axis; give other \
                 choices their own [[algorithm]] entry), found `{bad}`"
            )),
            None => Ok(a.clone()),
        },
        toml::Value::Table(t) => range_values(t),
        other => Err(format!(
            "a list of values or a range table {{ from, to, steps, scale }}, found {}",
            other.type_str()
        )),
    }
}

/// The values of a range table `{ from, to, steps, scale }`; integer endpoints give integers.
fn range_values(t: &toml::Table) -> Result<Vec<toml::Value>, String> {
    let r: ParsedRange = toml::Value::Table(t.clone())
        .try_into()
        .map_err(|e: toml::de::Error| e.message().to_string())?;
    let (Some(a), Some(b)) = (as_f64(&r.from), as_f64(&r.to)) else {
        return Err("`from` and `to` to be finite numbers".into());
    };
    if !(2..=MAX_SWEEP_STEPS).contains(&r.steps) {
        return Err(format!(
            "`steps` from 2 to {MAX_SWEEP_STEPS}, found {}",
            r.steps
        ));
    }
    if r.scale == Scale::Log && (a <= 0.0 || b <= 0.0) {
        return Err("positive `from` and `to` for a log range".into());
    }
    let integer =
        matches!(r.from, toml::Value::Integer(_)) && matches!(r.to, toml::Value::Integer(_));
    let mut out: Vec<toml::Value> = Vec::new();
    for i in 0..r.steps {
        let s = i as f64 / (r.steps - 1) as f64;
        let x = match r.scale {
            Scale::Linear => a + s * (b - a),
            Scale::Log => (a.ln() + s * (b.ln() - a.ln())).exp(),
        };
        let v = if integer {
            toml::Value::Integer(x.round() as i64)
        } else {
            // Round to 12 significant digits so labels are clean.
            toml::Value::Float(format!("{x:.12e}").parse().unwrap_or(x))
        };
        if !out.contains(&v) {
            out.push(v);
        }
    }
    Ok(out)
}

/// Formats a swept value for a label: integers plainly, reals with up to 4 significant digits.
pub fn format_value(x: f64) -> String {
    super::labels::format_digits(x, 4)
}

/// Deserialises an `AlgorithmConfig` from a table and validates it. serde's internally tagged
/// enums lose toml's positions, so on failure each key is tried alone to find the culprit and
/// report its line.
fn algorithm_from_table(
    cx: &Ctx<'_>,
    table: &toml::Table,
    label: &str,
    at: &dyn Fn(&str) -> Option<usize>,
) -> Result<AlgorithmConfig, SpecError> {
    let de = |t: &toml::Table| -> Result<AlgorithmConfig, String> {
        toml::Value::Table(t.clone())
            .try_into::<AlgorithmConfig>()
            .map_err(|e| e.message().to_string())
    };
    let config = match de(table) {
        Ok(c) => c,
        Err(whole) => {
            let kind = table.get("kind").cloned();
            for (k, v) in table {
                if k == "kind" {
                    continue;
                }
                let mut single = toml::Table::new();
                if let Some(kind) = &kind {
                    single.insert("kind".into(), kind.clone());
                }
                single.insert(k.clone(), v.clone());
                if let Err(m) = de(&single) {
                    return Err(cx.invalid(at(k), format!("algorithm `{label}`: `{k}`: {m}")));
                }
            }
            return Err(cx.invalid(at("kind"), format!("algorithm `{label}`: {whole}")));
        }
    };
    config.validate().map_err(|e| {
        cx.invalid(
            at(e.field),
            format!("algorithm `{label}`: `{}` {}", e.field, e.message),
        )
    })?;
    Ok(config)
}
