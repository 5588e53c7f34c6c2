//! Flags naming a data file and its filters (`fit`, `eval`, `info`, `polar`).

use std::path::PathBuf;

use brdf_experiment::spec::{DataFormat, FileSpec};
use clap::Args;

use super::values::{choice, enum_value};

/// Where a data set comes from and how it is filtered. The defaults are the data policy every
/// command shares, `run` included: non-finite values and samples below the horizon are dropped,
/// negative values are kept (noisy measurements and noisy synthetic data have them, and
/// dropping them biases the RMSE).
#[derive(Args, Clone)]
pub struct DataArgs {
    /// Data file: Cornell .brdf, CSV, or MERL binary.
    pub data: PathBuf,
    /// File format (default: from the extension).
    #[arg(long, value_parser = choice::<DataFormat>(DataFormat::NAMES))]
    pub format: Option<DataFormat>,
    /// Cornell wavelength in nm.
    #[arg(long, default_value_t = brdf_model::DEFAULT_WAVELENGTH_NM)]
    pub wavelength: f64,
    /// MERL channel: red, green or blue.
    #[arg(long, value_parser = enum_value::<brdf_model::Channel>, default_value = "green")]
    pub channel: brdf_model::Channel,
    /// Drop values above this (the paper used 1 for the Cornell paint).
    #[arg(long)]
    pub max_value: Option<f64>,
    /// Drop negative values (kept by default).
    #[arg(long)]
    pub drop_negative: bool,
    /// Keep samples with a direction below the horizon (dropped by default).
    #[arg(long)]
    pub keep_below_horizon: bool,
}

impl DataArgs {
    /// The same file and filters as an experiment spec's `[instance.file]` would give.
    pub fn file_spec(&self) -> FileSpec {
        FileSpec {
            path: self.data.clone(),
            format: self.format,
            wavelength: Some(self.wavelength),
            channel: Some(self.channel),
            max_value: self.max_value,
            drop_negative: self.drop_negative,
            drop_below_horizon: !self.keep_below_horizon,
        }
    }
}
