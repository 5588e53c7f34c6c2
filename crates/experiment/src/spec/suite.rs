//! Instances drawn from the named suites of `brdf_published::suite`: an `[instance.suite]`
//! table (one material), a top-level `[[suite]]` table (one instance per material it selects,
//! with shared targets and model options), and the built-in experiment of a suite
//! ([`Spec::suite_experiment`], `brdf-sls check suite:NAME`). The suites' data and generation
//! live in `brdf-published`; this module only names, checks and expands them. A suite instance
//! is a [`Source::Synthetic`] whose `suite` field says where it is drawn from; specs without
//! suites keep their canonical form.

use std::collections::BTreeMap;
use std::path::Path;

use brdf_io::Channel;
use brdf_model::{DataSet, FamilyRef, Params};
use brdf_published::suite::{self as published, Noise, Sampling, Selection, SuiteError};
use serde::Serialize;
use toml::Spanned;

use super::limits::MAX_SAMPLES;
use super::parsed::{ParsedInstance, ParsedSuite, ParsedSuiteRef, line_of};
use super::{Source, Spec, SpecError};

/// What a spec path names when it is a suite's built-in experiment: `suite:NAME`.
pub const SUITE_PREFIX: &str = "suite:";

/// Relative noise of a suite instance when `noise` is not given: 1% of each value (a
/// noise-free instance has a best-known RMSE of 0, which relative targets cannot use).
pub const DEFAULT_NOISE: f64 = 0.01;

/// Where a suite instance is drawn from (the canonical form records it).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SuiteSource {
    /// The suite (`ngan-ward`).
    pub suite: String,
    /// The material (`gold-metallic-paint`).
    pub material: String,
    /// The colour channel of the published fit.
    pub channel: Channel,
    /// The sampling pattern.
    #[serde(serialize_with = "sampling_name")]
    pub sampling: Sampling,
    /// Noise standard deviation relative to each value (the absolute part is the source's
    /// `sigma`).
    pub noise: f64,
}

fn sampling_name<S: serde::Serializer>(s: &Sampling, ser: S) -> Result<S::Ok, S::Error> {
    ser.serialize_str(s.name())
}

impl SuiteSource {
    /// The instance's data: [`brdf_published::suite::generate`] with the noise
    /// `sqrt((noise f)^2 + sigma^2)`.
    pub fn generate(
        &self,
        params: &Params,
        samples: usize,
        sigma: f64,
        seed: u64,
    ) -> Result<DataSet, SuiteError> {
        let noise = Noise {
            relative: self.noise,
            absolute: sigma,
        };
        published::generate(params, self.sampling, samples, noise, seed)
    }
}

/// An error at a line of the spec, `(line, message)`; the caller, who knows the file, makes it
/// a [`SpecError`].
pub(super) type Located = (Option<usize>, String);

/// The spec text, for the lines errors point at.
struct Cx<'a>(&'a str);

impl Cx<'_> {
    fn line<T>(&self, v: &Spanned<T>) -> Option<usize> {
        Some(line_of(self.0, v.span().start))
    }

    fn invalid(&self, line: Option<usize>, message: String) -> Located {
        (line, message)
    }
}

/// The suite called `name`, or an error at `line` naming `key` and listing the suites.
fn find(
    cx: &Cx<'_>,
    line: Option<usize>,
    key: &str,
    name: &str,
) -> Result<&'static published::Suite, Located> {
    published::suite(name).map_err(|e| cx.invalid(line, format!("{key}: {e}")))
}

