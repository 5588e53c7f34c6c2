//! Named suites of realistic instances: the MERL materials' parameter values that Ngan et al.
//! (2005) published, converted into this project's families, to be sampled at Cornell-like,
//! MERL-like or uniform direction pairs with stated, seeded noise ([`sampling`]).
//!
//! | suite | family | from |
//! |---|---|---|
//! | `ngan-lafortune` | `lafortune` | `ngan_lafortune.fit` ([`crate::NganLafortune`], exact) |
//! | `ngan-cook-torrance` | `cook-torrance` | `ngan_cooktorrance.fit` ([`crate::NganCookTorrance`], exact) |
//! | `ngan-blinn-phong` | `blinn-phong` | `ngan_blinnphong.fit` ([`crate::NganBlinnPhong`], the half-vector reading) |
//! | `ngan-ward` | `ward` | `ngan_ward.fit` ([`crate::NganWard`], exact) |
//! | `ngan-ashikhmin-shirley` | `ashikhmin-shirley` | `ngan_ashikhminshirley.fit` ([`crate::NganAshikhminShirley`], exact) |
//! | `ngan-ggx` | `ggx` | `ngan_cooktorrance.fit` through [`crate::NganCookTorrance::to_ggx_params`] (an approximation) |
//!
//! Each suite has the 86 materials of its file, in file order, in one colour channel (green
//! by default, like MERL files elsewhere in the project). The fit files are compiled in (from
//! `experiments/data/published-fits/`), so a suite needs no file at run time.
//!
//! **Bounds.** A material whose converted parameters leave the family's bounds is listed with
//! its violations ([`SuiteMaterial::violations`]). Where the suite states a wider bound for the
//! field ([`Suite::widened_bounds`]) the material is included and an instance of it fits with
//! that bound widened (the spec's `model.bounds`, which may exceed the family's box); otherwise
//! it is excluded ([`SuiteMaterial::inclusion`]). Only `ngan-lafortune` has such materials: 5
//! need `n` above Table 1's 10,000 (brass, hematite, steel, tungsten-carbide,
//! specular-violet-phenolic; up to 16,600), included with `lobe1.n` in [0, 20000].
//! `docs/suites.md` lists every suite's materials ([`listing_markdown`]).
//!
//! # Example
//! ```
//! use brdf_published::suite::{Noise, Sampling, generate, suite};
//! let s = suite("ngan-ward").unwrap();
//! let m = s.material("gold-metallic-paint", brdf_io::Channel::Green).unwrap();
//! let noise = Noise { relative: 0.01, absolute: 0.0 };
//! let data = generate(&m.params, Sampling::Merl, 2000, noise, 1).unwrap();
//! assert_eq!(data.len(), 2000);
//! ```

pub mod sampling;

use crate::{BoxViolation, ConvertError, PublishedFit, bounds_violations, parse_fits};
use crate::{NganAshikhminShirley, NganBlinnPhong, NganCookTorrance, NganLafortune, NganWard};
use brdf_io::Channel;
use brdf_model::{FamilyRef, Params};
use rand::SeedableRng;
use std::fmt::Write as _;

pub use sampling::{
    CORNELL_PAIRS, CORNELL_RETRO_EXCLUSION_DEG, MERL_CELLS, Noise, Pair, Sampling, cornell_pairs,
    generate, merl_cell,
};

/// Why a suite, material, pattern or generated instance is refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SuiteError {
    /// No suite has the name.
    #[error("unknown suite `{name}`; the suites: {}", suite_list())]
    UnknownSuite {
        /// The name asked for.
        name: String,
    },
    /// The suite has no such material.
    #[error("suite `{suite}` has no material `{name}`; its materials: {valid}")]
    UnknownMaterial {
        /// The suite.
        suite: String,
        /// The name asked for.
        name: String,
        /// Every material of the suite, comma-separated.
        valid: String,
    },
    /// The material is outside the family's bounds and the suite does not widen them.
    #[error("suite `{suite}`: material `{material}` is excluded: {why}")]
    Excluded {
        /// The suite.
        suite: String,
        /// The material.
        material: String,
        /// The fields outside the bounds.
        why: String,
    },
    /// No pattern has the name.
    #[error("unknown sampling `{name}`; expected one of: cornell, merl, uniform")]
    UnknownSampling {
        /// The name asked for.
        name: String,
    },
    /// A sample count the pattern cannot give.
    #[error("`{sampling}` sampling gives 1 to {max} samples, found {samples}")]
    SampleCount {
        /// The pattern.
        sampling: &'static str,
        /// The count asked for.
        samples: usize,
        /// The pattern's most.
        max: usize,
    },
    /// A noise part out of range.
    #[error(
        "noise: the relative part must be a finite number in [0, 10] and the absolute one in \
         [0, {}], found {relative} and {absolute}",
        brdf_model::MAX_SIGMA
    )]
    Noise {
        /// Relative part.
        relative: f64,
        /// Absolute part.
        absolute: f64,
    },
    /// A material sample larger than the suite.
    #[error("suite `{suite}`: a sample of {count} materials; expected 1 to {available}")]
    MaterialCount {
        /// The suite.
        suite: String,
        /// The count asked for.
        count: usize,
        /// Materials in the suite.
        available: usize,
    },
    /// A generated value is not finite.
    #[error("sample {index}: the value {value} is not finite")]
    NonFinite {
        /// Sample index.
        index: usize,
        /// The value.
        value: f64,
    },
    /// The compiled-in fit file could not be read or converted (a defect of the build).
    #[error("suite `{suite}`: {message}")]
    Data {
        /// The suite.
        suite: String,
        /// The reader's or converter's message.
        message: String,
    },
}

