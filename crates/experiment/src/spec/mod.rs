//! Experiment specs: one TOML file per experiment, read in stages.
//!
//! The format (every key, its default and its rules) is documented once, in
//! `docs/experiment-format.md`; `experiments/default.toml` is a complete commented example.
//!
//! 1. `parsed`: the TOML as written, into serde structs (`parsed::ParsedSpec`);
//!    unknown keys and wrong types are errors naming the key and its line.
//! 2. `validate`: values, sizes ([`limits`]), instances and models checked, defaults filled in.
//! 3. `sweep`: each `[[algorithm]]` entry expanded into labelled [`Configuration`]s.
//! 4. `plan`: the [`Spec`] (the resolved experiment), its trial plan and the fingerprint
//!    guarding a results file (everything that changes a trial's result, not the trial count,
//!    the other targets, plots or statistics options).
//! 5. `describe`: the readable plan `brdf-sls check` and `run` print.
//!
//! The optional `[tune]` table (automatic tuning with irace) is read and checked by [`tune`].

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use brdf_io::Channel;
use brdf_model::{ExponentCoord, FamilyRef, LobeKind, Params};
use serde::{Deserialize, Serialize};
use sls::{AlgorithmConfig, Budget};

mod describe;
mod labels;
pub mod limits;
mod parsed;
mod plan;
mod suite;
mod sweep;
pub mod tune;
mod validate;

pub use crate::duration::human_seconds;
pub use describe::budget_text;
pub use suite::{DEFAULT_NOISE, SUITE_PREFIX, SuiteSource};
pub use sweep::format_value;

/// The built-in default experiment. The crate embeds its own copy (`src/spec/default.toml`, so
/// the packaged crate is self-contained); the repository's user-facing copy,
/// `experiments/default.toml`, is tested to be byte-identical (`tests/experiments.rs`).
pub const DEFAULT_SPEC: &str = include_str!("default.toml");

/// A spec error: file, line (when known) and what is wrong.
#[derive(Debug, thiserror::Error)]
pub enum SpecError {
    /// The file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// The spec file.
        path: String,
        /// The underlying error.
        source: std::io::Error,
    },
    /// TOML syntax or structure (toml's message carries line and column).
    #[error("{path}: {message}")]
    Toml {
        /// The spec file.
        path: String,
        /// toml's message, with line, column and a snippet.
        message: String,
    },
    /// A value is invalid.
    #[error("{path}{}: {message}", line.map(|l| format!(":{l}")).unwrap_or_default())]
    Invalid {
        /// The spec file.
        path: String,
        /// 1-based line, when known.
        line: Option<usize>,
        /// What is wrong, naming the key.
        message: String,
    },
}

impl SpecError {
    /// The line of the error, when known (toml errors: parsed from toml's span).
    pub fn line(&self) -> Option<usize> {
        match self {
            SpecError::Invalid { line, .. } => *line,
            _ => None,
        }
    }
}

/// A data format's name as a spec or flag gives it (`cornell`, `csv`, `merl`, `alta`: the names
/// of [`brdf_io::Format`], checked when read); stored as written.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(transparent)]
pub struct FormatName(String);

impl FormatName {
    /// The name, checked against the formats' names (the error lists them).
    pub fn new(name: &str) -> Result<Self, String> {
        brdf_io::Format::from_name(name).map_err(|e| e.to_string())?;
        Ok(FormatName(name.trim().to_ascii_lowercase()))
    }

    /// The name.
    pub fn as_str(&self) -> &str {
        &self.0
    }
}

impl<'de> Deserialize<'de> for FormatName {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        FormatName::new(&s).map_err(serde::de::Error::custom)
    }
}

impl std::str::FromStr for FormatName {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        FormatName::new(s)
    }
}

