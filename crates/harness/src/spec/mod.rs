//! Experiment specs: the TOML format, validation, sweep expansion and the trial plan.
//!
//! # Format
//!
//! An experiment is one TOML file. Unknown keys anywhere are errors naming the key and its line;
//! so are values of the wrong type or out of range. Relative data paths resolve against the
//! directory of the spec file. A complete commented example is `experiments/default.toml`.
//!
//! ```toml
//! name = "tuning-aed-sweep"      # optional; default: the spec file's stem
//! description = "free text"      # optional
//! seed = 1                       # master seed (trial seeds are derived from it)
//! trials = 50                    # trials per (instance, configuration)
//! threads = 2                    # optional default for --threads (default: all CPUs)
//!
//! [budget]                       # at least one limit
//! cpu_seconds = 10.0             # CPU-time cutoff per trial (worker thread clock)
//! evaluations = 2e9              # optional sample-evaluation cutoff per trial
//!
//! [[instance]]                   # one or more
//! name = "tuning"
//! targets = [0.11, 0.115, 0.12]  # trials run to the lowest; the others come from the traces
//! [instance.synthetic]           # either synthetic ...
//! params = "tuning"              # "tuning", "cross", "paper-bluepaint", "pbrt-bluepaint", or
//!                                # { kd = 0.15, lobes = [{ cx = -1, cy = 0.8, cz = 0.96, n = 20, pan_deg = 45 }] }
//! samples = 10000                # default 10000
//! sigma = 0.1                    # Gaussian noise; default 0
//! seed = 7                       # instance seed; default 1
//! # [instance.file]              # ... or a data file
//! # path = "data/krylon_blue.brdf"   # relative to this spec file
//! # format = "cornell"           # cornell | csv | merl (default: from the extension)
//! # wavelength = 550             # Cornell: nm (default 550)
//! # channel = "green"            # MERL: red | green | blue (default green)
//! # max_value = 1.0              # drop values above (the paper used 1)
//! # drop_negative = true         # default true
//! # drop_below_horizon = true    # default true
//! [instance.model]               # the model shape to fit (all optional)
//! lobes = 1                      # default: the synthetic params' lobe count, else 1
//! kind = "anisotropic"           # or "isotropic" (Cxy, Cz, n; no pan)
//! # kinds = ["anisotropic", "isotropic"]   # per lobe, overrides lobes/kind
//! exponent = "log1p"             # optimiser coordinate of n: "log1p" (default) or "raw"
//! fixed = { "lobe1.pan" = 45.0 } # parameters held fixed
//! bounds = { "lobe1.n" = [0.0, 200.0] }   # bounds overriding Table 1
//!
//! [[algorithm]]                  # one or more
//! label = "AED"                  # default: the kind in capitals
//! kind = "aed"                   # aed | aers | rpls | ds | sa | sals | avg | asa (sls::AlgorithmConfig)
//! phi = 1.4                      # any parameter of that algorithm; missing = paper default
//! [algorithm.sweep]              # optional: one configuration per value (cartesian product)
//! rho0 = [10, 25, 50]            # a list, or
//! # phi = { from = 1.0, to = 2.0, steps = 5, scale = "linear" }   # linear | log; integer
//! #                              # endpoints give integer values
//!
//! [plots]                        # optional
//! draw = ["rtd", "rtd-evaluations", "sweep", "trace", "scatter", "error-time", "ecdf"]
//! formats = ["png", "svg"]
//! trace_trials = 3               # trials per configuration in the trace plot
//! error_range = [0.11, 0.2]      # target range of the error-time and ECDF plots
//! error_steps = 25
//!
//! [stats]                        # optional
//! bootstrap = 1000               # bootstrap resamples for the ERT
//! ```
//!
//! A swept configuration is labelled by its algorithm label and the swept values, e.g.
//! `"AED phi=1.2"`; labels must be unique. The fingerprint that guards the results file covers
//! everything that changes a trial's result (seed, budget, instances, their lowest target, the
//! expanded configurations with all defaults filled in) but not the trial count, the other
//! targets, plots or statistics options: raising `trials` later resumes and adds trials.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use brdf_model::{BrdfParams, Channel, ExponentCoord, LobeKind};
use serde::{Deserialize, Serialize};
use sls::{AlgorithmConfig, Budget};
use toml::Spanned;

use crate::seed::{fingerprint, trial_seed};

