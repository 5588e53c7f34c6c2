//! The open set of algorithms: the [`Algorithm`] trait and the process-wide registry of kinds.
//!
//! An algorithm is a configuration type (serde, with defaults and validation) whose
//! [`Algorithm::run`] searches through a `&mut dyn Search`. Registering the type under its
//! [`Algorithm::KIND`] makes `kind = "..."` in an experiment file (or a JSON record) deserialise
//! into it as an [`crate::AlgorithmConfig`]. The built-in algorithms (`aed`, `aers`, `rpls`,
//! `ds`, `sa`, `sals`, `avg`, `asa`) are registered the same way, before any other.
//!
//! A kind has two parts ([`crate::schema`]): its schema ([`Schema`]: the settings read,
//! checked, defaulted and written) and its runner ([`Algorithm::run`]). [`register`] adds both;
//! [`register_schema`] adds a kind a program only reads (the command line's `kind = "python"`,
//! whose trials run in the Python package), and [`read_unknown_kinds_as_opaque`] lets a program
//! that only reads results keep the settings of kinds it does not know at all.
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

use crate::algorithms::{
    AedConfig, AersConfig, AsaConfig, AvgConfig, DsConfig, RplsConfig, SaConfig, SalsConfig,
};
use crate::schema::{Erased, Opaque, Runner, runner_of};
use crate::value::Value;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, OnceLock, PoisonError, RwLock};

pub use crate::schema::{Algorithm, Schema};

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

/// How the registry makes and reads configurations of one kind, and runs them when the
/// program can.
struct Entry {
    kind: &'static str,
    default: fn() -> Erased,
    from_fields: fn(Value) -> Result<Erased, String>,
    runner: Option<Runner>,
}

impl Entry {
    /// The schema of `T` alone: read, checked and written, never run.
    fn schema<T: Schema>() -> Self {
        Entry {
            kind: <T as Schema>::KIND,
            default: || Erased::read_only(T::default()),
            from_fields: |fields| {
                T::deserialize(fields)
                    .map(Erased::read_only)
                    .map_err(|e| e.to_string())
            },
            runner: None,
        }
    }

    /// The schema and the runner of `T`.
    fn algorithm<T: Algorithm>() -> Self {
        Entry {
            runner: Some(runner_of::<T>()),
            default: || Erased::runnable(T::default()),
            from_fields: |fields| {
                T::deserialize(fields)
                    .map(Erased::runnable)
                    .map_err(|e| e.to_string())
            },
            ..Entry::schema::<T>()
        }
    }
}

/// Registers `T` (its schema and its runner) under [`Algorithm::KIND`] for the rest of the
/// process. Register before parsing the experiment files that use the kind (typically first
/// thing in `main`).
///
/// # Errors
/// [`RegistryError::Duplicate`] when the kind is taken (the built-ins' kinds included),
/// [`RegistryError::InvalidKind`] when it is empty or has characters other than lowercase ASCII
/// letters, digits, `-` and `_`.
pub fn register<T: Algorithm>() -> Result<(), RegistryError> {
    let mut entries = registry().write().unwrap_or_else(PoisonError::into_inner);
    insert(&mut entries, Entry::algorithm::<T>())
}

/// Registers the schema of a kind this program reads but does not run (specs and results that
/// name it are parsed, checked and summarised; running one of its configurations ends the
/// trial with a failure saying so). Errors as [`register`].
pub fn register_schema<T: Schema>() -> Result<(), RegistryError> {
    let mut entries = registry().write().unwrap_or_else(PoisonError::into_inner);
    insert(&mut entries, Entry::schema::<T>())
}

/// From now on, a kind that is not registered is read as opaque settings instead of refused:
/// its fields are kept as written (and written back as read), it validates, and it cannot run.
/// For programs that only read results folders (statistics, plots, reports, comparisons,
/// exports) written by a program that had the kind.
pub fn read_unknown_kinds_as_opaque() {
    OPAQUE.store(true, Ordering::Relaxed);
}

static OPAQUE: AtomicBool = AtomicBool::new(false);

/// The registered kinds, the built-ins first in the paper's order, then in registration order.
pub fn kinds() -> Vec<&'static str> {
    let entries = registry().read().unwrap_or_else(PoisonError::into_inner);
    entries.iter().map(|e| e.kind).collect()
}