/// A data file instance: path, reader options and filters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FileSpec {
    /// Path as written (relative to the spec file's directory).
    pub path: PathBuf,
    /// Format (default: from the extension; an extension no format has is an error).
    #[serde(default)]
    pub format: Option<FormatName>,
    /// Cornell wavelength in nm (default 550); for Cornell files only.
    #[serde(default)]
    pub wavelength: Option<f64>,
    /// The colour channel of MERL and ALTA RGB files (default green); for those only.
    #[serde(default)]
    pub channel: Option<Channel>,
    /// What an ALTA file's values are when its header has no `#PARAM_OUT` (`"INV_STERADIAN"`,
    /// `"INV_STERADIAN_COSINE_FACTOR"` or `"RGB_COLOR"`, as ALTA writes them); for ALTA files
    /// only. Left out of the canonical
    /// form when unset.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub param_out: Option<brdf_io::AltaOutput>,
    /// Drop values above this.
    #[serde(default)]
    pub max_value: Option<f64>,
    /// Drop negative values (default false: the data policy of every command, see
    /// `brdf_model::Filters::default`).
    #[serde(default)]
    pub drop_negative: bool,
    /// Drop samples below the horizon (default true).
    #[serde(default = "yes")]
    pub drop_below_horizon: bool,
}

fn yes() -> bool {
    true
}

impl FileSpec {
    /// The file at `path` (this spec's path resolved) with only the data policy's defaults:
    /// the format from the extension, every option at its default.
    pub fn plain(path: PathBuf) -> FileSpec {
        FileSpec {
            path,
            format: None,
            wavelength: None,
            channel: None,
            param_out: None,
            max_value: None,
            drop_negative: false,
            drop_below_horizon: true,
        }
    }

    /// The one place a file's format is decided: [`brdf_io::Format`] from `format` (else
    /// from `path`'s extension, which must be one a format has: never a silent default) with
    /// this spec's options applied and checked ([`brdf_io::Format::validate`]); an option
    /// the format does not take is an error naming it.
    pub fn format_for(&self, path: &Path) -> Result<brdf_io::Format, String> {
        use brdf_io::Format;
        let mut f = match &self.format {
            Some(n) => Format::from_name(n.as_str()).map_err(|e| e.to_string())?,
            None => Format::from_path(path).map_err(|e| e.to_string())?,
        };
        let not_for = |key: &str, f: &Format| {
            format!(
                "`{key}` applies to {} files, not {} ones",
                match key {
                    "wavelength" => "cornell",
                    "channel" => "merl and alta",
                    _ => "alta",
                },
                f.name()
            )
        };
        if let Some(w) = self.wavelength {
            match &mut f {
                Format::Cornell { wavelength_nm } => *wavelength_nm = w,
                other => return Err(not_for("wavelength", other)),
            }
        }
        if let Some(c) = self.channel {
            match &mut f {
                Format::Merl { channel } => *channel = c,
                Format::Alta { channel, .. } => *channel = Some(c),
                other => return Err(not_for("channel", other)),
            }
        }
        if let Some(o) = self.param_out {
            match &mut f {
                Format::Alta { param_out, .. } => *param_out = Some(o),
                other => return Err(not_for("param_out", other)),
            }
        }
        f.validate().map_err(|e| e.to_string())?;
        Ok(f)
    }

    /// The reader filters this spec asks for: [`brdf_model::Filters::default`] (the one data
    /// policy) with this file's options; non-finite values are always dropped.
    pub fn filters(&self) -> brdf_model::Filters {
        brdf_model::Filters {
            max_value: self.max_value,
            drop_negative: self.drop_negative,
            drop_below_horizon: self.drop_below_horizon,
            ..brdf_model::Filters::default()
        }
    }
}