/// A named suite: a published fit file converted into one family.
#[derive(Debug)]
pub struct Suite {
    name: &'static str,
    family: &'static str,
    file: &'static str,
    text: &'static str,
    convert: fn(&PublishedFit, Channel) -> Result<Params, ConvertError>,
    description: &'static str,
    widen: &'static [(&'static str, f64, f64)],
}

/// Every suite, in the order of [`SUITE_NAMES`].
static SUITES: [Suite; 6] = [
    Suite {
        name: "ngan-lafortune",
        family: "lafortune",
        file: "ngan_lafortune.fit",
        text: include_str!("../../../../experiments/data/published-fits/ngan_lafortune.fit"),
        convert: |f, c| Ok(Params::from(NganLafortune::from_fit(f)?.to_params(c))),
        description: "Ngan et al.'s normalised one-lobe Lafortune fits, converted exactly (one \
            isotropic lobe); 5 materials need n above Table 1's 10,000 (up to 16,600) and are \
            included with lobe1.n widened to [0, 20000]",
        widen: &[("lobe1.n", 0.0, 20000.0)],
    },
    Suite {
        name: "ngan-cook-torrance",
        family: "cook-torrance",
        file: "ngan_cooktorrance.fit",
        text: include_str!("../../../../experiments/data/published-fits/ngan_cooktorrance.fit"),
        convert: |f, c| Ok(NganCookTorrance::from_fit(f)?.to_params(c)),
        description: "Ngan et al.'s Cook-Torrance fits (Beckmann, V-cavity, Schlick), converted \
            exactly",
        widen: &[],
    },
    Suite {
        name: "ngan-blinn-phong",
        family: "blinn-phong",
        file: "ngan_blinnphong.fit",
        text: include_str!("../../../../experiments/data/published-fits/ngan_blinnphong.fit"),
        convert: |f, c| Ok(NganBlinnPhong::from_fit(f)?.to_params(c)),
        description: "Ngan et al.'s Blinn-Phong fits in the half-vector reading \
            (docs/published-fits.md), exact in that reading",
        widen: &[],
    },
    Suite {
        name: "ngan-ward",
        family: "ward",
        file: "ngan_ward.fit",
        text: include_str!("../../../../experiments/data/published-fits/ngan_ward.fit"),
        convert: |f, c| Ok(NganWard::from_fit(f)?.to_params(c)),
        description: "Ngan et al.'s Ward fits, converted exactly",
        widen: &[],
    },
    Suite {
        name: "ngan-ashikhmin-shirley",
        family: "ashikhmin-shirley",
        file: "ngan_ashikhminshirley.fit",
        text: include_str!("../../../../experiments/data/published-fits/ngan_ashikhminshirley.fit"),
        convert: |f, c| Ok(NganAshikhminShirley::from_fit(f)?.to_params(c)),
        description: "Ngan et al.'s Ashikhmin-Shirley fits, converted exactly",
        widen: &[],
    },
    Suite {
        name: "ngan-ggx",
        family: "ggx",
        file: "ngan_cooktorrance.fit",
        text: include_str!("../../../../experiments/data/published-fits/ngan_cooktorrance.fit"),
        convert: |f, c| Ok(NganCookTorrance::from_fit(f)?.to_ggx_params(c)),
        description: "GGX lobes from Ngan et al.'s Cook-Torrance fits with Beckmann's \
            half-maximum width (alpha = 1.2936 m), the same kd, ks and f0: an APPROXIMATION, not \
            a conversion (the distributions differ by a total-variation distance of 0.32; over \
            10,000 uniform direction pairs the RMSE between the two BRDFs is 0.056 to 3.24 \
            times the Cook-Torrance BRDF's RMS, median 0.98, mostly from the masking; \
            docs/model.md)",
        widen: &[],
    },
];

