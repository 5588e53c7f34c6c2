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
//! kernel = "auto"                # evaluation kernel: auto | avx512 | avx2 | portable | scalar
//!
//! [budget]                       # at least one limit
//! cpu_seconds = 10.0             # CPU-time cutoff per trial (worker thread clock)
//! evaluations = 2e9              # optional sample-evaluation cutoff per trial
//!
//! [[instance]]                   # one or more
//! name = "tuning"
//! targets = [0.11, 0.115, 0.12]  # trials run to the lowest; the others come from the traces
//! #                              # an entry { relative = 0.01 } is 1% above the best-known RMSE
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
//! # drop_negative = false        # default false (noisy data has negative values)
//! # drop_below_horizon = true    # default true
//! [instance.model]               # the model shape to fit (all optional)
//! lobes = 1                      # default: the synthetic params' lobe count, else 1
//! kind = "anisotropic"           # or "isotropic" (Cxy, Cz, n; no pan)
//! # kinds = ["anisotropic", "isotropic"]   # per lobe, overrides lobes/kind
//! exponent = "log1p"             # optimiser coordinate of n: "log1p" (default) or "raw"
//! starts = "coordinate"          # exponent in random starts: "coordinate" (default: uniform in
//!                                # the coordinate above), "uniform" (in n), "log-uniform"
//! fixed = { "lobe1.pan" = 45.0 } # parameters held fixed
//! bounds = { "lobe1.n" = [0.0, 200.0] }   # bounds overriding Table 1
//!
//! [[algorithm]]                  # one or more
//! label = "AED"                  # default: the kind in capitals
//! kind = "aed"                   # aed | aers | rpls | ds | sa | sals | avg | asa (sls::AlgorithmConfig)
//! phi = 1.4                      # any parameter of that algorithm; missing = paper default
//! descent = "default"            # the descents' solver: default | gauss-newton | n2fb (the
//!                                # paper's PORT N2FB configuration); not sweepable
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

mod describe;
mod labels;
pub mod limits;
mod plan;
mod raw;
mod sweep;
mod validate;

pub use describe::{budget_text, human_seconds};
pub use sweep::format_value;

/// The built-in default experiment (experiments/default.toml).
pub const DEFAULT_SPEC: &str = include_str!("../../../../experiments/default.toml");

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