/// The built-in default experiment (experiments/default.toml).
pub const DEFAULT_SPEC: &str = include_str!("../../../experiments/default.toml");

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

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSpec {
    name: Option<String>,
    description: Option<String>,
    seed: u64,
    trials: u32,
    threads: Option<usize>,
    budget: Spanned<RawBudget>,
    #[serde(rename = "instance")]
    instances: Vec<RawInstance>,
    #[serde(rename = "algorithm")]
    algorithms: Vec<Spanned<toml::Table>>,
    #[serde(default)]
    plots: PlotSpec,
    #[serde(default)]
    stats: StatsSpec,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBudget {
    cpu_seconds: Option<f64>,
    evaluations: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawInstance {
    name: Spanned<String>,
    targets: Spanned<Vec<f64>>,
    synthetic: Option<RawSynthetic>,
    file: Option<Spanned<FileSpec>>,
    #[serde(default)]
    model: Option<Spanned<RawModel>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSynthetic {
    params: Spanned<toml::Value>,
    #[serde(default = "default_samples")]
    samples: usize,
    #[serde(default)]
    sigma: f64,
    #[serde(default = "default_instance_seed")]
    seed: u64,
}

fn default_samples() -> usize {
    10_000
}
fn default_instance_seed() -> u64 {
    1
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawModel {
    lobes: Option<usize>,
    kind: Option<LobeKind>,
    kinds: Option<Vec<LobeKind>>,
    exponent: Option<ExponentCoord>,
    fixed: Option<Spanned<BTreeMap<String, f64>>>,
    bounds: Option<Spanned<BTreeMap<String, [f64; 2]>>>,
}

/// Data file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DataFormat {
    /// Cornell `.brdf` text.
    Cornell,
    /// CSV (vectors or angles in degrees).
    Csv,
    /// MERL binary.
    Merl,
}

impl DataFormat {
    /// Guesses the format from a file extension (`.brdf`, `.csv`, `.binary`/`.merl`).
    pub fn from_path(path: &Path) -> Option<Self> {
        match path
            .extension()?
            .to_string_lossy()
            .to_ascii_lowercase()
            .as_str()
        {
            "brdf" => Some(DataFormat::Cornell),
            "csv" => Some(DataFormat::Csv),
            "binary" | "merl" => Some(DataFormat::Merl),
            _ => None,
        }
    }
}

/// A data file instance: path, reader options and filters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FileSpec {
    /// Path as written (relative to the spec file's directory).
    pub path: PathBuf,
    /// Format (default: from the extension).
    #[serde(default)]
    pub format: Option<DataFormat>,
    /// Cornell wavelength in nm (default 550).
    #[serde(default)]
    pub wavelength: Option<f64>,
    /// MERL channel (default green).
    #[serde(default)]
    pub channel: Option<Channel>,
    /// Drop values above this.
    #[serde(default)]
    pub max_value: Option<f64>,
    /// Drop negative values (default true).
    #[serde(default = "yes")]
    pub drop_negative: bool,
    /// Drop samples below the horizon (default true).
    #[serde(default = "yes")]
    pub drop_below_horizon: bool,
}

fn yes() -> bool {
    true
}

impl FileSpec {
    /// The reader filters this spec asks for (non-finite values are always dropped).
    pub fn filters(&self) -> brdf_model::Filters {
        brdf_model::Filters {
            max_value: self.max_value,
            drop_negative: self.drop_negative,
            drop_non_finite: true,
            drop_below_horizon: self.drop_below_horizon,
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
        /// The generating parameters.
        params: BrdfParams,
        /// Sample count.
        samples: usize,
        /// Noise standard deviation.
        sigma: f64,
        /// Instance seed.
        seed: u64,
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
    /// Lobe kinds, one per lobe.
    pub kinds: Vec<LobeKind>,
    /// Exponent coordinate.
    pub exponent: ExponentCoord,
    /// Fixed parameters by name.
    pub fixed: BTreeMap<String, f64>,
    /// Bounds overrides by name.
    pub bounds: BTreeMap<String, [f64; 2]>,
}

impl ModelSpec {
    /// A model with `lobes` lobes of one kind, default coordinate, nothing fixed.
    pub fn simple(lobes: usize, kind: LobeKind) -> Self {
        ModelSpec {
            kinds: vec![kind; lobes],
            exponent: ExponentCoord::default(),
            fixed: BTreeMap::new(),
            bounds: BTreeMap::new(),
        }
    }

    /// Builds the parameter layout.
    pub fn layout(&self) -> Result<brdf_model::Layout, brdf_model::ModelError> {
        let mut b = brdf_model::Layout::builder(&self.kinds).exponent_coord(self.exponent);
        for (name, &[lo, hi]) in &self.bounds {
            b = b.bounds(name, lo, hi)?;
        }
        for (name, &v) in &self.fixed {
            b = b.fix(name, v)?;
        }
        b.build()
    }
}

/// One instance of an experiment.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct InstanceSpec {
    /// Name (used in trial keys, seeds and file names).
    pub name: String,
    /// Target RMSEs, ascending; trials run to the first.
    pub targets: Vec<f64>,
    /// The data.
    pub source: Source,
    /// The model to fit.
    pub model: ModelSpec,
}

impl InstanceSpec {
    /// The target trials run to (the lowest).
    pub fn run_target(&self) -> f64 {
        self.targets[0]
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

/// Image formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PlotFormat {
    /// PNG bitmap.
    Png,
    /// SVG vector.
    Svg,
}

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

/// A validated experiment.
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

fn line_of(source: &str, offset: usize) -> usize {
    source[..offset.min(source.len())]
        .bytes()
        .filter(|&b| b == b'\n')
        .count()
        + 1
}

/// Per `[[algorithm]]` entry: key name (`"phi"`, `"sweep.rho0"`) -> line.
fn algorithm_key_lines(source: &str) -> Vec<BTreeMap<String, usize>> {
    let mut out = Vec::new();
    let Ok(doc) = toml::de::DeTable::parse(source) else {
        return out;
    };
    let Some(arr) = doc
        .get_ref()
        .get("algorithm")
        .and_then(|v| v.get_ref().as_array())
    else {
        return out;
    };
    for item in arr {
        let mut lines = BTreeMap::new();
        if let Some(t) = item.get_ref().as_table() {
            for (k, v) in t {
                lines.insert(k.get_ref().to_string(), line_of(source, k.span().start));
                if let Some(sub) = v.get_ref().as_table() {
                    for (k2, _) in sub {
                        lines.insert(
                            format!("{}.{}", k.get_ref(), k2.get_ref()),
                            line_of(source, k2.span().start),
                        );
                    }
                }
            }
        }
        out.push(lines);
    }
    out
}

/// A sweep entry: list of values or a range.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRange {
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

fn as_f64(v: &toml::Value) -> Option<f64> {
    match v {
        toml::Value::Integer(i) => Some(*i as f64),
        toml::Value::Float(f) => Some(*f),
        _ => None,
    }
}

/// Expands one sweep value into a list of TOML values.
fn sweep_values(value: &toml::Value) -> Result<Vec<toml::Value>, String> {
    match value {
        toml::Value::Array(a) if !a.is_empty() => Ok(a.clone()),
        toml::Value::Array(_) => Err("an empty list".into()),
        toml::Value::Table(t) => {
            let r: RawRange = toml::Value::Table(t.clone())
                .try_into()
                .map_err(|e: toml::de::Error| e.message().to_string())?;
            let (Some(a), Some(b)) = (as_f64(&r.from), as_f64(&r.to)) else {
                return Err("`from` and `to` must be numbers".into());
            };
            if r.steps < 2 {
                return Err(format!("`steps` must be at least 2, found {}", r.steps));
            }
            if r.scale == Scale::Log && (a <= 0.0 || b <= 0.0) {
                return Err("a log range needs positive `from` and `to`".into());
            }
            let integer = matches!(r.from, toml::Value::Integer(_))
                && matches!(r.to, toml::Value::Integer(_));
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
        other => Err(format!(
            "a list of values or a range table {{ from, to, steps, scale }}, found {}",
            other.type_str()
        )),
    }
}

/// Formats a swept value for a label: integers plainly, reals with up to 4 significant digits.
pub fn format_value(x: f64) -> String {
    if x == x.trunc() && x.abs() < 1e15 {
        format!("{x:.0}")
    } else if x.abs() >= 1e-3 && x.abs() < 1e6 {
        let s = format!(
            "{:.*}",
            (3 - x.abs().log10().floor() as i32).max(0) as usize,
            x
        );
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{x:.3e}")
    }
}

fn value_label(v: &toml::Value) -> String {
    match v {
        toml::Value::Integer(i) => i.to_string(),
        toml::Value::Float(f) => format_value(*f),
        toml::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

impl Spec {
    /// Reads and validates a spec file.
    pub fn from_file(path: &Path) -> Result<Spec, SpecError> {
        let text = std::fs::read_to_string(path).map_err(|source| SpecError::Io {
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
        Spec::parse(&text, &path.display().to_string(), &stem, dir)
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
    /// experiment name, `base_dir` resolves relative paths.
    pub fn parse(text: &str, origin: &str, stem: &str, base_dir: &Path) -> Result<Spec, SpecError> {
        let raw: RawSpec = toml::from_str(text).map_err(|e| SpecError::Toml {
            path: origin.to_string(),
            message: e.to_string().trim_end().to_string(),
        })?;
        let invalid = |line: Option<usize>, message: String| SpecError::Invalid {
            path: origin.to_string(),
            line,
            message,
        };
        let budget_line = Some(line_of(text, raw.budget.span().start));
        let rb = raw.budget.into_inner();
        let budget = Budget {
            cpu_seconds: rb.cpu_seconds,
            sample_evaluations: rb.evaluations.map(|e| e as u64),
        };
        if let Some(c) = rb.cpu_seconds
            && !(c.is_finite() && c > 0.0)
        {
            return Err(invalid(
                budget_line,
                format!("`budget.cpu_seconds` must be a positive number, found {c}"),
            ));
        }
        if let Some(e) = rb.evaluations
            && !(e.is_finite() && e >= 1.0)
        {
            return Err(invalid(
                budget_line,
                format!("`budget.evaluations` must be at least 1, found {e}"),
            ));
        }
        if budget.cpu_seconds.is_none() && budget.sample_evaluations.is_none() {
            return Err(invalid(
                budget_line,
                "`budget` needs `cpu_seconds` or `evaluations` (a target may be unreachable)"
                    .into(),
            ));
        }
        if raw.trials == 0 {
            return Err(invalid(None, "`trials` must be at least 1".into()));
        }
        if raw.threads == Some(0) {
            return Err(invalid(None, "`threads` must be at least 1".into()));
        }
        if raw.instances.is_empty() {
            return Err(invalid(None, "at least one [[instance]] is needed".into()));
        }
        let mut instances: Vec<InstanceSpec> = Vec::new();
        for ri in raw.instances {
            let line = Some(line_of(text, ri.name.span().start));
            let name = ri.name.into_inner();
            let ctx = |m: String| invalid(line, format!("instance `{name}`: {m}"));
            if name.is_empty() || name.contains('/') {
                return Err(ctx("`name` must be non-empty and contain no '/'".into()));
            }
            if instances.iter().any(|i| i.name == name) {
                return Err(ctx("duplicate instance name".into()));
            }
            let tline = Some(line_of(text, ri.targets.span().start));
            let mut targets = ri.targets.into_inner();
            if targets.is_empty() || targets.iter().any(|t| !(t.is_finite() && *t >= 0.0)) {
                return Err(invalid(
                    tline,
                    format!("instance `{name}`: `targets` must be a non-empty list of RMSEs >= 0"),
                ));
            }
            targets.sort_by(f64::total_cmp);
            targets.dedup();
            let source = match (ri.synthetic, ri.file) {
                (Some(s), None) => {
                    let pline = Some(line_of(text, s.params.span().start));
                    let (pname, params) = match s.params.into_inner() {
                        toml::Value::String(n) => match brdf_model::named_params(&n) {
                            Some(p) => (Some(n), p),
                            None => {
                                return Err(invalid(
                                    pline,
                                    format!(
                                        "instance `{name}`: unknown `synthetic.params` name `{n}` (expected one of {})",
                                        brdf_model::NAMED_PARAMS.join(", ")
                                    ),
                                ));
                            }
                        },
                        v @ toml::Value::Table(_) => {
                            let p: BrdfParams = v.try_into().map_err(|e: toml::de::Error| {
                                invalid(
                                    pline,
                                    format!(
                                        "instance `{name}`: `synthetic.params`: {} (expected {{ kd, lobes = [{{ cx, cy, cz, n, pan_deg }}] }})",
                                        e.message()
                                    ),
                                )
                            })?;
                            (None, p)
                        }
                        other => {
                            return Err(invalid(
                                pline,
                                format!(
                                    "instance `{name}`: `synthetic.params` must be a name or a table, found {}",
                                    other.type_str()
                                ),
                            ));
                        }
                    };
                    if s.samples == 0 {
                        return Err(ctx("`synthetic.samples` must be at least 1".into()));
                    }
                    if !(s.sigma.is_finite() && s.sigma >= 0.0) {
                        return Err(ctx("`synthetic.sigma` must be >= 0".into()));
                    }
                    Source::Synthetic {
                        name: pname,
                        params,
                        samples: s.samples,
                        sigma: s.sigma,
                        seed: s.seed,
                    }
                }
                (None, Some(f)) => {
                    let fline = Some(line_of(text, f.span().start));
                    let f = f.into_inner();
                    let resolved = if f.path.is_absolute() {
                        f.path.clone()
                    } else {
                        base_dir.join(&f.path)
                    };
                    if f.format.is_none() && DataFormat::from_path(&f.path).is_none() {
                        return Err(invalid(
                            fline,
                            format!(
                                "instance `{name}`: cannot tell the format of `{}` from its extension; set `file.format` (cornell, csv, merl)",
                                f.path.display()
                            ),
                        ));
                    }
                    Source::File { spec: f, resolved }
                }
                _ => {
                    return Err(ctx(
                        "needs exactly one of [instance.synthetic] or [instance.file]".into(),
                    ));
                }
            };
            let mline = ri.model.as_ref().map(|m| line_of(text, m.span().start));
            let rm = ri.model.map(Spanned::into_inner).unwrap_or_default();
            let default_lobes = match &source {
                Source::Synthetic { params, .. } => params.lobes.len().max(1),
                Source::File { .. } => 1,
            };
            let kinds = match rm.kinds {
                Some(k) if !k.is_empty() => k,
                Some(_) => {
                    return Err(invalid(
                        mline,
                        format!("instance `{name}`: `model.kinds` is empty"),
                    ));
                }
                None => vec![
                    rm.kind.unwrap_or(LobeKind::Anisotropic);
                    rm.lobes.unwrap_or(default_lobes)
                ],
            };
            let fixed_line = rm.fixed.as_ref().map(|f| line_of(text, f.span().start));
            let bounds_line = rm.bounds.as_ref().map(|f| line_of(text, f.span().start));
            let model = ModelSpec {
                kinds,
                exponent: rm.exponent.unwrap_or_default(),
                fixed: rm.fixed.map(Spanned::into_inner).unwrap_or_default(),
                bounds: rm.bounds.map(Spanned::into_inner).unwrap_or_default(),
            };
            model.layout().map_err(|e| {
                // Point at the `fixed` or `bounds` entry that names the parameter.
                let culprit = match &e {
                    brdf_model::ModelError::UnknownParameter { name: n, .. }
                    | brdf_model::ModelError::InvalidBounds { name: n, .. }
                    | brdf_model::ModelError::FixedOutOfBounds { name: n, .. } => Some(n.clone()),
                };
                let l = match culprit {
                    Some(n) if model.fixed.contains_key(&n) => fixed_line,
                    Some(n) if model.bounds.contains_key(&n) => bounds_line,
                    _ => None,
                };
                invalid(
                    l.or(mline).or(line),
                    format!("instance `{name}`: model: {e}"),
                )
            })?;
            instances.push(InstanceSpec {
                name,
                targets,
                source,
                model,
            });
        }
        if raw.algorithms.is_empty() {
            return Err(invalid(None, "at least one [[algorithm]] is needed".into()));
        }
        let key_lines = algorithm_key_lines(text);
        let mut configurations: Vec<Configuration> = Vec::new();
        for (ai, entry) in raw.algorithms.into_iter().enumerate() {
            let entry_line = line_of(text, entry.span().start);
            let lines = key_lines.get(ai).cloned().unwrap_or_default();
            let at = |key: &str| Some(lines.get(key).copied().unwrap_or(entry_line));
            let mut table = entry.into_inner();
            let kind = match table.get("kind") {
                Some(toml::Value::String(k)) => k.clone(),
                Some(other) => {
                    return Err(invalid(
                        at("kind"),
                        format!(
                            "algorithm: `kind` must be a string, found {}",
                            other.type_str()
                        ),
                    ));
                }
                None => {
                    return Err(invalid(
                        Some(entry_line),
                        format!(
                            "algorithm: missing `kind` (one of {})",
                            known_kinds().join(", ")
                        ),
                    ));
                }
            };
            if AlgorithmConfig::default_for(&kind).is_none() {
                return Err(invalid(
                    at("kind"),
                    format!(
                        "algorithm: unknown `kind` `{kind}` (expected one of {})",
                        known_kinds().join(", ")
                    ),
                ));
            }
            let label = match table.remove("label") {
                Some(toml::Value::String(l)) => l,
                Some(other) => {
                    return Err(invalid(
                        at("label"),
                        format!(
                            "algorithm: `label` must be a string, found {}",
                            other.type_str()
                        ),
                    ));
                }
                None => kind.to_uppercase(),
            };
            if label.is_empty() || label.contains('/') {
                return Err(invalid(
                    at("label"),
                    format!("algorithm `{label}`: `label` must be non-empty and contain no '/'"),
                ));
            }
            let sweep = match table.remove("sweep") {
                None => Vec::new(),
                Some(toml::Value::Table(t)) => {
                    let mut sweep = Vec::new();
                    for (k, v) in t {
                        if k == "kind" || k == "label" {
                            return Err(invalid(
                                at(&format!("sweep.{k}")),
                                format!("algorithm `{label}`: cannot sweep `{k}`"),
                            ));
                        }
                        let values = sweep_values(&v).map_err(|m| {
                            invalid(
                                at(&format!("sweep.{k}")),
                                format!("algorithm `{label}`: `sweep.{k}`: expected {m}"),
                            )
                        })?;
                        sweep.push((k, values));
                    }
                    sweep
                }
                Some(other) => {
                    return Err(invalid(
                        at("sweep"),
                        format!(
                            "algorithm `{label}`: `sweep` must be a table, found {}",
                            other.type_str()
                        ),
                    ));
                }
            };
            // The base configuration must be valid by itself (swept keys may be absent).
            let base = algorithm_from_table(&table, &label, &at, origin)?;
            if sweep.is_empty() {
                push_config(
                    &mut configurations,
                    Configuration {
                        label: label.clone(),
                        algorithm_label: label.clone(),
                        swept: Vec::new(),
                        algorithm: base,
                    },
                    origin,
                    entry_line,
                )?;
                continue;
            }
            // Cartesian product, the first swept key varying slowest.
            let mut combos: Vec<Vec<(String, toml::Value)>> = vec![Vec::new()];
            for (k, values) in &sweep {
                let mut next = Vec::new();
                for c in &combos {
                    for v in values {
                        let mut c2 = c.clone();
                        c2.push((k.clone(), v.clone()));
                        next.push(c2);
                    }
                }
                combos = next;
            }
            for combo in combos {
                let mut t = table.clone();
                let mut parts = vec![label.clone()];
                let mut swept = Vec::new();
                for (k, v) in &combo {
                    t.insert(k.clone(), v.clone());
                    parts.push(format!("{k}={}", value_label(v)));
                    swept.push((k.clone(), as_f64(v).unwrap_or(f64::NAN)));
                }
                let sweep_at = |key: &str| {
                    let k = key.to_string();
                    if combo.iter().any(|(ck, _)| *ck == k) {
                        at(&format!("sweep.{k}"))
                    } else {
                        at(key)
                    }
                };
                let algorithm = algorithm_from_table(&t, &label, &sweep_at, origin)?;
                push_config(
                    &mut configurations,
                    Configuration {
                        label: parts.join(" "),
                        algorithm_label: label.clone(),
                        swept,
                        algorithm,
                    },
                    origin,
                    entry_line,
                )?;
            }
        }
        if raw.stats.bootstrap == 0 {
            return Err(invalid(None, "`stats.bootstrap` must be at least 1".into()));
        }
        if let Some([lo, hi]) = raw.plots.error_range
            && !(lo > 0.0 && hi > lo)
        {
            return Err(invalid(
                None,
                "`plots.error_range` must be [lo, hi] with 0 < lo < hi".into(),
            ));
        }
        if raw.plots.error_steps < 2 {
            return Err(invalid(
                None,
                "`plots.error_steps` must be at least 2".into(),
            ));
        }
        let name = raw.name.unwrap_or_else(|| stem.to_string());
        if name.is_empty() || name.contains('/') {
            return Err(invalid(
                None,
                "`name` must be non-empty and contain no '/'".into(),
            ));
        }
        Ok(Spec {
            name,
            description: raw.description,
            seed: raw.seed,
            trials: raw.trials,
            threads: raw.threads,
            budget,
            instances,
            configurations,
            plots: raw.plots,
            stats: raw.stats,
            base_dir: base_dir.to_path_buf(),
            text: text.to_string(),
        })
    }

    /// The canonical form of everything that determines trial results (see the module docs).
    pub fn canonical(&self) -> serde_json::Value {
        let instances: Vec<serde_json::Value> = self
            .instances
            .iter()
            .map(|i| {
                serde_json::json!({
                    "name": i.name,
                    "run_target": i.run_target(),
                    "source": i.source,
                    "model": i.model,
                })
            })
            .collect();
        let configs: Vec<serde_json::Value> = self
            .configurations
            .iter()
            .map(|c| serde_json::json!({"label": c.label, "algorithm": c.algorithm}))
            .collect();
        serde_json::json!({
            "seed": self.seed,
            "budget": self.budget,
            "instances": instances,
            "configurations": configs,
        })
    }

    /// Fingerprint of [`Spec::canonical`] (serde_json with sorted keys, hashed by
    /// [`crate::seed::fingerprint`]).
    pub fn fingerprint(&self) -> String {
        fingerprint(&self.canonical().to_string())
    }

    /// Every trial of the plan, interleaved (trial index outermost) so that partial results
    /// cover every configuration evenly.
    pub fn trials_plan(&self) -> Vec<PlannedTrial> {
        let mut out = Vec::new();
        for trial in 0..self.trials {
            for (ii, inst) in self.instances.iter().enumerate() {
                for (ci, cfg) in self.configurations.iter().enumerate() {
                    out.push(PlannedTrial {
                        instance: ii,
                        config: ci,
                        trial,
                        seed: trial_seed(self.seed, &inst.name, &cfg.label, trial),
                        key: crate::store::TrialRecord::make_key(&inst.name, &cfg.label, trial),
                    });
                }
            }
        }
        out
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

    /// Each instance's targets.
    pub fn targets(&self) -> Vec<(String, Vec<f64>)> {
        self.instances
            .iter()
            .map(|i| (i.name.clone(), i.targets.clone()))
            .collect()
    }

    /// A readable plan: instances, configurations, trial count and the work at the cutoff
    /// upper bound on `threads` threads.
    pub fn describe(&self, threads: usize) -> String {
        let mut s = String::new();
        s.push_str(&format!("experiment `{}`", self.name));
        if let Some(d) = &self.description {
            s.push_str(&format!(": {d}"));
        }
        s.push('\n');
        s.push_str(&format!(
            "master seed {}, {} trials per (instance, configuration), budget per trial: {}\n",
            self.seed,
            self.trials,
            budget_text(&self.budget)
        ));
        s.push_str(&format!("instances ({}):\n", self.instances.len()));
        for i in &self.instances {
            let src = match &i.source {
                Source::Synthetic {
                    name,
                    samples,
                    sigma,
                    seed,
                    ..
                } => format!(
                    "synthetic {} ({samples} samples, sigma {sigma}, seed {seed})",
                    name.as_deref().unwrap_or("custom params")
                ),
                Source::File { spec, resolved } => format!(
                    "file {} ({:?})",
                    resolved.display(),
                    spec.format
                        .or_else(|| DataFormat::from_path(&spec.path))
                        .unwrap_or(DataFormat::Csv)
                ),
            };
            let kinds: Vec<String> = i
                .model
                .kinds
                .iter()
                .map(|k| format!("{k:?}").to_lowercase())
                .collect();
            s.push_str(&format!(
                "  {}: {src}; model [{}], exponent {:?}{}; targets {:?}\n",
                i.name,
                kinds.join(", "),
                i.model.exponent,
                if i.model.fixed.is_empty() {
                    String::new()
                } else {
                    format!(", fixed {:?}", i.model.fixed)
                },
                i.targets
            ));
        }
        s.push_str(&format!(
            "configurations ({}):\n",
            self.configurations.len()
        ));
        for c in &self.configurations {
            let params = serde_json::to_value(&c.algorithm)
                .map(|v| v.to_string())
                .unwrap_or_default();
            s.push_str(&format!("  {:<24} {params}\n", c.label));
        }
        let n = self.trials as u64 * self.instances.len() as u64 * self.configurations.len() as u64;
        s.push_str(&format!(
            "plan: {} instance(s) x {} configuration(s) x {} trials = {n} trials\n",
            self.instances.len(),
            self.configurations.len(),
            self.trials
        ));
        if let Some(c) = self.budget.cpu_seconds {
            let total = n as f64 * c;
            s.push_str(&format!(
                "work at the cutoff upper bound: {} CPU ({} wall on {threads} thread(s)); successful trials stop earlier\n",
                human_seconds(total),
                human_seconds(total / threads.max(1) as f64)
            ));
        }
        if let Some(e) = self.budget.sample_evaluations {
            s.push_str(&format!(
                "evaluation upper bound: {:.3e} sample-evaluations\n",
                n as f64 * e as f64
            ));
        }
        s
    }
}

fn push_config(
    configs: &mut Vec<Configuration>,
    c: Configuration,
    origin: &str,
    line: usize,
) -> Result<(), SpecError> {
    if configs.iter().any(|x| x.label == c.label) {
        return Err(SpecError::Invalid {
            path: origin.to_string(),
            line: Some(line),
            message: format!(
                "duplicate configuration label `{}` (give each [[algorithm]] its own `label`)",
                c.label
            ),
        });
    }
    configs.push(c);
    Ok(())
}

/// Algorithm kinds this build of sls knows (names probed with `AlgorithmConfig::default_for`).
pub fn known_kinds() -> Vec<&'static str> {
    ["aed", "aers", "rpls", "ds", "sa", "sals", "avg", "asa"]
        .into_iter()
        .filter(|k| AlgorithmConfig::default_for(k).is_some())
        .collect()
}

/// Text of a budget, e.g. "10 CPU s".
pub fn budget_text(b: &Budget) -> String {
    let mut parts = Vec::new();
    if let Some(c) = b.cpu_seconds {
        parts.push(format!("{c} CPU s"));
    }
    if let Some(e) = b.sample_evaluations {
        parts.push(format!("{e} sample-evaluations"));
    }
    parts.join(", ")
}

/// Seconds as "1h 02m", "3m 05s" or "12.3 s".
pub fn human_seconds(s: f64) -> String {
    if s >= 3600.0 {
        format!(
            "{}h {:02}m",
            (s / 3600.0) as u64,
            ((s % 3600.0) / 60.0) as u64
        )
    } else if s >= 60.0 {
        format!("{}m {:02}s", (s / 60.0) as u64, (s % 60.0) as u64)
    } else {
        format!("{s:.1} s")
    }
}

/// Deserialises an `AlgorithmConfig` from a table and validates it. serde's internally tagged
/// enums lose toml's positions, so on failure each key is tried alone to find the culprit and
/// report its line.
fn algorithm_from_table(
    table: &toml::Table,
    label: &str,
    at: &dyn Fn(&str) -> Option<usize>,
    origin: &str,
) -> Result<AlgorithmConfig, SpecError> {
    let invalid = |line: Option<usize>, message: String| SpecError::Invalid {
        path: origin.to_string(),
        line,
        message,
    };
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
                    return Err(invalid(at(k), format!("algorithm `{label}`: `{k}`: {m}")));
                }
            }
            return Err(invalid(at("kind"), format!("algorithm `{label}`: {whole}")));
        }
    };
    config.validate().map_err(|e| {
        invalid(
            at(e.field),
            format!("algorithm `{label}`: `{}` {}", e.field, e.message),
        )
    })?;
    Ok(config)
}

#[cfg(test)]
mod tests {
    use super::*;

    const MINI: &str = r#"
name = "mini"
seed = 3
trials = 4

[budget]
cpu_seconds = 0.5

[[instance]]
name = "tuning"
targets = [0.12, 0.11]
[instance.synthetic]
params = "tuning"
samples = 500
sigma = 0.1

[[algorithm]]
label = "AED"
kind = "aed"
phi = 1.4
[algorithm.sweep]
rho0 = [10, 25]

[[algorithm]]
kind = "rpls"
"#;

    fn parse(text: &str) -> Result<Spec, SpecError> {
        Spec::parse(text, "t.toml", "t", Path::new("/base"))
    }

    #[test]
    fn parses_and_expands() {
        let s = parse(MINI).unwrap();
        assert_eq!(s.name, "mini");
        assert_eq!(s.instances[0].targets, vec![0.11, 0.12]);
        assert_eq!(s.instances[0].model.kinds, vec![LobeKind::Anisotropic]);
        let labels = s.config_labels();
        assert_eq!(labels, vec!["AED rho0=10", "AED rho0=25", "RPLS"]);
        match &s.configurations[0].algorithm {
            AlgorithmConfig::Aed(c) => {
                assert_eq!(c.rho0, 10);
                assert_eq!(c.phi, 1.4);
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(s.configurations[1].swept, vec![("rho0".to_string(), 25.0)]);
        assert_eq!(s.trials_plan().len(), 12);
        let plan = s.describe(2);
        assert!(plan.contains("12 trials"), "{plan}");
        assert!(plan.contains("6.0 s CPU"), "{plan}");
    }

    #[test]
    fn documented_example_parses() {
        // The format example in this module's docs is what users copy: keep it valid.
        let src = include_str!("spec.rs");
        let start = src.find("//! ```toml\n").unwrap() + "//! ```toml\n".len();
        let end = start + src[start..].find("//! ```\n").unwrap();
        let example: String = src[start..end]
            .lines()
            .map(|l| {
                l.strip_prefix("//!")
                    .unwrap_or(l)
                    .strip_prefix(' ')
                    .unwrap_or("")
            })
            .collect::<Vec<_>>()
            .join("\n");
        let s = parse(&example).unwrap_or_else(|e| panic!("{e}\n{example}"));
        assert_eq!(s.name, "tuning-aed-sweep");
        assert_eq!(
            s.config_labels(),
            vec!["AED rho0=10", "AED rho0=25", "AED rho0=50"]
        );
        assert_eq!(s.instances[0].model.fixed.get("lobe1.pan"), Some(&45.0));
        assert_eq!(s.budget.sample_evaluations, Some(2_000_000_000));
    }

    #[test]
    fn default_experiment_parses() {
        let s = Spec::default_experiment();
        assert!(s.configurations.len() >= 3);
    }

    #[test]
    fn range_sweeps_linear_log_integer() {
        let text = MINI.replace(
            "rho0 = [10, 25]",
            "phi = { from = 1.0, to = 2.0, steps = 3 }\nrho0 = { from = 10, to = 1000, steps = 3, scale = \"log\" }",
        );
        let s = parse(&text).unwrap();
        let labels = s.config_labels();
        assert_eq!(labels.len(), 10, "{labels:?}");
        assert_eq!(labels[0], "AED phi=1 rho0=10");
        assert_eq!(labels[1], "AED phi=1 rho0=100");
        assert_eq!(labels[4], "AED phi=1.5 rho0=100");
        assert_eq!(labels[8], "AED phi=2 rho0=1000");
        assert_eq!(format_value(1.2), "1.2");
        assert_eq!(format_value(0.0123456), "0.01235");
        assert_eq!(format_value(25.0), "25");
    }

    fn err(text: &str) -> String {
        parse(text).unwrap_err().to_string()
    }

    #[test]
    fn unknown_keys_name_key_and_line() {
        // Top level: toml's own error names the key and the line.
        let e = err(&MINI.replace("trials = 4", "trials = 4\ntrails = 5"));
        assert!(e.contains("trails") && e.contains("line 5"), "{e}");
        // Inside an instance.
        let e = err(&MINI.replace("sigma = 0.1", "sigma = 0.1\nnoise = 2"));
        assert!(e.contains("noise") && e.contains("line 16"), "{e}");
        // Inside an algorithm (deserialised by sls): the key's own line.
        let e = err(&MINI.replace("phi = 1.4", "phi = 1.4\nphy = 2.0"));
        assert!(e.contains("phy") && e.contains("t.toml:21:"), "{e}");
    }

    #[test]
    fn bad_values_name_key_and_line() {
        let e = err(&MINI.replace("phi = 1.4", "phi = \"fast\""));
        assert!(e.contains("`phi`") && e.contains("t.toml:20:"), "{e}");
        let e = err(&MINI.replace("phi = 1.4", "phi = 0.5"));
        assert!(e.contains("`phi`") && e.contains("t.toml:20:"), "{e}");
        let e = err(&MINI.replace("rho0 = [10, 25]", "rho0 = [10, 0]"));
        assert!(e.contains("rho0") && e.contains("t.toml:22:"), "{e}");
        let e = err(&MINI.replace("kind = \"rpls\"", "kind = \"magic\""));
        assert!(e.contains("magic") && e.contains("t.toml:25:"), "{e}");
        let e = err(&MINI.replace("params = \"tuning\"", "params = \"tunning\""));
        assert!(e.contains("tunning") && e.contains("t.toml:13:"), "{e}");
        let e = err(&MINI.replace("cpu_seconds = 0.5", "cpu_seconds = -1"));
        assert!(e.contains("cpu_seconds"), "{e}");
        let e = err(&MINI.replace("samples = 500", "samples = \"many\""));
        assert!(e.contains("samples") && e.contains("line 14"), "{e}");
        let e = err(&MINI.replace(
            "[[algorithm]]\nkind = \"rpls\"",
            "[[algorithm]]\nkind = \"aed\"\nlabel = \"AED rho0=10\"",
        ));
        assert!(e.contains("duplicate configuration label"), "{e}");
        let e = err(&MINI.replace(
            "sigma = 0.1",
            "sigma = 0.1\n[instance.model]\nfixed = { \"lobe1.foo\" = 1.0 }",
        ));
        assert!(e.contains("lobe1.foo") && e.contains("t.toml:17:"), "{e}");
    }

    #[test]
    fn fingerprint_ignores_trials_but_not_seed() {
        let a = parse(MINI).unwrap();
        let b = parse(&MINI.replace("trials = 4", "trials = 9")).unwrap();
        let c = parse(&MINI.replace("seed = 3", "seed = 4")).unwrap();
        // Spelling out a default does not change the fingerprint.
        let d = parse(&MINI.replace("phi = 1.4", "phi = 1.4\ndescent_evaluations = 200")).unwrap();
        assert_eq!(a.fingerprint(), b.fingerprint());
        assert_ne!(a.fingerprint(), c.fingerprint());
        assert_eq!(a.fingerprint(), d.fingerprint());
    }

    #[test]
    fn relative_paths_resolve_against_spec_dir() {
        let text = MINI.replace(
            "[instance.synthetic]\nparams = \"tuning\"\nsamples = 500\nsigma = 0.1",
            "[instance.file]\npath = \"data/x.brdf\"\nmax_value = 1.0",
        );
        let s = parse(&text).unwrap();
        match &s.instances[0].source {
            Source::File { resolved, spec } => {
                assert_eq!(resolved, Path::new("/base/data/x.brdf"));
                assert_eq!(spec.max_value, Some(1.0));
            }
            other => panic!("{other:?}"),
        }
    }
}