/// The source of an `[instance.suite]` table: the material's parameters and the draw, checked.
pub(super) fn source(
    text: &str,
    name: &str,
    raw: Spanned<ParsedSuiteRef>,
) -> Result<Source, Located> {
    let cx = &Cx(text);
    let line = cx.line(&raw);
    let r = raw.into_inner();
    let at = |key: &str| format!("instance `{name}`: `suite.{key}`");
    let suite = find(cx, cx.line(&r.suite), &at("suite"), r.suite.get_ref())?;
    let channel = r.channel.unwrap_or(brdf_published::DEFAULT_CHANNEL);
    let material = suite
        .material(r.material.get_ref(), channel)
        .map_err(|e| cx.invalid(cx.line(&r.material), format!("{}: {e}", at("material"))))?;
    let sampling = match &r.sampling {
        Some(s) => Sampling::from_name(s.get_ref())
            .map_err(|e| cx.invalid(cx.line(s), format!("{}: {e}", at("sampling"))))?,
        None => Sampling::Merl,
    };
    let samples = r
        .samples
        .as_ref()
        .map_or(sampling.default_samples(), |s| *s.get_ref());
    let max = sampling.max_samples().min(MAX_SAMPLES);
    if !(1..=max).contains(&samples) {
        return Err(cx.invalid(
            r.samples.as_ref().and_then(|s| cx.line(s)).or(line),
            format!(
                "{}: `{sampling}` sampling gives 1 to {max} samples, found {samples}",
                at("samples")
            ),
        ));
    }
    let noise = Noise {
        relative: r.noise.as_ref().map_or(DEFAULT_NOISE, |n| *n.get_ref()),
        absolute: r.sigma.as_ref().map_or(0.0, |n| *n.get_ref()),
    };
    // The line of the part out of range (the relative one when both are).
    let relative_ok = noise.relative.is_finite() && (0.0..=10.0).contains(&noise.relative);
    let culprit = if relative_ok { &r.sigma } else { &r.noise };
    let noise_line = culprit.as_ref().and_then(|n| cx.line(n));
    noise.check().map_err(|_| {
        cx.invalid(
            noise_line.or(line),
            format!(
                "{} and `suite.sigma`: `noise` (relative) must be a finite number in [0, 10] and \
                 `sigma` (absolute) in [0, {}], found {} and {}",
                at("noise"),
                brdf_model::MAX_SIGMA,
                noise.relative,
                noise.absolute
            ),
        )
    })?;
    Ok(Source::Synthetic {
        name: Some(format!("{}/{}", suite.name(), material.name)),
        params: material.params,
        samples,
        sigma: noise.absolute,
        seed: r.seed.unwrap_or(1),
        suite: Some(SuiteSource {
            suite: suite.name().to_string(),
            material: r.material.into_inner(),
            channel,
            sampling,
            noise: noise.relative,
        }),
    })
}