/// Data file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
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
    /// Start distribution of the exponents (`Coordinate`: uniform in the coordinate). Left out
    /// of the canonical form when it is the default, so older fingerprints stay valid.
    #[serde(skip_serializing_if = "is_native_starts")]
    pub starts: sls::StartDist,
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
            starts: sls::StartDist::Coordinate,
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
    /// ([`crate::best_known`]).
    pub best_known: Option<crate::best_known::BestKnown>,
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
    pub fn resolve_targets(&mut self, known: crate::best_known::BestKnown) {
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
    pub tune: Option<crate::tune::TuneSpec>,
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
    /// Reads and validates a spec file.
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
    /// experiment name, `base_dir` resolves relative paths. The stages: `raw` (TOML into
    /// serde structs), `validate` (values, sizes, instances and models), `sweep`
    /// (configurations), then the plan's size.
    pub fn parse(text: &str, origin: &str, stem: &str, base_dir: &Path) -> Result<Spec, SpecError> {
        let raw = raw::parse(text, origin)?;
        let cx = validate::Ctx { text, origin };
        let budget = validate::budget(&cx, raw.budget)?;
        validate::counts(&cx, raw.trials, raw.threads)?;
        let instances = validate::instances(&cx, raw.instances, base_dir)?;
        let configurations = sweep::configurations(&cx, raw.algorithms)?;
        validate::options(&cx, &raw.plots, &raw.stats)?;
        validate::plan_size(&cx, raw.trials, instances.len(), configurations.len())?;
        if raw.tune.is_some()
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
        let tune = match raw.tune {
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
            name: validate::name(&cx, raw.name, stem)?,
            description: raw.description,
            seed: raw.seed,
            trials: raw.trials,
            threads: raw.threads,
            kernel: raw.kernel,
            budget,
            instances,
            configurations,
            plots: raw.plots,
            stats: raw.stats,
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
    pub fn best_known(&self) -> BTreeMap<String, crate::best_known::BestKnown> {
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

/// Algorithm kinds this build of sls knows (names probed with `AlgorithmConfig::default_for`).
pub fn known_kinds() -> Vec<&'static str> {
    ["aed", "aers", "rpls", "ds", "sa", "sals", "avg", "asa"]
        .into_iter()
        .filter(|k| AlgorithmConfig::default_for(k).is_some())
        .collect()
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
        let src = include_str!("mod.rs");
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
    fn relative_targets_parse_and_bad_ones_name_the_key() {
        let s = parse(&MINI.replace(
            "targets = [0.12, 0.11]",
            "targets = [{ relative = 0.05 }, 0.12, { relative = 0.01 }]",
        ))
        .unwrap();
        let i = &s.instances[0];
        assert_eq!(i.relative_targets, vec![0.01, 0.05]);
        assert_eq!(i.absolute_targets, vec![0.12]);
        assert!(s.has_unresolved_targets());
        // The fingerprint holds the relative value as written.
        assert_ne!(s.fingerprint(), parse(MINI).unwrap().fingerprint());
        for (entry, needle) in [
            (
                "{ relative = -0.01 }",
                "`targets[0].relative` must be a finite fraction",
            ),
            (
                "{ relative = 0.01, absolute = 0.1 }",
                "`targets[0]`: `relative` and `absolute`",
            ),
            (
                "{ relative = \"1%\" }",
                "`targets[0].relative` must be a number",
            ),
            ("{ relatve = 0.01 }", "`targets[0]`: unknown key `relatve`"),
            ("{}", "`targets[0]`: empty table"),
            ("\"0.1\"", "`targets[0]` must be a number or a table"),
            (
                "{ absolute = -1 }",
                "`targets[0].absolute` must be a finite RMSE",
            ),
        ] {
            let e = err(&MINI.replace("targets = [0.12, 0.11]", &format!("targets = [{entry}]")));
            assert!(
                e.contains(needle) && e.contains("t.toml:11:"),
                "{entry}: {e}"
            );
        }
        let tuned = format!(
            "{}\n[tune]\ntrain = [\"tuning\"]\ntest = [\"tuning\"]\nbudget = 100\ncost = \"evaluations\"\n[[tune.parameter]]\nname = \"phi\"\ntype = \"real\"\nrange = [1.0, 2.0]\n",
            MINI.replace("targets = [0.12, 0.11]", "targets = [{ relative = 0.01 }]")
        );
        assert!(err(&tuned).contains("relative targets are not supported with [tune]"));
    }

    #[test]
    fn starts_are_validated_and_the_default_keeps_the_fingerprint() {
        let with = |model: &str| {
            parse(&MINI.replace(
                "sigma = 0.1",
                &format!("sigma = 0.1\n[instance.model]\n{model}"),
            ))
        };
        let base = with("exponent = \"log1p\"").unwrap();
        let same = with("exponent = \"log1p\"\nstarts = \"log-uniform\"").unwrap();
        let uniform = with("exponent = \"log1p\"\nstarts = \"uniform\"").unwrap();
        assert_eq!(base.fingerprint(), same.fingerprint());
        assert_eq!(base.fingerprint(), parse(MINI).unwrap().fingerprint());
        assert_ne!(base.fingerprint(), uniform.fingerprint());
        assert_eq!(uniform.instances[0].model.starts, sls::StartDist::Uniform);
        let raw = with("exponent = \"raw\"\nstarts = \"uniform\"").unwrap();
        assert_eq!(raw.instances[0].model.starts, sls::StartDist::Coordinate);
        let e = with("starts = \"gaussian\"").unwrap_err().to_string();
        assert!(e.contains("gaussian") && e.contains("starts"), "{e}");
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
    fn descent_is_read_per_entry_and_fingerprinted_only_when_not_default() {
        let plain = parse(MINI).unwrap();
        assert!(
            plain
                .configurations
                .iter()
                .all(|c| c.descent == sls::DescentModel::Default)
        );
        let spelled =
            parse(&MINI.replace("phi = 1.4", "phi = 1.4\ndescent = \"default\"")).unwrap();
        assert_eq!(plain.fingerprint(), spelled.fingerprint());
        let n2fb = parse(&MINI.replace("phi = 1.4", "phi = 1.4\ndescent = \"n2fb\"")).unwrap();
        assert_ne!(plain.fingerprint(), n2fb.fingerprint());
        // Every swept configuration of the entry gets it; the other entry keeps the default.
        let descents: Vec<_> = n2fb.configurations.iter().map(|c| c.descent).collect();
        use sls::DescentModel::{Default, N2fb};
        assert_eq!(descents, [N2fb, N2fb, Default]);
        assert!(
            n2fb.describe(1).contains("descent=n2fb"),
            "{}",
            n2fb.describe(1)
        );
    }

    #[test]
    fn bad_descent_names_line_and_choices() {
        let e = err(&MINI.replace("phi = 1.4", "phi = 1.4\ndescent = \"port\""));
        assert!(
            e.contains("t.toml:21:") && e.contains("`port`") && e.contains("`n2fb`"),
            "{e}"
        );
        let e = err(&MINI.replace("phi = 1.4", "phi = 1.4\ndescent = 2"));
        assert!(
            e.contains("t.toml:21:") && e.contains("must be a string"),
            "{e}"
        );
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

    #[test]
    fn sizes_and_values_are_checked_before_any_work() {
        let with_synthetic =
            |extra: &str| MINI.replace("sigma = 0.1", &format!("sigma = 0.1\n{extra}"));
        for (text, needle) in [
            (MINI.replace("samples = 500", "samples = 9223372036854775807"), "samples"),
            (with_synthetic("[instance.model]\nlobes = 9223372036854775807"), "model.lobes"),
            (MINI.replace("rho0 = [10, 25]", "rho0 = { from = 1, to = 9, steps = 4000000000 }"), "steps"),
            (format!("{MINI}\n[stats]\nbootstrap = 1000000000\n"), "bootstrap"),
            (MINI.replace("sigma = 0.1", "sigma = 1e300"), "sigma"),
            (MINI.replace("sigma = 0.1", "sigma = nan"), "sigma"),
            (MINI.replace("params = \"tuning\"", "params = { kd = nan, lobes = [] }"), "kd"),
            (
                MINI.replace(
                    "params = \"tuning\"",
                    "params = { kd = 0.1, lobes = [{ cx = inf, cy = 0.8, cz = 0.96, n = 20, pan_deg = 45 }] }",
                ),
                "cx",
            ),
            (
                MINI.replace(
                    "params = \"tuning\"",
                    "params = { kd = 0.1, lobes = [{ cx = 1, cy = 0.8, cz = 5, n = 20, pan_deg = 45 }] }",
                ),
                "cz",
            ),
            (with_synthetic("[instance.model]\nbounds = { \"lobe1.n\" = [0.0, 1.0, 2.0] }"), "bounds"),
            (MINI.replace("rho0 = [10, 25]", "rho0 = [10, \"many\"]"), "rho0"),
            (MINI.replace("trials = 4", "trials = 4000000000"), "plan"),
            (MINI.replace("targets = [0.12, 0.11]", "targets = [nan]"), "targets"),
            (MINI.replace("cpu_seconds = 0.5", "cpu_seconds = inf"), "cpu_seconds"),
        ] {
            let started = std::time::Instant::now();
            let e = match parse(&text) {
                Ok(_) => panic!("`{needle}` case accepted:\n{text}"),
                Err(e) => e.to_string(),
            };
            assert!(e.contains(needle), "expected an error naming `{needle}`, got: {e}");
            assert!(started.elapsed().as_secs_f64() < 1.0, "{needle}: too slow");
        }
    }
}
