//! Flags naming a data file and its filters (`fit`, `eval`, `info`, `polar`).

use std::path::PathBuf;

use brdf_experiment::spec::{FileSpec, FormatName};
use clap::Args;

use super::values::enum_value;

/// Where a data set comes from and how it is filtered. The defaults are the data policy every
/// command shares, `run` included: non-finite values and samples below the horizon are dropped,
/// negative values are kept (noisy measurements and noisy synthetic data have them, and
/// dropping them biases the RMSE).
#[derive(Args, Clone)]
pub struct DataArgs {
    /// Data file: Cornell .brdf, CSV, MERL binary or ALTA text (.dat, .alta).
    pub data: PathBuf,
    /// File format: cornell, csv, merl or alta (default: from the extension).
    #[arg(long, value_parser = |s: &str| s.parse::<FormatName>())]
    pub format: Option<FormatName>,
    /// Cornell wavelength in nm (default 550); Cornell files only.
    #[arg(long)]
    pub wavelength: Option<f64>,
    /// Channel of MERL and ALTA RGB files: red, green (default) or blue.
    #[arg(long, value_parser = enum_value::<brdf_io::Channel>)]
    pub channel: Option<brdf_io::Channel>,
    /// What an ALTA file's values are when its header lacks #PARAM_OUT: INV_STERADIAN,
    /// INV_STERADIAN_COSINE_FACTOR or RGB_COLOR.
    #[arg(long, value_parser = enum_value::<brdf_io::AltaOutput>)]
    pub param_out: Option<brdf_io::AltaOutput>,
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
            format: self.format.clone(),
            wavelength: self.wavelength,
            channel: self.channel,
            param_out: self.param_out,
            max_value: self.max_value,
            drop_negative: self.drop_negative,
            drop_below_horizon: !self.keep_below_horizon,
        }
    }
}