/// Whether this program can run configurations of `kind` (it is registered with its runner).
pub fn can_run(kind: &str) -> bool {
    lookup(kind, |e| e.runner.is_some()).unwrap_or(false)
}

/// The default configuration of `kind`, if it is registered (or read as opaque).
pub(crate) fn default_for(kind: &str) -> Option<Erased> {
    match lookup(kind, |e| e.default) {
        Some(make) => Some(make()),
        None => opaque(kind, Vec::new()),
    }
}

/// Reads the configuration of `kind` from the fields beside the tag; the error says what was
/// wrong, or lists the registered kinds when `kind` is not one of them.
pub(crate) fn from_fields(kind: &str, fields: Value) -> Result<Erased, String> {
    match lookup(kind, |e| e.from_fields) {
        Some(read) => read(fields),
        None => {
            let entries = match fields {
                Value::Map(entries) => entries,
                _ => Vec::new(),
            };
            opaque(kind, entries).ok_or_else(|| {
                format!(
                    "unknown algorithm kind `{kind}`, expected one of {}",
                    quoted(&kinds())
                )
            })
        }
    }
}

/// An opaque configuration of `kind` when unknown kinds are read so.
fn opaque(kind: &str, fields: Vec<(Value, Value)>) -> Option<Erased> {
    if !OPAQUE.load(Ordering::Relaxed) || !is_valid_kind(kind) {
        return None;
    }
    Some(Erased {
        config: Box::new(Opaque {
            kind: leaked(kind),
            fields,
        }),
        runner: None,
    })
}

/// `kind` as a `&'static str`, leaked once per distinct kind.
fn leaked(kind: &str) -> &'static str {
    static NAMES: Mutex<Vec<&'static str>> = Mutex::new(Vec::new());
    let mut names = NAMES.lock().unwrap_or_else(PoisonError::into_inner);
    if let Some(n) = names.iter().find(|n| **n == kind) {
        return n;
    }
    let name: &'static str = Box::leak(kind.to_string().into_boxed_str());
    names.push(name);
    name
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
        Entry::algorithm::<AedConfig>(),
        Entry::algorithm::<AersConfig>(),
        Entry::algorithm::<RplsConfig>(),
        Entry::algorithm::<DsConfig>(),
        Entry::algorithm::<SaConfig>(),
        Entry::algorithm::<SalsConfig>(),
        Entry::algorithm::<AvgConfig>(),
        Entry::algorithm::<AsaConfig>(),
    ] {
        insert(&mut entries, entry).expect("the built-in kinds are distinct and valid");
    }
    entries
}

/// A hash of the settings schema of `kind` (its fields, their order and defaults: the default
/// configuration as serialised), if it is registered: 16 hex digits (FNV-1a, 64 bits) that
/// change when a field is added, removed, renamed or given another default. Results record it
/// for custom kinds, so a resumed run can say the kind changed.
pub fn schema_hash(kind: &str) -> Option<String> {
    let default = lookup(kind, |e| e.default)?();
    let fields = default.config.capture().ok()?;
    let text = format!("{kind} {fields:?}");
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for byte in text.bytes() {
        hash ^= u64::from(byte);
        hash = hash.wrapping_mul(0x0100_0000_01b3);
    }
    Some(format!("{hash:016x}"))
}

/// Whether `kind` is one of the built-in algorithms (which the program's version pins).
pub fn is_builtin(kind: &str) -> bool {
    ["aed", "aers", "rpls", "ds", "sa", "sals", "avg", "asa"].contains(&kind)
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
    fn a_schema_hash_follows_the_fields_and_defaults() {
        let aed = schema_hash("aed").unwrap();
        assert_eq!(aed.len(), 16);
        assert_eq!(schema_hash("aed").unwrap(), aed, "stable");
        assert_ne!(schema_hash("aers").unwrap(), aed);
        assert_eq!(schema_hash("no-such-kind"), None);
    }

    #[test]
    fn an_unknown_kind_lists_the_registered_ones() {
        let err = from_fields("nope", Value::Map(Vec::new())).err().unwrap();
        assert!(err.starts_with("unknown algorithm kind `nope`"), "{err}");
        assert!(err.contains("`aed`, `aers`, `rpls`"), "{err}");
    }
}
