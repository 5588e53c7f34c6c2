//! Stage 2 of reading a spec: checking the raw values and turning them into the validated
//! types, with errors that name the file, the line and the key. Sizes are checked against the
//! limits in [`super::limits`] before anything is allocated or generated.

use std::path::Path;

use brdf_model::{ExponentCoord, LobeKind};
use sls::Budget;
use toml::Spanned;

use crate::params::ParamsInput;

use super::limits::{
    MAX_BOOTSTRAP, MAX_CPU_SECONDS, MAX_ERROR_STEPS, MAX_LABEL_CHARS, MAX_LOBES,
    MAX_PLANNED_TRIALS, MAX_SAMPLE_PARAMS, MAX_SAMPLES, MAX_TARGETS, MAX_TRACE_TRIALS,
};
use super::parsed::{ParsedBudget, ParsedInstance, ParsedModel, ParsedSynthetic, line_of};
use super::{InstanceSpec, ModelSpec, PlotSpec, Source, SpecError, StatsSpec};

/// Where errors point: the spec text (for line numbers) and its name.
pub(super) struct Ctx<'a> {
    /// The spec's TOML text.
    pub(super) text: &'a str,
    /// The file name (or `<built-in default>`) errors start with.
    pub(super) origin: &'a str,
}

impl Ctx<'_> {
    /// An error at `line` (when known).
    pub(super) fn invalid(&self, line: Option<usize>, message: String) -> SpecError {
        SpecError::Invalid {
            path: self.origin.to_string(),
            line,
            message,
        }
    }

    /// The line a spanned value starts on.
    pub(super) fn line<T>(&self, v: &Spanned<T>) -> Option<usize> {
        Some(line_of(self.text, v.span().start))
    }
}

/// The `[budget]` table: at least one positive, finite limit.
pub(super) fn budget(cx: &Ctx<'_>, raw: Spanned<ParsedBudget>) -> Result<Budget, SpecError> {
    let line = cx.line(&raw);
    let rb = raw.into_inner();
    if let Some(c) = rb.cpu_seconds
        && !(c > 0.0 && c <= MAX_CPU_SECONDS)
    {
        return Err(cx.invalid(
            line,
            format!(
                "`budget.cpu_seconds` must be a positive number of at most {MAX_CPU_SECONDS:e}, found {}",
                crate::spec::format_value(c)
            ),
        ));
    }
    if let Some(e) = rb.evaluations
        && !(e.is_finite() && (1.0..=u64::MAX as f64).contains(&e))
    {
        return Err(cx.invalid(
            line,
            format!("`budget.evaluations` must be a number from 1 to 1.8e19, found {e}"),
        ));
    }
    if rb.cpu_seconds.is_none() && rb.evaluations.is_none() {
        return Err(cx.invalid(
            line,
            "`budget` needs `cpu_seconds` or `evaluations` (a target may be unreachable)".into(),
        ));
    }
    Ok(Budget {
        cpu_seconds: rb.cpu_seconds,
        sample_evaluations: rb.evaluations.map(|e| e as u64),
    })
}

/// `trials` and `threads`, refused naming their lines.
pub(super) fn counts(
    cx: &Ctx<'_>,
    trials: &Spanned<u32>,
    threads: Option<&Spanned<usize>>,
) -> Result<(), SpecError> {
    if *trials.get_ref() == 0 {
        return Err(cx.invalid(cx.line(trials), "`trials` must be at least 1".into()));
    }
    if let Some(n) = threads {
        crate::threads::check(*n.get_ref(), "`threads`").map_err(|m| cx.invalid(cx.line(n), m))?;
    }
    Ok(())
}

/// Every `[[instance]]`, in order; names must be unique.
pub(super) fn instances(
    cx: &Ctx<'_>,
    raw: Vec<ParsedInstance>,
    base_dir: &Path,
) -> Result<Vec<InstanceSpec>, SpecError> {
    if raw.is_empty() {
        return Err(cx.invalid(
            None,
            "at least one [[instance]] or [[suite]] is needed".into(),
        ));
    }
    let mut out: Vec<InstanceSpec> = Vec::new();
    for ri in raw {
        let line = cx.line(&ri.name);
        let inst = instance(cx, ri, base_dir)?;
        if out.iter().any(|i| i.name == inst.name) {
            return Err(cx.invalid(
                line,
                format!(
                    "instance `{}`: duplicate name (a [[suite]] names its instances by material;                      its `prefix` keeps them apart)",
                    inst.name
                ),
            ));
        }
        out.push(inst);
    }
    Ok(out)
}

