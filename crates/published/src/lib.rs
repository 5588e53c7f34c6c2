//! Published per-material BRDF fits of the MERL materials: a reader for bbm's `.fit` files and
//! the conversions of Ngan et al.'s fits into this crate's parameters: Lafortune
//! ([`BrdfParams`]), Cook-Torrance ([`NganCookTorrance`]), Blinn-Phong ([`NganBlinnPhong`]),
//! Ward ([`NganWard`]) and Ashikhmin-Shirley ([`NganAshikhminShirley`]) as [`brdf_model::Params`] of
//! those families; [`bounds_violations`] lists what falls outside a family's bounds. The
//! [`suite`] module turns them into named suites of synthetic instances (`ngan-ward`, ...)
//! sampled like the Cornell or MERL measurements.
//!
//! The files in `experiments/data/published-fits/` come from the BSD-licensed repository
//! bsdfbenchmark/bbm (folder `fits/`); they hold the fits that Ngan, Durand and Matusik (2005),
//! Löw et al. (2012) and Bagher et al. (2012) published. `docs/published-fits.md` gives their
//! provenance, every model's formula and parameter conventions as bbm evaluates them, and the
//! ranges of the values ([`report_markdown`] writes that page's tables).
//!
//! # The `.fit` format
//! UTF-8 text, one material per line; lines starting with `#` are comments (bbm's files name
//! the paper there) and blank lines are skipped:
//!
//! ```text
//! # BSDF fits for the lafortune BSDF model extracted from: ...
//! alum-bronze = Aggregate(Lambertian(albedo = [0.0923, 0.0625, 0.0311]), NganLafortune(albedo = [0.322, 0.193, 0.105], Cxy = -0.579, Cz = 0.574, sharpness = 630.0))
//! ```
//!
//! The grammar (whitespace between tokens is free):
//!
//! ```text
//! line     = material "=" call
//! material = 1*( letter | digit | "-" | "_" | "." | "+" )
//! call     = ident "(" [ arg *( "," arg ) ] ")"
//! arg      = [ ident "=" ] expr
//! expr     = number | "[" [ expr *( "," expr ) ] "]" | call
//! ident    = ( letter | "_" ) *( letter | digit | "_" )
//! ```
//!
//! Numbers are Rust `f64` literals (`0.5`, `1.27e-07`, `-3`) and must be finite. The call is
//! either `Aggregate(...)` with models as positional arguments, or a single model. A
//! `Lambertian(albedo = [r, g, b])` term (at most one) becomes [`PublishedFit::diffuse`]; there
//! must be exactly one other model, the specular one, whose arguments must all be named. A
//! parameter is a number (the same for the three channels, [`FitParam::shared`]), a list of
//! three numbers (red, green, blue) or a list of such lists (Bagher's two-component `eta`),
//! which becomes one parameter per inner list, named `eta.0`, `eta.1`, ... A material may
//! appear once per file.
//!
//! # Errors and limits
//! Every problem is a [`FitError`] naming the file, the line and column and what was
//! expected; nothing panics. Input is bounded by [`MAX_FIT_BYTES`], [`MAX_FIT_LINE_BYTES`],
//! [`MAX_FIT_MATERIALS`], [`MAX_FIT_DEPTH`], [`MAX_FIT_ITEMS`] and [`MAX_FIT_NAME_BYTES`].
//!
//! # Example
//! ```
//! use brdf_published::{NganLafortune, parse_fits};
//! let text = "m = Aggregate(Lambertian(albedo = [0.1, 0.2, 0.3]), \
//!             NganLafortune(albedo = [0.5, 0.4, 0.3], Cxy = -0.577, Cz = 0.577, sharpness = 100.0))";
//! let file = parse_fits(text, "example.fit").unwrap();
//! let fit = &file.fits[0];
//! assert_eq!(fit.model, "NganLafortune");
//! assert_eq!(fit.rgb("sharpness"), Some([100.0; 3]));
//! let params = NganLafortune::from_fit(fit).unwrap().to_params_default();
//! assert!((params.kd - 0.2 / std::f64::consts::PI).abs() < 1e-15); // green channel
//! ```
//!
//! [`BrdfParams`]: brdf_model::BrdfParams

#![warn(missing_docs)]

mod ashikhmin_shirley;
mod blinn_phong;
mod bounds;
mod convert;
mod cook_torrance;
mod lafortune;
mod parse;
mod report;
pub mod suite;
mod ward;

pub use ashikhmin_shirley::NganAshikhminShirley;
pub use blinn_phong::NganBlinnPhong;
pub use bounds::bounds_violations;
pub use cook_torrance::{GGX_PER_BECKMANN, NganCookTorrance, ggx_alpha_from_beckmann};
pub use lafortune::{
    BoxViolation, ConvertError, DEFAULT_CHANNEL, NganLafortune, table1_violations,
};
pub use parse::{
    FitError, FitFile, MAX_FIT_BYTES, MAX_FIT_DEPTH, MAX_FIT_ITEMS, MAX_FIT_LINE_BYTES,
    MAX_FIT_MATERIALS, MAX_FIT_NAME_BYTES, parse_fits, read_fits,
};
pub use report::{FIT_FILES, ParamSummary, report_markdown, summarise};
pub use ward::NganWard;

use brdf_io::Channel;

/// One material's published fit: the material, the model and its parameters per channel.
#[derive(Clone, Debug, PartialEq)]
pub struct PublishedFit {
    /// The MERL material name as in the file (`alum-bronze`, `specular-black-phenolic`, ...).
    pub material: String,
    /// bbm's name of the specular model (`NganLafortune`, `NganWard`, `LowCookTorrance`,
    /// `Bagher`, ...); `docs/published-fits.md` gives each one's formula.
    pub model: String,
    /// The line of the file it was read from (from 1).
    pub line: usize,
    /// The albedo of the `Lambertian` term, red, green, blue (the BRDF term is albedo / pi);
    /// `None` when the line has no Lambertian term.
    pub diffuse: Option<[f64; 3]>,
    /// The specular model's parameters, in file order.
    pub params: Vec<FitParam>,
}

/// One parameter of a published fit.
#[derive(Clone, Debug, PartialEq)]
pub struct FitParam {
    /// The name as in the file (`albedo`, `roughness`, `sharpness`, ...); a list of lists
    /// gives `name.0`, `name.1`, ...
    pub name: String,
    /// The value for red, green and blue (the same three times when [`FitParam::shared`]).
    pub rgb: [f64; 3],
    /// True when the file gives one number for all channels.
    pub shared: bool,
}

impl PublishedFit {
    /// The parameter called `name`, if the model has it.
    pub fn param(&self, name: &str) -> Option<&FitParam> {
        self.params.iter().find(|p| p.name == name)
    }

    /// The red, green and blue values of the parameter called `name`.
    pub fn rgb(&self, name: &str) -> Option<[f64; 3]> {
        self.param(name).map(|p| p.rgb)
    }

    /// The value of the parameter called `name` in one channel.
    pub fn value(&self, name: &str, channel: Channel) -> Option<f64> {
        self.rgb(name).map(|v| v[channel_index(channel)])
    }
}

/// 0, 1, 2 for red, green, blue.
pub(crate) fn channel_index(channel: Channel) -> usize {
    match channel {
        Channel::Red => 0,
        Channel::Green => 1,
        Channel::Blue => 2,
    }
}
