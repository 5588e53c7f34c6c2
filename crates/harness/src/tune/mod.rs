//! Automatic tuning with irace: irace's input files and the parsing of its output ([`irace`]),
//! and the validation experiment that compares irace's elites with the defaults
//! ([`validation`]). The spec's `[tune]` table is
//! [`brdf_experiment::spec::tune`].

pub mod irace;
pub mod validation;