fn instance(cx: &Ctx<'_>, ri: ParsedInstance, base_dir: &Path) -> Result<InstanceSpec, SpecError> {
    let line = cx.line(&ri.name);
    let name = ri.name.into_inner();
    if name.is_empty() || name.contains('/') {
        return Err(cx.invalid(
            line,
            format!("instance `{name}`: `name` must be non-empty and contain no '/'"),
        ));
    }
    let (targets, relative_targets) = targets(cx, &name, ri.targets)?;
    // The truth of a synthetic instance is checked against the model's box, with the bounds
    // the model widens (well-formed entries only: the others are refused with the model).
    let widened: std::collections::BTreeMap<String, [f64; 2]> = ri
        .model
        .as_ref()
        .and_then(|m| m.get_ref().bounds.as_ref())
        .map(|b| {
            b.get_ref()
                .iter()
                .filter_map(|(k, v)| match v[..] {
                    [lo, hi] => Some((k.clone(), [lo, hi])),
                    _ => None,
                })
                .collect()
        })
        .unwrap_or_default();
    let source = match (ri.synthetic, ri.file, ri.suite) {
        (Some(s), None, None) => synthetic(cx, &name, line, s, &widened)?,
        (None, Some(f), None) => file(cx, &name, f, base_dir)?,
        (None, None, Some(s)) => {
            super::suite::source(cx.text, &name, s).map_err(|(l, m)| cx.invalid(l, m))?
        }
        _ => {
            return Err(cx.invalid(
                line,
                format!(
                    "instance `{name}`: needs exactly one of [instance.synthetic], [instance.file] or [instance.suite]"
                ),
            ));
        }
    };
    let model = model(cx, &name, line, ri.model, &source)?;
    Ok(InstanceSpec {
        name,
        absolute_targets: targets.clone(),
        targets,
        relative_targets,
        best_known: None,
        source,
        model,
    })
}

/// The targets as written: absolute RMSEs and relative ones (`{ relative = r }`: the
/// instance's best-known RMSE times `1 + r`), each ascending and without duplicates.
fn targets(
    cx: &Ctx<'_>,
    name: &str,
    raw: Spanned<Vec<toml::Value>>,
) -> Result<(Vec<f64>, Vec<f64>), SpecError> {
    let line = cx.line(&raw);
    let entries = raw.into_inner();
    if entries.is_empty() || entries.len() > MAX_TARGETS {
        return Err(cx.invalid(
            line,
            format!(
                "instance `{name}`: `targets` must be a list of 1 to {MAX_TARGETS} RMSEs or {{ relative = r }} tables"
            ),
        ));
    }
    let (mut absolute, mut relative) = (Vec::new(), Vec::new());
    for (k, v) in entries.iter().enumerate() {
        match target_entry(v)
            .map_err(|m| cx.invalid(line, format!("instance `{name}`: `targets[{k}]{m}")))?
        {
            Target::Absolute(t) => absolute.push(t),
            Target::Relative(r) => relative.push(r),
        }
    }
    for list in [&mut absolute, &mut relative] {
        list.sort_by(f64::total_cmp);
        list.dedup();
    }
    Ok((absolute, relative))
}

/// One entry of `targets`, as written.
enum Target {
    Absolute(f64),
    Relative(f64),
}

/// Reads one `targets` entry; the error continues the sentence "`targets[k]`...".
fn target_entry(v: &toml::Value) -> Result<Target, String> {
    let number = |v: &toml::Value| match v {
        toml::Value::Float(f) => Some(*f),
        toml::Value::Integer(i) => Some(*i as f64),
        _ => None,
    };
    if let Some(t) = number(v) {
        return if t.is_finite() && t >= 0.0 {
            Ok(Target::Absolute(t))
        } else {
            Err(format!("` must be a finite RMSE >= 0, found {t}"))
        };
    }
    let Some(table) = v.as_table() else {
        return Err(format!(
            "` must be a number or a table {{ relative = r }}, found {}",
            v.type_str()
        ));
    };
    if let Some(k) = table.keys().find(|k| *k != "relative" && *k != "absolute") {
        return Err(format!(
            "`: unknown key `{k}`; expected `relative` (a fraction above the best-known RMSE)"
        ));
    }
    match (table.get("relative"), table.get("absolute")) {
        (Some(_), Some(_)) => {
            Err("`: `relative` and `absolute` are both given; use one per entry".into())
        }
        (None, Some(a)) => target_entry(a).map_err(|m| format!(".absolute{m}")),
        (None, None) => Err("`: empty table; expected { relative = r }".into()),
        (Some(r), None) => match number(r) {
            Some(r) if (0.0..=10.0).contains(&r) => Ok(Target::Relative(r)),
            Some(r) => Err(format!(
                ".relative` must be a finite fraction from 0 to 10 (0.01 = 1% above the best-known RMSE), found {r}"
            )),
            None => Err(format!(
                ".relative` must be a number, found {}",
                r.type_str()
            )),
        },
    }
}