/// Where an instance's data comes from.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Source {
    /// A synthetic instance generated by `brdf_model::synthetic`.
    Synthetic {
        /// Paper table name, when given by name.
        name: Option<String>,
        /// The generating parameters (of any family).
        params: Params,
        /// Sample count.
        samples: usize,
        /// Noise standard deviation.
        sigma: f64,
        /// Instance seed.
        seed: u64,
        /// The suite and material it is drawn from, with its sampling and relative noise
        /// (`[instance.suite]`, `[[suite]]`; `sigma` is then the absolute part of the noise).
        /// `None` for `[instance.synthetic]`, and then left out of the canonical form.
        #[serde(skip_serializing_if = "Option::is_none")]
        suite: Option<SuiteSource>,
    },
    /// A data file.
    File {
        /// File and reader options.
        spec: FileSpec,
        /// The path resolved against the spec's directory.
        #[serde(skip)]
        resolved: PathBuf,
    },
}

/// The model shape to fit.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModelSpec {
    /// The model family (`family = "ggx"`). Left out of the canonical form when it is
    /// Lafortune, the default, so the fingerprints of specs written before families existed
    /// stay valid.
    #[serde(
        skip_serializing_if = "FamilyRef::is_lafortune",
        serialize_with = "family_name"
    )]
    pub family: FamilyRef,
    /// Lobe kinds, one per lobe.
    pub kinds: Vec<LobeKind>,
    /// Exponent coordinate.
    pub exponent: ExponentCoord,
    /// Start distribution of the exponents (`Coordinate`: uniform in the coordinate). Left out
    /// of the canonical form when it is the default, so older fingerprints stay valid.
    #[serde(skip_serializing_if = "is_native_starts")]
    pub starts: sls::StartDist,
    /// Fixed parameters by name.
    pub fixed: BTreeMap<String, f64>,
    /// Bounds overrides by name.
    pub bounds: BTreeMap<String, [f64; 2]>,
}

fn family_name<S: serde::Serializer>(f: &FamilyRef, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(f.name())
}

impl ModelSpec {
    /// A Lafortune model with `lobes` lobes of one kind, default coordinate, nothing fixed.
    pub fn simple(lobes: usize, kind: LobeKind) -> Self {
        Self::of_family(FamilyRef::lafortune(), lobes, kind)
    }

    /// A model of `family` with `lobes` lobes of one kind, default coordinate, nothing fixed.
    pub fn of_family(family: FamilyRef, lobes: usize, kind: LobeKind) -> Self {
        ModelSpec {
            family,
            kinds: vec![kind; lobes],
            exponent: ExponentCoord::default(),
            starts: sls::StartDist::Coordinate,
            fixed: BTreeMap::new(),
            bounds: BTreeMap::new(),
        }
    }

    /// Builds the parameter layout.
    pub fn layout(&self) -> Result<brdf_model::Layout, brdf_model::ModelError> {
        let mut b = brdf_model::Layout::builder_for(&self.family, &self.kinds)?
            .exponent_coord(self.exponent);
        for (name, &[lo, hi]) in &self.bounds {
            b = b.bounds(name, lo, hi)?;
        }
        for (name, &v) in &self.fixed {
            b = b.fix(name, v)?;
        }
        b.build()
    }
}

/// Why a model of `layout` cannot be fitted: every parameter is fixed, so a search has nothing
/// to move and no trial would evaluate a candidate (`None` when a parameter is free). `fit`,
/// `check` and `run` refuse such a model up front with these words; `brdf-sls eval` gives the
/// RMSE of given parameters.
pub fn nothing_to_fit(layout: &brdf_model::Layout) -> Option<String> {
    (layout.dim() == 0).then(|| {
        format!(
            "every parameter is fixed (all {}): nothing to fit; free at least one (the RMSE of \
             given parameters is `brdf-sls eval`'s)",
            layout.all_names().len()
        )
    })
}

fn is_native_starts(s: &sls::StartDist) -> bool {
    *s == sls::StartDist::Coordinate
}

