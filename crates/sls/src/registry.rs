//! The open set of algorithms: the [`Algorithm`] trait and the process-wide registry of kinds.
//!
//! An algorithm is a configuration type (serde, with defaults and validation) whose
//! [`Algorithm::run`] searches through a `&mut dyn Search`. Registering the type under its
//! [`Algorithm::KIND`] makes `kind = "..."` in an experiment file (or a JSON record) deserialise
//! into it as an [`AlgorithmConfig`]. The built-in algorithms (`aed`, `aers`, `rpls`, `ds`,
//! `sa`, `sals`, `avg`, `asa`) are registered the same way, before any other.
//!
//! ```
//! use serde::{Deserialize, Serialize};
//! use sls::registry::{self, Algorithm};
//! use sls::{AlgorithmConfig, ConfigError, Search, Stop};
//!
//! /// Evaluates random picks until the budget or the target stops it.
//! #[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
//! #[serde(default, deny_unknown_fields)]
//! struct PureRandom {}
//!
//! impl Algorithm for PureRandom {
//!     const KIND: &'static str = "pure-random";
//!     fn validate(&self) -> Result<(), ConfigError> {
//!         Ok(())
//!     }
//!     fn run(&self, search: &mut dyn Search) -> Result<(), Stop> {
//!         let mut x = vec![0.0; search.dim()];
//!         loop {
//!             search.random_pick(&mut x);
//!             search.evaluate(&x)?;
//!         }
//!     }
//! }
//!
//! registry::register::<PureRandom>().unwrap();
//! let config: AlgorithmConfig = serde_json::from_str(r#"{"kind": "pure-random"}"#).unwrap();
//! assert_eq!(config.kind_name(), "pure-random");
//! assert!(registry::kinds().contains(&"pure-random"));
//! // A second registration of the same kind is refused.
//! assert!(registry::register::<PureRandom>().is_err());
//! ```

mod value;

use crate::algorithms::{
    AedConfig, AersConfig, AsaConfig, AvgConfig, DsConfig, RplsConfig, SaConfig, SalsConfig,
};
use crate::config::AlgorithmConfig;
use crate::search::{Search, Stop};
use crate::validate::ConfigError;
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::fmt::Debug;
use std::sync::{OnceLock, PoisonError, RwLock};

pub(crate) use value::{Value, capture};

/// A search algorithm: its configuration type, which the registry deserialises from
/// `{"kind": KIND, ...}` and runs.
///
/// The configuration's serde representation must be a struct or a map (its fields sit beside
/// `kind`); use `#[serde(default, deny_unknown_fields)]` so missing fields take the defaults and
/// misspelt ones are rejected. `Default` is the configuration `kind = "..."` alone selects.
pub trait Algorithm:
    Serialize + DeserializeOwned + Default + Clone + Debug + PartialEq + Send + Sync + 'static
{
    /// The `kind` tag that selects this algorithm: lowercase ASCII letters, digits, `-`, `_`.
    const KIND: &'static str;

    /// Checks every parameter; the error names the offending field (use
    /// [`ConfigError::new`] with [`Algorithm::KIND`]).
    fn validate(&self) -> Result<(), ConfigError>;

    /// Searches until a [`Search`] method returns a [`Stop`] (target reached, budget spent,
    /// interrupted), which it propagates with `?`; `Ok(())` means the algorithm ended by itself.
    /// Every sample-evaluation goes through `search`, which counts it, checks the budget and
    /// records the best candidate and the anytime trace.
    fn run(&self, search: &mut dyn Search) -> Result<(), Stop>;
}

/// Why a registration was refused.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum RegistryError {
    /// Another configuration type is already registered under this kind.
    #[error("algorithm kind `{kind}` is already registered (registered kinds: {registered})")]
    Duplicate {
        /// The kind.
        kind: &'static str,
        /// All registered kinds, comma-separated.
        registered: String,
    },
    /// The kind is not a usable tag.
    #[error(
        "algorithm kind `{kind}` is not valid: expected lowercase ASCII letters, digits, `-` or \
         `_`, starting with a letter"
    )]
    InvalidKind {
        /// The kind.
        kind: &'static str,
    },
}

/// How the registry makes and reads configurations of one kind.
struct Entry {
    kind: &'static str,
    default: fn() -> AlgorithmConfig,
    from_fields: fn(Value) -> Result<AlgorithmConfig, String>,
}