fn synthetic(
    cx: &Ctx<'_>,
    name: &str,
    line: Option<usize>,
    s: ParsedSynthetic,
    bounds: &std::collections::BTreeMap<String, [f64; 2]>,
) -> Result<Source, SpecError> {
    let pline = cx.line(&s.params);
    let origin = format!("instance `{name}`: `synthetic.params`");
    let given =
        crate::params::parse_params_within(&origin, ParamsInput::Toml(s.params.get_ref()), bounds)
            .map_err(|e| cx.invalid(pline, e.to_string()))?;
    if !(1..=MAX_SAMPLES).contains(&s.samples) {
        return Err(cx.invalid(
            line,
            format!(
                "instance `{name}`: `synthetic.samples` must be from 1 to {MAX_SAMPLES}, found {}",
                s.samples
            ),
        ));
    }
    if !(s.sigma.is_finite() && (0.0..=brdf_model::MAX_SIGMA).contains(&s.sigma)) {
        return Err(cx.invalid(
            line,
            format!(
                "instance `{name}`: `synthetic.sigma` must be a finite number in [0, {}], found {}",
                brdf_model::MAX_SIGMA,
                s.sigma
            ),
        ));
    }
    Ok(Source::Synthetic {
        name: given.name,
        params: given.params,
        samples: s.samples,
        sigma: s.sigma,
        seed: s.seed,
        suite: None,
    })
}

fn file(
    cx: &Ctx<'_>,
    name: &str,
    f: Spanned<super::FileSpec>,
    base_dir: &Path,
) -> Result<Source, SpecError> {
    let line = cx.line(&f);
    let f = f.into_inner();
    let resolved = if f.path.is_absolute() {
        f.path.clone()
    } else {
        base_dir.join(&f.path)
    };
    // The one check of the format and its options (the reader applies the same).
    if let Err(e) = f.format_for(&f.path) {
        return Err(cx.invalid(line, format!("instance `{name}`: `file`: {e}")));
    }
    if let Some(m) = f.max_value
        && m.is_nan()
    {
        return Err(cx.invalid(
            line,
            format!("instance `{name}`: `file.max_value` must be a number, found NaN"),
        ));
    }
    Ok(Source::File { spec: f, resolved })
}