/// One instance of an experiment.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct InstanceSpec {
    /// Name (used in trial keys, seeds and file names).
    pub name: String,
    /// Target RMSEs, ascending; trials run to the first. The absolute targets as written, plus
    /// the relative ones once [`InstanceSpec::resolve_targets`] knows the best-known RMSE.
    pub targets: Vec<f64>,
    /// The absolute targets as written, ascending.
    pub absolute_targets: Vec<f64>,
    /// Relative targets as written (`{ relative = r }`: best-known RMSE times `1 + r`),
    /// ascending.
    pub relative_targets: Vec<f64>,
    /// The best-known RMSE of this instance, once computed or read back
    /// (the `brdf-best-known` crate computes it).
    pub best_known: Option<crate::best_known_record::BestKnown>,
    /// The data.
    pub source: Source,
    /// The model to fit.
    pub model: ModelSpec,
}

impl InstanceSpec {
    /// The target trials run to (the lowest); NaN while relative targets are unresolved and
    /// no absolute target is given (a NaN target is never reached, so nothing runs to it).
    pub fn run_target(&self) -> f64 {
        self.targets.first().copied().unwrap_or(f64::NAN)
    }

    /// The run target in the fingerprint: the lowest absolute target as before when there are
    /// no relative targets (older fingerprints stay valid); otherwise both lowest values as
    /// written, so the fingerprint does not depend on the best-known RMSE's last bits.
    pub fn canonical_run_target(&self) -> serde_json::Value {
        if self.relative_targets.is_empty() {
            return serde_json::json!(self.absolute_targets.first());
        }
        serde_json::json!({
            "absolute": self.absolute_targets.first(),
            "relative": self.relative_targets.first(),
        })
    }

    /// The text naming target `t` in file names: the number for an absolute target,
    /// `rel<r>` for a resolved relative one (its value depends on the best-known RMSE's last
    /// bits, which make poor file names).
    pub fn target_label(&self, t: f64) -> String {
        if self.absolute_targets.contains(&t) {
            return format!("{t}");
        }
        let bk = self.best_known.as_ref().map(|b| b.rmse);
        match self
            .relative_targets
            .iter()
            .find(|&&r| bk.is_some_and(|bk| bk * (1.0 + r) == t))
        {
            Some(r) => format!("rel{r}"),
            None => format!("{t}"),
        }
    }

    /// Sets the best-known RMSE and resolves the relative targets against it (idempotent).
    pub fn resolve_targets(&mut self, known: crate::best_known_record::BestKnown) {
        let best_known = known.rmse;
        self.best_known = Some(known);
        let mut all = self.absolute_targets.clone();
        all.extend(self.relative_targets.iter().map(|r| best_known * (1.0 + r)));
        all.sort_by(f64::total_cmp);
        all.dedup();
        self.targets = all;
    }
}

/// One expanded algorithm configuration.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Configuration {
    /// Unique label, e.g. `"AED phi=1.2"`.
    pub label: String,
    /// The `[[algorithm]]` label it came from.
    pub algorithm_label: String,
    /// Swept parameters and their values in this configuration.
    pub swept: Vec<(String, f64)>,
    /// The algorithm and all its parameters.
    pub algorithm: AlgorithmConfig,
    /// The descents' solver configuration (the entry's `descent` key).
    pub descent: sls::DescentModel,
}

/// Plot kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PlotKind {
    /// RTD in CPU time.
    Rtd,
    /// RTD in sample-evaluations.
    RtdEvaluations,
    /// ERT and median against a swept parameter.
    Sweep,
    /// Best RMSE against CPU time for some trials.
    Trace,
    /// Run time against final RMSE.
    Scatter,
    /// Median time and ERT against the target RMSE.
    ErrorTime,
    /// COCO-style ECDF aggregated over targets.
    Ecdf,
}

impl PlotKind {
    /// Every plot kind.
    pub const ALL: [PlotKind; 7] = [
        PlotKind::Rtd,
        PlotKind::RtdEvaluations,
        PlotKind::Sweep,
        PlotKind::Trace,
        PlotKind::Scatter,
        PlotKind::ErrorTime,
        PlotKind::Ecdf,
    ];
}

