//! What a kind of algorithm is made of, in two parts a program may have apart: its **schema**
//! ([`Schema`]: the configuration type, which parses, validates, defaults and serialises the
//! settings) and its **runner** ([`Algorithm::run`], the search loop). A program that only reads
//! specs and results needs the schema; one that runs trials needs both. The registry
//! ([`crate::registry`]) holds kinds with or without a runner, and [`crate::AlgorithmConfig`]
//! holds one configuration with its type erased.

use std::any::Any;
use std::fmt::Debug;

use serde::Serialize;
use serde::de::DeserializeOwned;

use crate::search::{Search, Stop};
use crate::validate::ConfigError;
use crate::value::{Value, capture};

/// The settings of a kind of algorithm: the configuration type the registry deserialises from
/// `{"kind": KIND, ...}`, validates, fills with defaults and serialises back, without running
/// anything. Register a schema alone with [`crate::registry::register_schema`] where the kind
/// is only read (specs and results that name it); every [`Algorithm`] is also a schema.
///
/// The serde representation must be a struct or a map (its fields sit beside `kind`); use
/// `#[serde(default, deny_unknown_fields)]` so missing fields take the defaults and misspelt
/// ones are rejected. `Default` is the configuration `kind = "..."` alone selects.
pub trait Schema:
    Serialize + DeserializeOwned + Default + Clone + Debug + PartialEq + Send + Sync + 'static
{
    /// The `kind` tag: lowercase ASCII letters, digits, `-`, `_`.
    const KIND: &'static str;

    /// Checks every setting; the error names the offending field.
    fn validate(&self) -> Result<(), ConfigError>;
}

/// A search algorithm: its configuration type (so also its [`Schema`]) and its search loop.
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
    /// records the best candidate and the anytime trace. An algorithm that cannot go on (bad
    /// input of its own, a failed library call) ends its trial with
    /// `Err(search.fail(message))` ([`Search::fail`]).
    fn run(&self, search: &mut dyn Search) -> Result<(), Stop>;
}

/// Every algorithm's configuration is its schema.
impl<T: Algorithm> Schema for T {
    const KIND: &'static str = <T as Algorithm>::KIND;

    fn validate(&self) -> Result<(), ConfigError> {
        Algorithm::validate(self)
    }
}

/// Runs the configuration behind `&dyn Any` (which must be the kind's type).
pub(crate) type Runner = fn(&dyn Any, &mut dyn Search) -> Result<(), Stop>;

/// The runner of `T`.
pub(crate) fn runner_of<T: Algorithm>() -> Runner {
    |config, search| match config.downcast_ref::<T>() {
        Some(config) => config.run(search),
        None => Err(search.fail(format!(
            "internal error: a configuration of another type was given to `{}`",
            <T as Algorithm>::KIND
        ))),
    }
}

/// A [`Schema`] with its type erased.
pub(crate) trait DynSchema: Debug + Send + Sync {
    fn kind(&self) -> &'static str;
    fn validate(&self) -> Result<(), ConfigError>;
    fn clone_box(&self) -> Box<dyn DynSchema>;
    fn dyn_eq(&self, other: &dyn Any) -> bool;
    fn capture(&self) -> Result<Value, serde::de::value::Error>;
    fn as_any(&self) -> &dyn Any;
    fn as_any_mut(&mut self) -> &mut dyn Any;
}

impl<T: Schema> DynSchema for T {
    fn kind(&self) -> &'static str {
        <T as Schema>::KIND
    }
    fn validate(&self) -> Result<(), ConfigError> {
        Schema::validate(self)
    }
    fn clone_box(&self) -> Box<dyn DynSchema> {
        Box::new(self.clone())
    }
    fn dyn_eq(&self, other: &dyn Any) -> bool {
        other.downcast_ref::<T>() == Some(self)
    }
    fn capture(&self) -> Result<Value, serde::de::value::Error> {
        capture(self)
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

/// One configuration with its type erased, and its kind's runner where this program has one.
pub(crate) struct Erased {
    pub(crate) config: Box<dyn DynSchema>,
    pub(crate) runner: Option<Runner>,
}

impl Erased {
    /// A configuration of a kind this program can run.
    pub(crate) fn runnable<T: Algorithm>(config: T) -> Self {
        Erased {
            config: Box::new(config),
            runner: Some(runner_of::<T>()),
        }
    }

    /// A configuration of a kind this program only reads.
    pub(crate) fn read_only<T: Schema>(config: T) -> Self {
        Erased {
            config: Box::new(config),
            runner: None,
        }
    }
}

impl Clone for Erased {
    fn clone(&self) -> Self {
        Erased {
            config: self.config.clone_box(),
            runner: self.runner,
        }
    }
}

/// The settings of a kind this program does not know, kept as read (see
/// [`crate::registry::read_unknown_kinds_as_opaque`]): serialised back field for field,
/// always valid, never run.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Opaque {
    pub(crate) kind: &'static str,
    pub(crate) fields: Vec<(Value, Value)>,
}

impl DynSchema for Opaque {
    fn kind(&self) -> &'static str {
        self.kind
    }
    fn validate(&self) -> Result<(), ConfigError> {
        Ok(())
    }
    fn clone_box(&self) -> Box<dyn DynSchema> {
        Box::new(self.clone())
    }
    fn dyn_eq(&self, other: &dyn Any) -> bool {
        other.downcast_ref::<Opaque>() == Some(self)
    }
    fn capture(&self) -> Result<Value, serde::de::value::Error> {
        Ok(Value::Map(self.fields.clone()))
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}