fn model(
    cx: &Ctx<'_>,
    name: &str,
    line: Option<usize>,
    raw: Option<Spanned<ParsedModel>>,
    source: &Source,
) -> Result<ModelSpec, SpecError> {
    let mline = raw.as_ref().and_then(|m| cx.line(m));
    let rm = raw.map(Spanned::into_inner).unwrap_or_default();
    let default_lobes = match source {
        Source::Synthetic { params, .. } => params.lobe_count().max(1),
        Source::File { .. } => 1,
    };
    // The family: as written, else the synthetic parameters' (data made by a model is fitted
    // by it unless the spec says otherwise), else Lafortune.
    let family = match &rm.family {
        Some(f) => brdf_model::family(f.get_ref()).map_err(|e| {
            cx.invalid(
                cx.line(f),
                format!("instance `{name}`: `model.family`: {e}"),
            )
        })?,
        None => match source {
            Source::Synthetic { params, .. } => params.family().clone(),
            Source::File { .. } => brdf_model::FamilyRef::lafortune(),
        },
    };
    // A suite's materials are published as one isotropic lobe: fitted so by default.
    let from_suite = matches!(source, Source::Synthetic { suite: Some(_), .. });
    let default_kind = if from_suite && family.kinds().contains(&LobeKind::Isotropic) {
        LobeKind::Isotropic
    } else if family.kinds().contains(&LobeKind::Anisotropic) {
        LobeKind::Anisotropic
    } else {
        family.kinds()[0]
    };
    let kinds = match rm.kinds {
        Some(k) if !k.is_empty() => k,
        Some(_) => {
            return Err(cx.invalid(mline, format!("instance `{name}`: `model.kinds` is empty")));
        }
        None => {
            let lobes = rm.lobes.unwrap_or(default_lobes);
            if !(1..=MAX_LOBES).contains(&lobes) {
                return Err(cx.invalid(
                    mline,
                    format!("instance `{name}`: `model.lobes` must be from 1 to {MAX_LOBES}, found {lobes}"),
                ));
            }
            vec![rm.kind.unwrap_or(default_kind); lobes]
        }
    };
    if kinds.len() > MAX_LOBES {
        return Err(cx.invalid(
            mline,
            format!(
                "instance `{name}`: `model.kinds` lists {} lobes; at most {MAX_LOBES}",
                kinds.len()
            ),
        ));
    }
    let fixed_line = rm.fixed.as_ref().and_then(|f| cx.line(f));
    let bounds_line = rm.bounds.as_ref().and_then(|f| cx.line(f));
    let mut bounds = std::collections::BTreeMap::new();
    for (k, v) in rm.bounds.map(Spanned::into_inner).unwrap_or_default() {
        match v[..] {
            [lo, hi] if lo.is_finite() && hi.is_finite() => {
                bounds.insert(k, [lo, hi]);
            }
            _ => {
                return Err(cx.invalid(
                    bounds_line,
                    format!(
                        "instance `{name}`: `model.bounds.\"{k}\"` must be two finite numbers [lo, hi], found {v:?}"
                    ),
                ));
            }
        }
    }
    let at = bounds_line.or(mline).or(line);
    super::suite::widen(cx.text, name, at, source, &family, &mut bounds)
        .map_err(|(l, m)| cx.invalid(l, m))?;
    let fixed = rm.fixed.map(Spanned::into_inner).unwrap_or_default();
    if let Some((k, v)) = fixed.iter().find(|(_, v)| !v.is_finite()) {
        return Err(cx.invalid(
            fixed_line,
            format!("instance `{name}`: `model.fixed.\"{k}\"` must be a finite number, found {v}"),
        ));
    }
    let exponent = rm.exponent.unwrap_or_default();
    let model = ModelSpec {
        family,
        kinds,
        exponent,
        starts: canonical_starts(rm.starts.unwrap_or_default(), exponent),
        fixed,
        bounds,
    };
    let layout = model.layout().map_err(|e| {
        // Point at the `fixed` or `bounds` entry that names the parameter.
        let culprit = match &e {
            brdf_model::ModelError::UnknownParameter { name: n, .. }
            | brdf_model::ModelError::InvalidBounds { name: n, .. }
            | brdf_model::ModelError::FixedOutOfBounds { name: n, .. }
            | brdf_model::ModelError::BeyondBox { name: n, .. } => Some(n.clone()),
            brdf_model::ModelError::UnsupportedKind { .. }
            | brdf_model::ModelError::TooManyLobes { .. } => None,
        };
        let l = match culprit {
            Some(n) if model.fixed.contains_key(&n) => fixed_line,
            Some(n) if model.bounds.contains_key(&n) => bounds_line,
            _ => None,
        };
        cx.invalid(
            l.or(mline).or(line),
            format!("instance `{name}`: model: {e}"),
        )
    })?;
    if let Some(why) = super::nothing_to_fit(&layout) {
        return Err(cx.invalid(
            fixed_line.or(mline).or(line),
            format!("instance `{name}`: model: {why}"),
        ));
    }
    if let Source::Synthetic { samples, .. } = source
        && samples.saturating_mul(layout.dim()) > MAX_SAMPLE_PARAMS
    {
        return Err(cx.invalid(
            mline.or(line),
            format!(
                "instance `{name}`: {samples} samples x {} free parameters is more than {MAX_SAMPLE_PARAMS} \
                 Jacobian entries per worker thread; use fewer samples or lobes",
                layout.dim()
            ),
        ));
    }
    if let Source::Synthetic { samples, .. } = source
        && *samples <= layout.dim()
    {
        return Err(cx.invalid(
            line,
            format!(
                "instance `{name}`: `{}.samples` must be at least the model's free \
                 parameters + 1 ({}) for a fit to be determined, found {samples}",
                if from_suite { "suite" } else { "synthetic" },
                layout.dim() + 1
            ),
        ));
    }
    Ok(model)
}