/// The suites' names.
pub const SUITE_NAMES: [&str; 6] = [
    "ngan-lafortune",
    "ngan-cook-torrance",
    "ngan-blinn-phong",
    "ngan-ward",
    "ngan-ashikhmin-shirley",
    "ngan-ggx",
];

fn suite_list() -> String {
    SUITE_NAMES.join(", ")
}

/// Every suite.
pub fn suites() -> &'static [Suite] {
    &SUITES
}

/// The suite called `name`; an unknown name is an error listing the suites.
pub fn suite(name: &str) -> Result<&'static Suite, SuiteError> {
    SUITES
        .iter()
        .find(|s| s.name == name)
        .ok_or_else(|| SuiteError::UnknownSuite {
            name: name.to_string(),
        })
}

/// One material of a suite in one channel.
#[derive(Clone, Debug, PartialEq)]
pub struct SuiteMaterial {
    /// The MERL material name.
    pub name: String,
    /// Its parameters in the suite's family.
    pub params: Params,
    /// The fields outside the family's own bounds (empty for most).
    pub violations: Vec<BoxViolation>,
}

/// Whether a material can be used, and how.
#[derive(Clone, Debug, PartialEq)]
pub enum Inclusion {
    /// Inside the family's bounds.
    Inside,
    /// Outside them, included with these bounds widened (field name, `[lo, hi]`).
    Widened(Vec<(String, [f64; 2])>),
    /// Outside them where the suite widens nothing: not usable; the violations, as text.
    Excluded(String),
}

impl SuiteMaterial {
    /// How the suite `s` (the material's own) can use the material.
    pub fn inclusion(&self, s: &Suite) -> Inclusion {
        if self.violations.is_empty() {
            return Inclusion::Inside;
        }
        let mut widened = Vec::new();
        for v in &self.violations {
            match s.widen.iter().find(|w| w.0 == v.name) {
                Some(&(name, lo, hi)) if v.value >= lo && v.value <= hi => {
                    widened.push((name.to_string(), [lo, hi]));
                }
                _ => return Inclusion::Excluded(self.violation_text()),
            }
        }
        Inclusion::Widened(widened)
    }

    /// The violations, `lobe1.n = 16600 outside [0, 10000]; ...`.
    pub fn violation_text(&self) -> String {
        let parts: Vec<String> = self.violations.iter().map(|v| v.to_string()).collect();
        parts.join("; ")
    }
}

/// Which materials of a suite to take.
#[derive(Clone, Debug, PartialEq)]
pub enum Selection {
    /// Every usable material (inside the bounds or included with them widened).
    All,
    /// Only the materials inside the family's own bounds.
    InBounds,
    /// These, by name (each must exist and be usable).
    Names(Vec<String>),
    /// `count` usable materials drawn without replacement with `seed` (PCG64-MCG), in file
    /// order.
    Sample {
        /// How many.
        count: usize,
        /// The draw's seed.
        seed: u64,
    },
}

