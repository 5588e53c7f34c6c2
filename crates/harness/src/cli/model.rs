//! Flags of the model to fit, of `fit`, and of a parameter set (`gen`, `eval`, `render`).

use brdf_model::{ExponentCoord, FamilyRef, LobeKind, Params};
use clap::Args;

use super::DataArgs;
use super::values::{
    enum_value, family, finite, lobe_of, named_bounds, named_number, named_toml, params,
};

/// The model to fit.
#[derive(Args, Clone)]
pub struct ModelArgs {
    /// The model family: lafortune (the paper's, the default), ggx, cook-torrance, ward,
    /// ward-gmd, blinn-phong, ashikhmin-shirley, or one a program registered.
    #[arg(long, value_parser = family, default_value = "lafortune")]
    pub family: FamilyRef,
    /// Number of lobes.
    #[arg(long, default_value_t = 1)]
    pub lobes: usize,
    /// Lobe kind: anisotropic or isotropic (default: anisotropic where the family has it).
    #[arg(long, value_parser = enum_value::<LobeKind>)]
    pub kind: Option<LobeKind>,
    /// Hold a parameter fixed: NAME=VALUE (e.g. lobe1.pan=45); repeatable.
    #[arg(long = "fix", value_name = "NAME=VALUE", value_parser = named_number)]
    pub fixed: Vec<(String, f64)>,
    /// Bounds of a parameter: NAME=LO,HI (e.g. lobe1.n=0,20000), inside its family's box;
    /// an exponent's may reach beyond Table 1's 10000, up to 1e6 (measured metals need
    /// 16600); repeatable.
    #[arg(long = "bounds", value_name = "NAME=LO,HI", value_parser = named_bounds)]
    pub bounds: Vec<(String, [f64; 2])>,
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
    /// Algorithm kind: aed, aers, rpls, ds, sa, sals, avg, asa (default rpls: on noisy
    /// 2-lobe data AED left a lobe dead in 9 of 20 seeds, RPLS in none).
    #[arg(long, default_value = brdf_fit::DEFAULT_ALGORITHM)]
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

impl ModelArgs {
    /// The lobe kind: as given, else anisotropic where the family has it, else its one kind.
    pub fn kind(&self) -> LobeKind {
        self.kind.unwrap_or_else(|| {
            let kinds = self.family.kinds();
            if kinds.contains(&LobeKind::Anisotropic) {
                LobeKind::Anisotropic
            } else {
                kinds[0]
            }
        })
    }
}

/// Parameters: a named set, JSON, or flags.
#[derive(Args, Clone)]
pub struct ParamArgs {
    /// Named parameters (tuning, cross, paper-bluepaint, pbrt-bluepaint), JSON
    /// {"kd":0.15,"lobes":[{"cx":-1,"cy":0.8,"cz":0.96,"n":20,"pan_deg":45}]} (another family:
    /// {"family":"ggx","kd":0.1,"lobes":[{"ks":0.5,"ax":0.1,"ay":0.1,"f0":0.04,"pan":0}]}) or
    /// @FILE.
    #[arg(long, value_parser = params)]
    pub params: Option<Params>,
    /// The family of --kd and --lobe (default lafortune).
    #[arg(long = "family", value_parser = family, value_name = "FAMILY")]
    pub family: Option<FamilyRef>,
    /// Diffuse term kd (with --lobe, instead of --params).
    #[arg(long, value_parser = finite)]
    pub kd: Option<f64>,
    /// A lobe: its fields in the family's order (Lafortune: CX,CY,CZ,N[,PAN_DEG]) or
    /// NAME=VALUE pairs (ks=0.5,ax=0.1,ay=0.2); repeatable.
    #[arg(
        long = "lobe",
        value_name = "CX,CY,CZ,N[,PAN] | NAME=VALUE,...",
        allow_hyphen_values = true
    )]
    pub lobes: Vec<String>,
}

impl ParamArgs {
    /// The parameter set the flags describe, checked against its family's box.
    pub fn params(&self) -> Result<Params, String> {
        if let Some(p) = &self.params {
            if self.kd.is_some() || !self.lobes.is_empty() {
                return Err("give either --params or --kd/--lobe, not both".into());
            }
            if let Some(f) = &self.family
                && f != p.family()
            {
                return Err(format!(
                    "--family {} but --params are of the {} family",
                    f.name(),
                    p.family().name()
                ));
            }
            return Ok(p.clone());
        }
        let Some(kd) = self.kd else {
            return Err("give --params NAME|JSON|@FILE, or --kd and --lobe".into());
        };
        let family = self.family.clone().unwrap_or_else(FamilyRef::lafortune);
        let mut p = Params::defaults(family.clone(), 0);
        if !p.set("kd", kd) {
            return Err(format!("--kd: the {} family has no kd", family.name()));
        }
        for l in &self.lobes {
            let values = lobe_of(&family, l).map_err(|e| format!("--lobe {e}"))?;
            p.push_lobe(values).map_err(|e| format!("--lobe: {e}"))?;
        }
        p.validate().map_err(|e| format!("--kd/--lobe: {e}"))?;
        Ok(p)
    }
}
