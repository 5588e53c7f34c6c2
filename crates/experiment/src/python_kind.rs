//! `kind = "python"`: the configuration of a search algorithm written in Python, defined once
//! for the Python package, which runs it (`brdf_sls`, crates/py), and for the command line,
//! which reads, checks and summarises specs and results that use it (its schema) and runs its
//! trials in worker processes of the Python package.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};
use sls::ConfigError;
use sls::registry::Schema;

/// The kind's tag.
pub const KIND: &str = "python";

/// `[[algorithm]] kind = "python"`: `entry = "package.module:function"` names the function, and
/// every other key of the entry is passed to it as a keyword argument.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PythonEntry {
    /// The function: `package.module:function`.
    pub entry: String,
    /// Every other key of the entry: the function's keyword arguments.
    #[serde(flatten)]
    pub settings: BTreeMap<String, serde_json::Value>,
}

impl PythonEntry {
    /// The module path and the function name of [`PythonEntry::entry`], or an error naming the
    /// expected form.
    pub fn split_entry(&self) -> Result<(&str, &str), ConfigError> {
        let bad = || {
            ConfigError::new(
                KIND,
                "entry",
                format!("must be `package.module:function`, found {:?}", self.entry),
            )
        };
        let (module, function) = self.entry.split_once(':').ok_or_else(bad)?;
        if !module.split('.').all(is_identifier) || !is_identifier(function) {
            return Err(bad());
        }
        Ok((module, function))
    }

    /// Checks the entry's form and that every setting can be a keyword argument (what can be
    /// checked without Python).
    pub fn check_form(&self) -> Result<(), ConfigError> {
        self.split_entry()?;
        match self.settings.keys().find(|k| !is_identifier(k)) {
            Some(key) => Err(ConfigError::new(
                KIND,
                "entry",
                format!(
                    "setting `{key}` is not a Python identifier, so it cannot be passed as a \
                     keyword argument"
                ),
            )),
            None => Ok(()),
        }
    }
}

/// Whether `s` is a Python identifier (ASCII or Unicode letters, digits and `_`, not starting
/// with a digit).
pub fn is_identifier(s: &str) -> bool {
    let mut chars = s.chars();
    chars.next().is_some_and(|c| c.is_alphabetic() || c == '_')
        && chars.all(|c| c.is_alphanumeric() || c == '_')
}

/// The kind's schema: what the command line registers ([`register_schema`]) to read, check,
/// store and summarise specs and results that name it; the Python package registers the same
/// settings with a runner.
impl Schema for PythonEntry {
    const KIND: &'static str = KIND;

    fn validate(&self) -> Result<(), ConfigError> {
        self.check_form()
    }
}

/// Registers the kind's schema unless the kind is registered already (by the Python package,
/// which runs it).
pub fn register_schema() {
    // The only possible error is the kind being taken, which is what this asks for.
    let _ = sls::registry::register_schema::<PythonEntry>();
}

#[cfg(test)]
mod tests {
    use super::*;
    use sls::AlgorithmConfig;

    #[test]
    fn entries_are_checked_for_form() {
        let entry = |e: &str| PythonEntry {
            entry: e.into(),
            settings: BTreeMap::new(),
        };
        assert_eq!(entry("pkg.mod:f").split_entry(), Ok(("pkg.mod", "f")));
        for bad in [
            "pkg.mod",
            "pkg..mod:f",
            ":f",
            "m:",
            "m:f:g",
            "1m:f",
            "m:f-g",
        ] {
            let e = entry(bad).check_form().unwrap_err();
            assert_eq!(e.field, "entry");
            assert!(e.message.contains("package.module:function"), "{bad}");
        }
        let mut e = entry("m:f");
        e.settings.insert("step-size".into(), 1.into());
        assert!(e.check_form().unwrap_err().message.contains("`step-size`"));
    }

    #[test]
    fn the_schema_reads_and_writes_the_packages_records() {
        register_schema();
        let text = r#"{"kind":"python","entry":"algos.walk:search","step":0.1,"restarts":true}"#;
        let config: AlgorithmConfig = serde_json::from_str(text).unwrap();
        assert_eq!(config.kind_name(), "python");
        assert_eq!(config.validate(), Ok(()));
        assert!(!config.can_run(), "the schema alone runs nothing");
        // The settings come back sorted by name, as the package writes them.
        let again = serde_json::to_string(&config).unwrap();
        assert_eq!(
            again,
            r#"{"kind":"python","entry":"algos.walk:search","restarts":true,"step":0.1}"#
        );
        let missing = serde_json::from_str::<AlgorithmConfig>(r#"{"kind":"python"}"#);
        assert!(missing.unwrap_err().to_string().contains("entry"));
    }
}