impl Entry {
    fn of<T: Algorithm>() -> Self {
        Entry {
            kind: T::KIND,
            default: || AlgorithmConfig::new(T::default()),
            from_fields: |fields| {
                T::deserialize(fields)
                    .map(AlgorithmConfig::new)
                    .map_err(|e| e.to_string())
            },
        }
    }
}

/// Registers `T` under [`Algorithm::KIND`] for the rest of the process. Register before parsing
/// the experiment files that use the kind (typically first thing in `main`).
///
/// # Errors
/// [`RegistryError::Duplicate`] when the kind is taken (the built-ins' kinds included),
/// [`RegistryError::InvalidKind`] when it is empty or has characters other than lowercase ASCII
/// letters, digits, `-` and `_`.
pub fn register<T: Algorithm>() -> Result<(), RegistryError> {
    let mut entries = registry().write().unwrap_or_else(PoisonError::into_inner);
    insert(&mut entries, Entry::of::<T>())
}

/// The registered kinds, the built-ins first in the paper's order, then in registration order.
pub fn kinds() -> Vec<&'static str> {
    let entries = registry().read().unwrap_or_else(PoisonError::into_inner);
    entries.iter().map(|e| e.kind).collect()
}

/// The default configuration of `kind`, if it is registered.
pub(crate) fn default_for(kind: &str) -> Option<AlgorithmConfig> {
    let make = lookup(kind, |e| e.default)?;
    Some(make())
}

/// Reads the configuration of `kind` from the fields beside the tag; the error says what was
/// wrong, or lists the registered kinds when `kind` is not one of them.
pub(crate) fn from_fields(kind: &str, fields: Value) -> Result<AlgorithmConfig, String> {
    match lookup(kind, |e| e.from_fields) {
        Some(read) => read(fields),
        None => Err(format!(
            "unknown algorithm kind `{kind}`, expected one of {}",
            quoted(&kinds())
        )),
    }
}

fn lookup<R>(kind: &str, get: impl Fn(&Entry) -> R) -> Option<R> {
    let entries = registry().read().unwrap_or_else(PoisonError::into_inner);
    entries.iter().find(|e| e.kind == kind).map(get)
}

fn registry() -> &'static RwLock<Vec<Entry>> {
    static REGISTRY: OnceLock<RwLock<Vec<Entry>>> = OnceLock::new();
    REGISTRY.get_or_init(|| RwLock::new(builtins()))
}

/// The built-in algorithms, registered through [`insert`] like any other.
fn builtins() -> Vec<Entry> {
    let mut entries = Vec::new();
    for entry in [
        Entry::of::<AedConfig>(),
        Entry::of::<AersConfig>(),
        Entry::of::<RplsConfig>(),
        Entry::of::<DsConfig>(),
        Entry::of::<SaConfig>(),
        Entry::of::<SalsConfig>(),
        Entry::of::<AvgConfig>(),
        Entry::of::<AsaConfig>(),
    ] {
        insert(&mut entries, entry).expect("the built-in kinds are distinct and valid");
    }
    entries
}

fn insert(entries: &mut Vec<Entry>, entry: Entry) -> Result<(), RegistryError> {
    if !is_valid_kind(entry.kind) {
        return Err(RegistryError::InvalidKind { kind: entry.kind });
    }
    if entries.iter().any(|e| e.kind == entry.kind) {
        let registered: Vec<_> = entries.iter().map(|e| e.kind).collect();
        return Err(RegistryError::Duplicate {
            kind: entry.kind,
            registered: registered.join(", "),
        });
    }
    entries.push(entry);
    Ok(())
}

fn is_valid_kind(kind: &str) -> bool {
    kind.starts_with(|c: char| c.is_ascii_lowercase())
        && kind
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-' || c == '_')
}

fn quoted(kinds: &[&str]) -> String {
    let quoted: Vec<String> = kinds.iter().map(|k| format!("`{k}`")).collect();
    quoted.join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_are_checked() {
        assert!(is_valid_kind("random-restart_2"));
        for bad in ["", "Aed", "2opt", "a b", "-x"] {
            assert!(!is_valid_kind(bad), "{bad}");
        }
    }

    #[test]
    fn builtins_come_first_in_the_papers_order() {
        assert_eq!(
            kinds()[..8],
            ["aed", "aers", "rpls", "ds", "sa", "sals", "avg", "asa"]
        );
    }

    #[test]
    fn an_unknown_kind_lists_the_registered_ones() {
        let err = from_fields("nope", Value::Map(Vec::new())).unwrap_err();
        assert!(err.starts_with("unknown algorithm kind `nope`"), "{err}");
        assert!(err.contains("`aed`, `aers`, `rpls`"), "{err}");
    }
}