/// Widens the model's `bounds` where the suite instance's material needs it (the suite's
/// stated bound, e.g. `lobe1.n` in [0, 20000] for the Lafortune materials with `n > 10000`),
/// when the model is of the material's family; a bound the spec gives itself must admit the
/// material. Nothing happens for other sources or families.
pub(super) fn widen(
    text: &str,
    name: &str,
    line: Option<usize>,
    source: &Source,
    family: &FamilyRef,
    bounds: &mut BTreeMap<String, [f64; 2]>,
) -> Result<(), Located> {
    let cx = &Cx(text);
    let Source::Synthetic {
        params,
        suite: Some(s),
        ..
    } = source
    else {
        return Ok(());
    };
    if params.family() != family {
        return Ok(());
    }
    let suite = find(cx, line, &format!("instance `{name}`"), &s.suite)?;
    for v in brdf_published::bounds_violations(params) {
        let widened = suite.widened_bounds().iter().find(|w| w.0 == v.name);
        match (bounds.get(&v.name), widened) {
            (Some(&[lo, hi]), _) if (lo..=hi).contains(&v.value) => {}
            (Some(&[lo, hi]), _) => {
                return Err(cx.invalid(
                    line,
                    format!(
                        "instance `{name}`: material `{}` has {} = {}, outside `model.bounds.\"{}\"` = [{lo}, {hi}]",
                        s.material, v.name, v.value, v.name
                    ),
                ));
            }
            (None, Some(&(field, lo, hi))) => {
                bounds.insert(field.to_string(), [lo, hi]);
            }
            (None, None) => {
                return Err(cx.invalid(
                    line,
                    format!(
                        "instance `{name}`: suite `{}`: material `{}` is excluded: {v}",
                        s.suite, s.material
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Every `[[suite]]` table expanded into `[[instance]]`s, one per selected material (named
/// `prefix` + material), sharing the table's targets, draw and model.
pub(super) fn expand(
    text: &str,
    raw: Vec<Spanned<ParsedSuite>>,
) -> Result<Vec<ParsedInstance>, Located> {
    let cx = &Cx(text);
    let mut out = Vec::new();
    for (k, table) in raw.into_iter().enumerate() {
        let tline = cx.line(&table);
        let t = table.into_inner();
        let at = format!("[[suite]] {}", k + 1);
        let suite = find(
            cx,
            cx.line(&t.suite),
            &format!("{at}: `suite`"),
            t.suite.get_ref(),
        )?;
        let channel = t.channel.unwrap_or(brdf_published::DEFAULT_CHANNEL);
        let mline = t.materials.as_ref().and_then(|m| cx.line(m)).or(tline);
        let selection = match &t.materials {
            None => Selection::All,
            Some(v) => selection(v.get_ref())
                .map_err(|m| cx.invalid(mline, format!("{at}: `materials{m}")))?,
        };
        if t.prefix.as_deref().is_some_and(|p| p.contains('/')) {
            return Err(cx.invalid(tline, format!("{at}: `prefix` must contain no '/'")));
        }
        let materials = suite
            .select(&selection, channel)
            .map_err(|e| cx.invalid(mline, format!("{at}: `materials`: {e}")))?;
        let span = t.suite.span();
        for m in materials {
            let draw = ParsedSuiteRef {
                suite: t.suite.clone(),
                material: Spanned::new(span.clone(), m.name.clone()),
                channel: t.channel,
                sampling: t.sampling.clone(),
                samples: t.samples.clone(),
                noise: t.noise.clone(),
                sigma: t.sigma.clone(),
                seed: t.seed,
            };
            out.push(ParsedInstance {
                name: Spanned::new(
                    span.clone(),
                    format!("{}{}", t.prefix.as_deref().unwrap_or(""), m.name),
                ),
                targets: t.targets.clone(),
                synthetic: None,
                file: None,
                suite: Some(Spanned::new(span.clone(), draw)),
                model: t.model.clone(),
            });
        }
    }
    Ok(out)
}

/// `materials` as written: `"all"`, `"in-bounds"`, a list of names, or `{ sample = k, seed =
/// s }`; the error continues the sentence "`materials`...".
fn selection(v: &toml::Value) -> Result<Selection, String> {
    match v {
        toml::Value::String(s) if s == "all" => Ok(Selection::All),
        toml::Value::String(s) if s == "in-bounds" => Ok(Selection::InBounds),
        toml::Value::Array(items) => {
            let mut names = Vec::with_capacity(items.len());
            for (i, item) in items.iter().enumerate() {
                match item.as_str() {
                    Some(s) if !names.iter().any(|n| n == s) => names.push(s.to_string()),
                    Some(s) => return Err(format!("[{i}]`: `{s}` is listed twice")),
                    None => {
                        return Err(format!(
                            "[{i}]` must be a material name, found {}",
                            item.type_str()
                        ));
                    }
                }
            }
            if names.is_empty() {
                return Err("` is an empty list".into());
            }
            Ok(Selection::Names(names))
        }
        toml::Value::Table(t) => {
            if let Some(k) = t.keys().find(|k| *k != "sample" && *k != "seed") {
                return Err(format!(
                    "`: unknown key `{k}`; expected `sample` (how many) and `seed`"
                ));
            }
            let int = |key: &str| match t.get(key) {
                None => Ok(None),
                Some(toml::Value::Integer(i)) if *i >= 0 => Ok(Some(*i as u64)),
                Some(other) => Err(format!(".{key}` must be an integer >= 0, found {other}")),
            };
            let count = int("sample")?.ok_or("`: the table needs `sample` (how many)")?;
            Ok(Selection::Sample {
                count: count as usize,
                seed: int("seed")?.unwrap_or(1),
            })
        }
        other => Err(format!(
            "` must be \"all\", \"in-bounds\", a list of material names or {{ sample = k, seed = s }}, found {other}"
        )),
    }
}

impl Spec {
    /// The built-in experiment of the suite `name` (what `brdf-sls check suite:NAME` and `run
    /// suite:NAME` run): every usable material of the suite, green channel, `merl` sampling of
    /// 10,000 cells, noise 1% of each value, instance seed 1; AED and RPLS with their defaults,
    /// 10 trials each per material, 1 CPU second per trial; targets 1% above each instance's
    /// best-known RMSE. Its text is generated (and stored with results like any spec's). An
    /// unknown name is an error listing the suites.
    pub fn suite_experiment(name: &str) -> Result<Spec, SpecError> {
        let origin = format!("{SUITE_PREFIX}{name}");
        let suite = published::suite(name).map_err(|e| SpecError::Invalid {
            path: origin.clone(),
            line: None,
            message: if name.is_empty() {
                let list: Vec<String> = published::suites()
                    .iter()
                    .map(|s| format!("{} (family {})", s.name(), s.family_name()))
                    .collect();
                format!(
                    "a suite name is needed after `{SUITE_PREFIX}`; the suites: {}",
                    list.join(", ")
                )
            } else {
                e.to_string()
            },
        })?;
        let count = suite
            .select(&Selection::All, brdf_published::DEFAULT_CHANNEL)
            .map(|m| m.len())
            .unwrap_or(0);
        let description = format!(
            "the built-in experiment of suite `{name}`: {count} materials, family {} ({}); \
             green channel, merl sampling of 10000 cells, noise 1% of each value, instance \
             seed 1; AED and RPLS, 10 trials per material, 1 CPU s per trial; targets 1% \
             above each instance's best-known RMSE",
            suite.family_name(),
            suite.description()
        );
        let text = format!(
            "# {origin}: generated by Spec::suite_experiment\n\
             name = \"suite-{name}\"\n\
             description = {}\n\
             seed = 1\n\
             trials = 10\n\n\
             [budget]\n\
             cpu_seconds = 1.0\n\n\
             [[suite]]\n\
             suite = \"{name}\"\n\
             materials = \"all\"\n\
             sampling = \"merl\"\n\
             samples = 10000\n\
             noise = 0.01\n\
             seed = 1\n\
             targets = [{{ relative = 0.01 }}]\n\n\
             [[algorithm]]\n\
             kind = \"aed\"\n\n\
             [[algorithm]]\n\
             kind = \"rpls\"\n",
            toml::Value::String(description)
        );
        Spec::parse(&text, &origin, &format!("suite-{name}"), Path::new("."))
    }
}
