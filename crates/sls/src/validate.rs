//! Configuration errors and the range checks the algorithm configurations share.
//!
//! The algorithms' `validate` methods use these; [`crate::AlgorithmConfig`] (which depends on
//! the algorithms) only forwards to them, so the dependency runs one way:
//! `config -> algorithms -> validate`.

/// A configuration value out of range; names the algorithm and the field.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("invalid {algorithm} configuration: `{field}` {message}")]
pub struct ConfigError {
    /// Algorithm kind (`"aed"`, ...).
    pub algorithm: &'static str,
    /// The offending field.
    pub field: &'static str,
    /// What was expected, with the value found.
    pub message: String,
}

impl ConfigError {
    /// A new error for `algorithm.field`.
    pub fn new(algorithm: &'static str, field: &'static str, message: impl Into<String>) -> Self {
        Self {
            algorithm,
            field,
            message: message.into(),
        }
    }
}

/// Checks `value >= min` (and finite) for a real-valued field.
pub(crate) fn check_at_least(
    algorithm: &'static str,
    field: &'static str,
    value: f64,
    min: f64,
) -> Result<(), ConfigError> {
    if value.is_finite() && value >= min {
        Ok(())
    } else {
        Err(ConfigError::new(
            algorithm,
            field,
            format!("must be a finite number >= {min}, found {value}"),
        ))
    }
}

/// Checks `value >= min` for an integer field.
pub(crate) fn check_count(
    algorithm: &'static str,
    field: &'static str,
    value: usize,
    min: usize,
) -> Result<(), ConfigError> {
    if value >= min {
        Ok(())
    } else {
        Err(ConfigError::new(
            algorithm,
            field,
            format!("must be at least {min}, found {value}"),
        ))
    }
}
