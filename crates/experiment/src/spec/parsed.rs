//! Stage 1 of reading a spec: the TOML text as serde structs (unknown keys rejected by
//! serde with toml's line and column), and the source positions later stages cite.

use std::collections::BTreeMap;

use brdf_io::Channel;
use brdf_model::{ExponentCoord, Kernel, LobeKind};
use serde::Deserialize;
use toml::Spanned;

use super::{FileSpec, PlotSpec, SpecError, StatsSpec};

/// Parses spec text into the raw structs; `origin` names the file in errors.
pub(super) fn parse(text: &str, origin: &str) -> Result<ParsedSpec, SpecError> {
    toml::from_str(text).map_err(|e| SpecError::Toml {
        path: origin.to_string(),
        message: e.to_string().trim_end().to_string(),
    })
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ParsedSpec {
    pub(super) name: Option<String>,
    pub(super) description: Option<String>,
    pub(super) seed: u64,
    pub(super) trials: Spanned<u32>,
    pub(super) threads: Option<Spanned<usize>>,
    #[serde(default)]
    pub(super) kernel: Kernel,
    pub(super) budget: Spanned<ParsedBudget>,
    #[serde(rename = "instance", default)]
    pub(super) instances: Vec<ParsedInstance>,
    /// `[[suite]]` tables, each expanded into instances (see `super::suite`).
    #[serde(rename = "suite", default)]
    pub(super) suites: Vec<Spanned<ParsedSuite>>,
    #[serde(rename = "algorithm")]
    pub(super) algorithms: Vec<Spanned<toml::Table>>,
    #[serde(default)]
    pub(super) plots: PlotSpec,
    #[serde(default)]
    pub(super) stats: StatsSpec,
    /// Optional `[tune]` table (automatic tuning with irace; see `super::tune`).
    #[serde(default)]
    pub(super) tune: Option<Spanned<super::tune::ParsedTune>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ParsedBudget {
    pub(super) cpu_seconds: Option<f64>,
    pub(super) evaluations: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ParsedInstance {
    pub(super) name: Spanned<String>,
    /// Numbers (absolute RMSEs) or `{ relative = r }` tables (see `validate::targets`).
    pub(super) targets: Spanned<Vec<toml::Value>>,
    pub(super) synthetic: Option<ParsedSynthetic>,
    pub(super) file: Option<Spanned<FileSpec>>,
    /// A material of a named suite (see `super::suite`).
    #[serde(default)]
    pub(super) suite: Option<Spanned<ParsedSuiteRef>>,
    #[serde(default)]
    pub(super) model: Option<Spanned<ParsedModel>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ParsedSynthetic {
    pub(super) params: Spanned<toml::Value>,
    #[serde(default = "default_samples")]
    pub(super) samples: usize,
    #[serde(default)]
    pub(super) sigma: f64,
    #[serde(default = "default_instance_seed")]
    pub(super) seed: u64,
}

fn default_samples() -> usize {
    10_000
}
fn default_instance_seed() -> u64 {
    1
}

#[derive(Clone, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct ParsedModel {
    pub(super) family: Option<Spanned<String>>,
    pub(super) lobes: Option<usize>,
    pub(super) kind: Option<LobeKind>,
    pub(super) kinds: Option<Vec<LobeKind>>,
    pub(super) exponent: Option<ExponentCoord>,
    pub(super) starts: Option<sls::StartDist>,
    pub(super) fixed: Option<Spanned<BTreeMap<String, f64>>>,
    pub(super) bounds: Option<Spanned<BTreeMap<String, Vec<f64>>>>,
}

/// The draw of a suite instance as written: `[instance.suite]`, whose keys `[[suite]]` shares
/// (see `super::suite`).
#[derive(Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ParsedSuiteRef {
    pub(super) suite: Spanned<String>,
    pub(super) material: Spanned<String>,
    #[serde(default)]
    pub(super) channel: Option<Channel>,
    #[serde(default)]
    pub(super) sampling: Option<Spanned<String>>,
    #[serde(default)]
    pub(super) samples: Option<Spanned<usize>>,
    #[serde(default)]
    pub(super) noise: Option<Spanned<f64>>,
    #[serde(default)]
    pub(super) sigma: Option<Spanned<f64>>,
    #[serde(default)]
    pub(super) seed: Option<u64>,
}

/// A top-level `[[suite]]` table as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ParsedSuite {
    pub(super) suite: Spanned<String>,
    #[serde(default)]
    pub(super) materials: Option<Spanned<toml::Value>>,
    #[serde(default)]
    pub(super) prefix: Option<String>,
    pub(super) targets: Spanned<Vec<toml::Value>>,
    #[serde(default)]
    pub(super) channel: Option<Channel>,
    #[serde(default)]
    pub(super) sampling: Option<Spanned<String>>,
    #[serde(default)]
    pub(super) samples: Option<Spanned<usize>>,
    #[serde(default)]
    pub(super) noise: Option<Spanned<f64>>,
    #[serde(default)]
    pub(super) sigma: Option<Spanned<f64>>,
    #[serde(default)]
    pub(super) seed: Option<u64>,
    #[serde(default)]
    pub(super) model: Option<Spanned<ParsedModel>>,
}

pub(super) fn line_of(source: &str, offset: usize) -> usize {
    source[..offset.min(source.len())]
        .bytes()
        .filter(|&b| b == b'\n')
        .count()
        + 1
}

/// Per `[[algorithm]]` entry: key name (`"phi"`, `"sweep.rho0"`) -> line.
pub(super) fn algorithm_key_lines(source: &str) -> Vec<BTreeMap<String, usize>> {
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