/// Image formats of the plots.
pub use brdf_graphics::ImageFormat as PlotFormat;

/// The `[plots]` table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PlotSpec {
    /// Which plots to draw.
    pub draw: Vec<PlotKind>,
    /// Image formats.
    pub formats: Vec<PlotFormat>,
    /// Trials per configuration in the trace plot.
    pub trace_trials: usize,
    /// Target range of the error-time and ECDF plots (default: from the traces).
    pub error_range: Option<[f64; 2]>,
    /// Targets in that range.
    pub error_steps: usize,
}

impl Default for PlotSpec {
    fn default() -> Self {
        PlotSpec {
            draw: PlotKind::ALL.to_vec(),
            formats: vec![PlotFormat::Png, PlotFormat::Svg],
            trace_trials: 3,
            error_range: None,
            error_steps: 25,
        }
    }
}

/// The `[stats]` table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct StatsSpec {
    /// Bootstrap resamples.
    pub bootstrap: usize,
}

impl Default for StatsSpec {
    fn default() -> Self {
        StatsSpec { bootstrap: 1000 }
    }
}

/// A resolved experiment: validated, defaults filled in, sweeps expanded into configurations
/// (what everything after reading runs on). The TOML as written is a different type, the
/// private `parsed::ParsedSpec`, and only [`Spec::parse`] turns one into the other.
#[derive(Clone, Debug, PartialEq)]
pub struct Spec {
    /// Experiment name.
    pub name: String,
    /// Free text.
    pub description: Option<String>,
    /// Master seed.
    pub seed: u64,
    /// Trials per (instance, configuration).
    pub trials: u32,
    /// Default thread count.
    pub threads: Option<usize>,
    /// Evaluation kernel (`--kernel` overrides it). Not part of the fingerprint: kernels agree
    /// to rounding, and each session records the one it used.
    pub kernel: brdf_model::Kernel,
    /// Per-trial budget.
    pub budget: Budget,
    /// Instances.
    pub instances: Vec<InstanceSpec>,
    /// Expanded configurations.
    pub configurations: Vec<Configuration>,
    /// Plot options.
    pub plots: PlotSpec,
    /// Statistics options.
    pub stats: StatsSpec,
    /// The optional `[tune]` table (`brdf-sls tune`); not part of the fingerprint.
    pub tune: Option<tune::TuneSpec>,
    /// Directory relative paths resolve against.
    pub base_dir: PathBuf,
    /// The spec's TOML text (stored in the results header so `plot`/`stats` can work from a
    /// results directory alone).
    pub text: String,
}

/// One trial to run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlannedTrial {
    /// Index into [`Spec::instances`].
    pub instance: usize,
    /// Index into [`Spec::configurations`].
    pub config: usize,
    /// Trial index.
    pub trial: u32,
    /// Derived seed.
    pub seed: u64,
    /// Key `instance/config/trial`.
    pub key: String,
}

