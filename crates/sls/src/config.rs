//! Algorithm selection: [`AlgorithmConfig`], deserialised from the harness's TOML/JSON with
//! `kind = "aed"` etc. (validation errors are [`ConfigError`], defined in `validate.rs`; the
//! kinds are those of [`crate::registry`]).

use crate::registry;
use crate::schema::{Algorithm, Erased, Schema};
use crate::search::{Search, Stop};
use crate::validate::ConfigError;
use crate::value::Value;
use serde::de::Error as _;
use serde::ser::{Error as _, SerializeMap, SerializeStruct};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// Which algorithm a trial runs, with its parameters: any registered [`Algorithm`]'s
/// configuration. Serialised with a `kind` tag beside the configuration's fields:
/// `{"kind": "aed", "phi": 1.4}`; missing fields take the algorithm's defaults, unknown fields
/// and unregistered kinds are rejected.
///
/// ```
/// use sls::{AedConfig, AlgorithmConfig};
///
/// let config = AlgorithmConfig::new(AedConfig { phi: 1.2, ..AedConfig::default() });
/// assert_eq!(config.kind_name(), "aed");
/// let text = serde_json::to_string(&config).unwrap();
/// assert!(text.starts_with(r#"{"kind":"aed","phi":1.2,"#));
/// let back: AlgorithmConfig = serde_json::from_str(&text).unwrap();
/// assert_eq!(back.downcast_ref::<AedConfig>().unwrap().phi, 1.2);
/// ```
pub struct AlgorithmConfig {
    inner: Erased,
}

impl AlgorithmConfig {
    /// Wraps an algorithm's configuration (registered or not: only deserialisation needs the
    /// kind registered).
    pub fn new<T: Algorithm>(config: T) -> Self {
        Self {
            inner: Erased::runnable(config),
        }
    }

    /// Wraps the configuration of a kind this program reads but cannot run
    /// ([`AlgorithmConfig::run`] then ends the trial with a failure).
    pub fn read_only<T: Schema>(config: T) -> Self {
        Self {
            inner: Erased::read_only(config),
        }
    }

    /// Whether this program can run the configuration (its kind has a runner here).
    pub fn can_run(&self) -> bool {
        self.inner.runner.is_some()
    }

    /// Checks every parameter; the error names the offending field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.inner.config.validate()
    }

    /// The `kind` tag: `"aed"`, `"aers"`, `"rpls"`, `"ds"`, `"sa"`, `"sals"`, `"avg"`, `"asa"`,
    /// or a registered algorithm's [`Algorithm::KIND`].
    pub fn kind_name(&self) -> &'static str {
        self.inner.config.kind()
    }

    /// The default configuration of the registered algorithm named `kind`, if there is one.
    pub fn default_for(kind: &str) -> Option<Self> {
        registry::default_for(kind).map(|inner| Self { inner })
    }

    /// Runs the algorithm until it stops (`Err`) or finishes by itself (`Ok`). A configuration
    /// of a kind this program cannot run ends the trial at once with a failure saying so
    /// ([`Stop::Failed`]).
    pub fn run(&self, search: &mut dyn Search) -> Result<(), Stop> {
        match self.inner.runner {
            Some(run) => run(self.inner.config.as_any(), search),
            None => Err(search.fail(format!(
                "algorithm kind `{}` cannot run in this program: it only reads its settings",
                self.kind_name()
            ))),
        }
    }

    /// The configuration, if it is a `T`.
    pub fn downcast_ref<T: Schema>(&self) -> Option<&T> {
        self.inner.config.as_any().downcast_ref()
    }

    /// The configuration, mutably, if it is a `T`.
    pub fn downcast_mut<T: Schema>(&mut self) -> Option<&mut T> {
        self.inner.config.as_any_mut().downcast_mut()
    }
}

impl<T: Algorithm> From<T> for AlgorithmConfig {
    fn from(config: T) -> Self {
        Self::new(config)
    }
}

impl Clone for AlgorithmConfig {
    fn clone(&self) -> Self {
        Self {
            inner: self.inner.clone(),
        }
    }
}

impl PartialEq for AlgorithmConfig {
    fn eq(&self, other: &Self) -> bool {
        self.inner.config.dyn_eq(other.inner.config.as_any())
    }
}

/// The configuration's own `Debug` (its type name and fields).
impl fmt::Debug for AlgorithmConfig {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.inner.config.fmt(f)
    }
}

/// Writes what serde writes for an internally tagged enum variant: the struct (or map) of the
/// configuration with `kind` as its first field.
impl Serialize for AlgorithmConfig {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let kind = self.kind_name();
        match self.inner.config.capture().map_err(S::Error::custom)? {
            Value::Struct(name, fields) => {
                let mut s = serializer.serialize_struct(name, fields.len() + 1)?;
                s.serialize_field("kind", kind)?;
                for (key, value) in &fields {
                    s.serialize_field(key, value)?;
                }
                s.end()
            }
            Value::Map(entries) => {
                let mut m = serializer.serialize_map(Some(entries.len() + 1))?;
                m.serialize_entry("kind", kind)?;
                for (key, value) in &entries {
                    m.serialize_entry(key, value)?;
                }
                m.end()
            }
            _ => Err(S::Error::custom(format!(
                "algorithm `{kind}`: its configuration must serialise as a struct or a map"
            ))),
        }
    }
}

/// Reads `kind` and hands the other fields to the registered configuration type.
impl<'de> Deserialize<'de> for AlgorithmConfig {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let Value::Map(mut entries) = Value::deserialize(deserializer)? else {
            return Err(D::Error::custom(
                "an algorithm configuration must be a table with a `kind`",
            ));
        };
        let at = entries
            .iter()
            .position(|(k, _)| matches!(k, Value::Str(s) if s == "kind"))
            .ok_or_else(|| D::Error::missing_field("kind"))?;
        let kind = match entries.remove(at).1 {
            Value::Str(kind) => kind,
            other => {
                let found = other.type_name();
                return Err(D::Error::custom(format!(
                    "`kind` must be a string, found {found}"
                )));
            }
        };
        registry::from_fields(&kind, Value::Map(entries))
            .map(|inner| AlgorithmConfig { inner })
            .map_err(D::Error::custom)
    }
}
