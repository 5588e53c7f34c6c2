//! Flags of the model to fit, of `fit`, and of a parameter set (`gen`, `eval`, `render`).

use brdf_model::{BrdfParams, ExponentCoord, Lobe, LobeKind};
use clap::Args;

use super::DataArgs;
use super::values::{enum_value, finite, lobe, named_number, named_toml, params};

/// The model to fit.
#[derive(Args, Clone)]
pub struct ModelArgs {
    /// Number of lobes.
    #[arg(long, default_value_t = 1)]
    pub lobes: usize,
    /// Lobe kind: anisotropic or isotropic.
    #[arg(long, value_parser = enum_value::<LobeKind>, default_value = "anisotropic")]
    pub kind: LobeKind,
    /// Hold a parameter fixed: NAME=VALUE (e.g. lobe1.pan=45); repeatable.
    #[arg(long = "fix", value_name = "NAME=VALUE", value_parser = named_number)]
    pub fixed: Vec<(String, f64)>,
    /// Exponent coordinate of the optimiser: log1p (default) or raw (the paper's).
    #[arg(long, value_parser = enum_value::<ExponentCoord>, default_value = "log1p")]
    pub exponent: ExponentCoord,
}

/// `brdf-sls fit`.
#[derive(Args)]
pub struct FitArgs {
    /// The data set.
    #[command(flatten)]
    pub data: DataArgs,
    /// The model.
    #[command(flatten)]
    pub model: ModelArgs,
    /// Algorithm kind: aed, aers, rpls, ds, sa, sals, avg, asa.
    #[arg(long, default_value = "aed")]
    pub algorithm: String,
    /// Algorithm parameter NAME=VALUE (TOML value, e.g. phi=1.2); repeatable.
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = named_toml)]
    pub set: Vec<(String, toml::Value)>,
    /// Stop when the RMSE reaches this (default 0: use the whole budget).
    #[arg(long, default_value_t = 0.0, value_parser = finite)]
    pub target: f64,
    /// CPU-time budget in seconds.
    #[arg(long, default_value_t = 10.0, value_parser = finite)]
    pub cpu_seconds: f64,
    /// Seed of the run.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Evaluation kernel: auto, avx512, avx2, portable or scalar.
    #[arg(long, default_value = "auto")]
    pub kernel: brdf_model::Kernel,
    /// The descents' solver: default, gauss-newton, or n2fb (PORT's N2FB rule, the paper's).
    #[arg(long, default_value = "default")]
    pub descent: sls::DescentModel,
    /// Also diagnose the fit: singular values and condition number of the scaled Jacobian,
    /// standard errors, correlations, parameters the data cannot determine, seeded bootstrap
    /// intervals and sensitivity to perturbed data.
    #[arg(long)]
    pub diagnose: bool,
    /// Bootstrap resamples of --diagnose (0 skips the bootstrap).
    #[arg(long, default_value_t = 200, requires = "diagnose")]
    pub bootstrap: usize,
    /// Keep the search's best as it is, without the full-data descents that end the fit at a
    /// local minimum.
    #[arg(long)]
    pub no_polish: bool,
    /// Progress on standard error (the best RMSE each second): auto (a line on a terminal
    /// unless CI=true, nothing otherwise), bars (that line), plain (lines), quiet.
    #[arg(long, value_enum, default_value = "auto")]
    pub progress: brdf_experiment::progress::ProgressMode,
}

/// Parameters: a named set, JSON, or flags.
#[derive(Args, Clone)]
pub struct ParamArgs {
    /// Named parameters (tuning, cross, paper-bluepaint, pbrt-bluepaint), JSON
    /// {"kd":0.15,"lobes":[{"cx":-1,"cy":0.8,"cz":0.96,"n":20,"pan_deg":45}]} or @FILE.
    #[arg(long, value_parser = params)]
    pub params: Option<BrdfParams>,
    /// Diffuse term kd (with --lobe, instead of --params).
    #[arg(long, value_parser = finite)]
    pub kd: Option<f64>,
    /// A lobe CX,CY,CZ,N[,PAN_DEG]; repeatable.
    #[arg(
        long = "lobe",
        value_name = "CX,CY,CZ,N[,PAN]",
        allow_hyphen_values = true,
        value_parser = lobe
    )]
    pub lobes: Vec<Lobe>,
}

impl ParamArgs {
    /// The parameter set the flags describe, checked against the model's box.
    pub fn params(&self) -> Result<BrdfParams, String> {
        if let Some(p) = &self.params {
            if self.kd.is_some() || !self.lobes.is_empty() {
                return Err("give either --params or --kd/--lobe, not both".into());
            }
            return Ok(p.clone());
        }
        let Some(kd) = self.kd else {
            return Err("give --params NAME|JSON|@FILE, or --kd and --lobe".into());
        };
        let p = BrdfParams {
            kd,
            lobes: self.lobes.clone(),
        };
        p.validate().map_err(|e| format!("--kd/--lobe: {e}"))?;
        Ok(p)
    }
}