impl Spec {
    /// Reads and validates a spec file, including the limits only new runs are held to
    /// (label length: [`limits::MAX_LABEL_CHARS`]).
    pub fn from_file(path: &Path) -> Result<Spec, SpecError> {
        let text = crate::input_file::read_spec_text(path).map_err(|source| SpecError::Io {
            path: path.display().to_string(),
            source,
        })?;
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "experiment".into());
        let dir = path
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let origin = path.display().to_string();
        let spec = Spec::parse(&text, &origin, &stem, dir)?;
        let cx = validate::Ctx {
            text: &text,
            origin: &origin,
        };
        validate::label_lengths(&cx, &spec.configurations)?;
        Ok(spec)
    }

    /// The built-in default experiment (relative paths resolve against the current directory).
    pub fn default_experiment() -> Spec {
        // The embedded file is tested to parse (see tests); a failure here is a build defect.
        Spec::parse(
            DEFAULT_SPEC,
            "<built-in default>",
            "default",
            Path::new("."),
        )
        .unwrap_or_else(|e| panic!("built-in default experiment is invalid: {e}"))
    }

    /// Parses and validates spec text. `origin` names it in errors, `stem` is the default
    /// experiment name, `base_dir` resolves relative paths. The stages: `parsed` (TOML into
    /// serde structs, as written), `validate` (values, sizes, instances and models), `sweep`
    /// (configurations), then the plan's size.
    pub fn parse(text: &str, origin: &str, stem: &str, base_dir: &Path) -> Result<Spec, SpecError> {
        let parsed = parsed::parse(text, origin)?;
        let cx = validate::Ctx { text, origin };
        let budget = validate::budget(&cx, parsed.budget)?;
        validate::counts(&cx, &parsed.trials, parsed.threads.as_ref())?;
        let mut raw_instances = parsed.instances;
        raw_instances
            .extend(suite::expand(text, parsed.suites).map_err(|(l, m)| cx.invalid(l, m))?);
        let instances = validate::instances(&cx, raw_instances, base_dir)?;
        let configurations = sweep::configurations(&cx, parsed.algorithms)?;
        validate::options(&cx, &parsed.plots, &parsed.stats)?;
        validate::plan_size(
            &cx,
            *parsed.trials.get_ref(),
            instances.len(),
            configurations.len(),
        )?;
        if parsed.tune.is_some()
            && let Some(i) = instances.iter().find(|i| !i.relative_targets.is_empty())
        {
            return Err(SpecError::Invalid {
                path: origin.to_string(),
                line: None,
                message: format!(
                    "instance `{}`: relative targets are not supported with [tune]; give absolute `targets`",
                    i.name
                ),
            });
        }
        let tune = match parsed.tune {
            Some(t) => Some(validate::tune(
                &cx,
                t,
                &instances,
                &configurations,
                &budget,
            )?),
            None => None,
        };
        Ok(Spec {
            name: validate::name(&cx, parsed.name, stem)?,
            description: parsed.description,
            seed: parsed.seed,
            trials: parsed.trials.into_inner(),
            threads: parsed.threads.map(toml::Spanned::into_inner),
            kernel: parsed.kernel,
            budget,
            instances,
            configurations,
            plots: parsed.plots,
            stats: parsed.stats,
            tune,
            base_dir: base_dir.to_path_buf(),
            text: text.to_string(),
        })
    }

    /// Configuration labels in order.
    pub fn config_labels(&self) -> Vec<String> {
        self.configurations
            .iter()
            .map(|c| c.label.clone())
            .collect()
    }

    /// Instance names in order.
    pub fn instance_names(&self) -> Vec<String> {
        self.instances.iter().map(|i| i.name.clone()).collect()
    }

    /// True when some instance has relative targets not yet resolved.
    pub fn has_unresolved_targets(&self) -> bool {
        self.instances
            .iter()
            .any(|i| !i.relative_targets.is_empty() && i.best_known.is_none())
    }

    /// The best-known RMSE of every instance that has one, by name (recorded with results).
    pub fn best_known(&self) -> BTreeMap<String, crate::best_known_record::BestKnown> {
        self.instances
            .iter()
            .filter_map(|i| Some((i.name.clone(), i.best_known.clone()?)))
            .collect()
    }

    /// Each instance's targets.
    pub fn targets(&self) -> Vec<(String, Vec<f64>)> {
        self.instances
            .iter()
            .map(|i| (i.name.clone(), i.targets.clone()))
            .collect()
    }
}

/// Algorithm kinds registered in this process: sls's built-ins, then any added with
/// `sls::registry::register`.
pub fn known_kinds() -> Vec<&'static str> {
    sls::registry::kinds()
}

#[cfg(test)]
mod tests;