/// `starts` as stored: `Coordinate` when the asked distribution is the coordinate's own, so
/// that spelling out the default (`starts = "log-uniform"` with log1p) keeps the fingerprint.
fn canonical_starts(starts: sls::StartDist, exponent: ExponentCoord) -> sls::StartDist {
    if starts.resolve(exponent) == sls::StartDist::Coordinate.resolve(exponent) {
        sls::StartDist::Coordinate
    } else {
        starts
    }
}

/// The `[plots]` and `[stats]` tables.
pub(super) fn options(cx: &Ctx<'_>, plots: &PlotSpec, stats: &StatsSpec) -> Result<(), SpecError> {
    if !(1..=MAX_BOOTSTRAP).contains(&stats.bootstrap) {
        return Err(cx.invalid(
            None,
            format!(
                "`stats.bootstrap` must be from 1 to {MAX_BOOTSTRAP}, found {}",
                stats.bootstrap
            ),
        ));
    }
    if let Some([lo, hi]) = plots.error_range
        && !(lo.is_finite() && hi.is_finite() && lo > 0.0 && hi > lo)
    {
        return Err(cx.invalid(
            None,
            "`plots.error_range` must be [lo, hi] with 0 < lo < hi".into(),
        ));
    }
    if !(2..=MAX_ERROR_STEPS).contains(&plots.error_steps) {
        return Err(cx.invalid(
            None,
            format!(
                "`plots.error_steps` must be from 2 to {MAX_ERROR_STEPS}, found {}",
                plots.error_steps
            ),
        ));
    }
    if plots.trace_trials > MAX_TRACE_TRIALS {
        return Err(cx.invalid(
            None,
            format!(
                "`plots.trace_trials` must be at most {MAX_TRACE_TRIALS}, found {}",
                plots.trace_trials
            ),
        ));
    }
    Ok(())
}

/// The plan's size: trials x instances x configurations within [`MAX_PLANNED_TRIALS`].
pub(super) fn plan_size(
    cx: &Ctx<'_>,
    trials: u32,
    instances: usize,
    configurations: usize,
) -> Result<(), SpecError> {
    let n = u64::from(trials)
        .saturating_mul(instances as u64)
        .saturating_mul(configurations as u64);
    if n > MAX_PLANNED_TRIALS {
        return Err(cx.invalid(
            None,
            format!(
                "the plan has {trials} trials x {instances} instance(s) x {configurations} configuration(s) = {n} trials; at most {MAX_PLANNED_TRIALS}"
            ),
        ));
    }
    Ok(())
}

/// Every configuration label within [`MAX_LABEL_CHARS`] characters.
pub(super) fn label_lengths(
    cx: &Ctx<'_>,
    configurations: &[super::Configuration],
) -> Result<(), SpecError> {
    for c in configurations {
        let chars = c.label.chars().count();
        if chars > MAX_LABEL_CHARS {
            let start: String = c.label.chars().take(40).collect();
            return Err(cx.invalid(
                None,
                format!(
                    "algorithm `{start}...`: `label` (with its swept values) has {chars} characters; at most {MAX_LABEL_CHARS}"
                ),
            ));
        }
    }
    Ok(())
}

/// The experiment's name (default: the spec file's stem).
pub(super) fn name(cx: &Ctx<'_>, raw: Option<String>, stem: &str) -> Result<String, SpecError> {
    let name = raw.unwrap_or_else(|| stem.to_string());
    if name.is_empty() || name.contains('/') {
        return Err(cx.invalid(None, "`name` must be non-empty and contain no '/'".into()));
    }
    Ok(name)
}

/// The optional `[tune]` table, checked against the instances, configurations and budget
/// (see [`tune`](super::tune)).
pub(super) fn tune(
    cx: &Ctx<'_>,
    raw: Spanned<super::tune::ParsedTune>,
    instances: &[InstanceSpec],
    configurations: &[super::Configuration],
    budget: &Budget,
) -> Result<super::tune::TuneSpec, SpecError> {
    let line = cx.line(&raw);
    let names: Vec<String> = instances.iter().map(|i| i.name.clone()).collect();
    let configs: Vec<(String, sls::AlgorithmConfig)> = configurations
        .iter()
        .map(|c| (c.label.clone(), c.algorithm.clone()))
        .collect();
    super::tune::TuneSpec::from_raw(raw.into_inner(), &names, &configs, budget)
        .map_err(|m| cx.invalid(line, m))
}