impl Suite {
    /// The suite's name (`ngan-ward`).
    pub fn name(&self) -> &'static str {
        self.name
    }

    /// The name of its family (`ward`).
    pub fn family_name(&self) -> &'static str {
        self.family
    }

    /// Its family.
    pub fn family(&self) -> FamilyRef {
        brdf_model::family(self.family).expect("a suite's family is a built-in one")
    }

    /// The published file it is drawn from (in `experiments/data/published-fits/`).
    pub fn fit_file(&self) -> &'static str {
        self.file
    }

    /// What it holds and how it was converted (for `ngan-ggx`: that it is an approximation,
    /// with its measured accuracy).
    pub fn description(&self) -> &'static str {
        self.description
    }

    /// The bounds the suite widens for materials outside the family's (field name, lo, hi).
    pub fn widened_bounds(&self) -> &'static [(&'static str, f64, f64)] {
        self.widen
    }

    fn data_error(&self, message: String) -> SuiteError {
        SuiteError::Data {
            suite: self.name.into(),
            message,
        }
    }

    /// Every material in file order, converted in `channel`.
    pub fn materials(&self, channel: Channel) -> Result<Vec<SuiteMaterial>, SuiteError> {
        let file = parse_fits(self.text, self.file).map_err(|e| self.data_error(e.to_string()))?;
        file.fits
            .iter()
            .map(|f| {
                let params =
                    (self.convert)(f, channel).map_err(|e| self.data_error(e.to_string()))?;
                Ok(SuiteMaterial {
                    name: f.material.clone(),
                    violations: bounds_violations(&params),
                    params,
                })
            })
            .collect()
    }

    /// The material called `name`, converted in `channel`; an unknown name is an error
    /// listing the suite's materials. (An excluded material is returned: see
    /// [`SuiteMaterial::inclusion`].)
    pub fn material(&self, name: &str, channel: Channel) -> Result<SuiteMaterial, SuiteError> {
        let all = self.materials(channel)?;
        let valid = || {
            all.iter()
                .map(|m| m.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        };
        let Some(m) = all.iter().find(|m| m.name == name) else {
            return Err(SuiteError::UnknownMaterial {
                suite: self.name.into(),
                name: name.to_string(),
                valid: valid(),
            });
        };
        Ok(m.clone())
    }

    /// The materials `selection` names, in `channel`: each known and usable (an excluded one
    /// named is an error), in the order given ([`Selection::Names`]) or file order.
    pub fn select(
        &self,
        selection: &Selection,
        channel: Channel,
    ) -> Result<Vec<SuiteMaterial>, SuiteError> {
        let all = self.materials(channel)?;
        let usable = |m: &SuiteMaterial| !matches!(m.inclusion(self), Inclusion::Excluded(_));
        Ok(match selection {
            Selection::All => all.into_iter().filter(usable).collect(),
            Selection::InBounds => all
                .into_iter()
                .filter(|m| m.violations.is_empty())
                .collect(),
            Selection::Names(names) => {
                let mut out = Vec::with_capacity(names.len());
                for n in names {
                    let m = self.material(n, channel)?;
                    if let Inclusion::Excluded(why) = m.inclusion(self) {
                        return Err(SuiteError::Excluded {
                            suite: self.name.into(),
                            material: m.name,
                            why,
                        });
                    }
                    out.push(m);
                }
                out
            }
            Selection::Sample { count, seed } => {
                let pool: Vec<SuiteMaterial> = all.into_iter().filter(usable).collect();
                if !(1..=pool.len()).contains(count) {
                    return Err(SuiteError::MaterialCount {
                        suite: self.name.into(),
                        count: *count,
                        available: pool.len(),
                    });
                }
                let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(*seed);
                let mut idx: Vec<usize> = (0..pool.len()).collect();
                for i in 0..*count {
                    let j = rand::RngExt::random_range(&mut rng, i..idx.len());
                    idx.swap(i, j);
                }
                let mut chosen = idx[..*count].to_vec();
                chosen.sort_unstable();
                chosen.into_iter().map(|i| pool[i].clone()).collect()
            }
        })
    }
}

/// The listing of `docs/suites.md`: per suite, its family, source, material count, the
/// materials outside the family's bounds in `channel` (with why) and whether they are
/// included, then the materials; a test keeps the page current.
pub fn listing_markdown(channel: Channel) -> Result<String, SuiteError> {
    let mut s = String::new();
    let mut lists: Vec<Vec<String>> = Vec::new();
    for suite in suites() {
        let all = suite.materials(channel)?;
        lists.push(all.iter().map(|m| m.name.clone()).collect());
        let _ = writeln!(s, "### `{}`\n", suite.name);
        let _ = writeln!(
            s,
            "Family `{}`, from `{}`, {} materials ({channel} channel). {}.\n",
            suite.family,
            suite.file,
            all.len(),
            capitalise(suite.description)
        );
        let outside: Vec<&SuiteMaterial> =
            all.iter().filter(|m| !m.violations.is_empty()).collect();
        if outside.is_empty() {
            let _ = writeln!(s, "Outside the family's bounds: none.\n");
        } else {
            let _ = writeln!(
                s,
                "Outside the family's bounds: {}.\n\n| material | why | included |\n|---|---|---|",
                outside.len()
            );
            for m in outside {
                let how = match m.inclusion(suite) {
                    Inclusion::Inside => "yes".to_string(),
                    Inclusion::Widened(w) => {
                        let parts: Vec<String> = w
                            .iter()
                            .map(|(n, [lo, hi])| format!("`{n}` widened to [{lo}, {hi}]"))
                            .collect();
                        format!("yes, {}", parts.join(", "))
                    }
                    Inclusion::Excluded(_) => "no (excluded)".to_string(),
                };
                let _ = writeln!(s, "| {} | {} | {how} |", m.name, m.violation_text());
            }
            s.push('\n');
        }
    }
    if lists.windows(2).all(|w| w[0] == w[1]) {
        let _ = writeln!(
            s,
            "### Materials\n\nThe same {} in every suite, in file order: {}.",
            lists[0].len(),
            lists[0].join(", ")
        );
    } else {
        for (suite, names) in suites().iter().zip(&lists) {
            let _ = writeln!(s, "Materials of `{}`: {}.\n", suite.name, names.join(", "));
        }
    }
    Ok(s)
}

fn capitalise(text: &str) -> String {
    let mut c = text.chars();
    match c.next() {
        Some(f) => f.to_uppercase().chain(c).collect(),
        None => String::new(),
    }
}
