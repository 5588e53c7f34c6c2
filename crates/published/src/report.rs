//! Summaries of the published fits: per-parameter min, median and max, values outside the
//! usual ranges, the Lafortune conversion's statistics and a lobe-shape check. They make the
//! generated tables of `docs/published-fits.md` ([`report_markdown`]; the example
//! `published_fits` prints them and a test checks the page is current).

use super::{FitError, FitFile};
use super::{NganLafortune, PublishedFit, read_fits, table1_violations};
use brdf_io::Channel;
use std::fmt::Write as _;
use std::path::Path;

/// The published files, as committed in `experiments/data/published-fits/`.
pub const FIT_FILES: [&str; 14] = [
    "ngan_lafortune.fit",
    "ngan_ward.fit",
    "ngan_wardduer.fit",
    "ngan_blinnphong.fit",
    "ngan_cooktorrance.fit",
    "ngan_ashikhminshirley.fit",
    "ngan_he.fit",
    "low_cooktorrance_E1.fit",
    "low_cooktorrance_E2.fit",
    "low_ashikhminshirley_E1.fit",
    "low_ashikhminshirley_E2.fit",
    "low_lowmicrofacet_E2.fit",
    "low_lowsmooth_E2.fit",
    "bagher_sgd.fit",
];

/// The spread of one parameter over the materials of a file (and over the channels, unless the
/// parameter is shared).
#[derive(Clone, Debug, PartialEq)]
pub struct ParamSummary {
    /// Parameter name; `Lambertian.albedo` for the diffuse term.
    pub name: String,
    /// True when every material gives one number for all channels.
    pub shared: bool,
    /// Values counted (materials, times 3 unless shared).
    pub count: usize,
    /// Smallest value.
    pub min: f64,
    /// Median (the mean of the two middle values for an even count).
    pub median: f64,
    /// Largest value.
    pub max: f64,
    /// Where the smallest value is: `material` or `material (g)`.
    pub min_at: String,
    /// Where the largest value is.
    pub max_at: String,
}

/// One value with where it is from.
struct Value {
    v: f64,
    at: String,
}

const CHANNELS: [&str; 3] = ["r", "g", "b"];

/// Every value of parameter `name` (`Lambertian.albedo` for the diffuse term), with its place.
fn values(fits: &[PublishedFit], name: &str) -> (Vec<Value>, bool) {
    let mut out = Vec::new();
    let mut shared = true;
    for f in fits {
        let (rgb, sh) = if name == "Lambertian.albedo" {
            match f.diffuse {
                Some(d) => (d, false),
                None => continue,
            }
        } else {
            match f.param(name) {
                Some(p) => (p.rgb, p.shared),
                None => continue,
            }
        };
        shared &= sh;
        if sh {
            out.push(Value {
                v: rgb[0],
                at: f.material.clone(),
            });
        } else {
            for (k, v) in rgb.into_iter().enumerate() {
                out.push(Value {
                    v,
                    at: format!("{} ({})", f.material, CHANNELS[k]),
                });
            }
        }
    }
    (out, shared)
}

fn param_names(fits: &[PublishedFit]) -> Vec<String> {
    let mut names = Vec::new();
    if fits.iter().any(|f| f.diffuse.is_some()) {
        names.push("Lambertian.albedo".to_string());
    }
    for f in fits {
        for p in &f.params {
            if !names.contains(&p.name) {
                names.push(p.name.clone());
            }
        }
    }
    names
}

fn median(sorted: &[f64]) -> f64 {
    let n = sorted.len();
    if n % 2 == 1 {
        sorted[n / 2]
    } else {
        0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
    }
}

/// Min, median and max of every parameter over `fits` (the Lambertian albedo first, then the
/// parameters in the order they first appear). Values are pooled over the channels unless the
/// parameter is shared.
pub fn summarise(fits: &[PublishedFit]) -> Vec<ParamSummary> {
    let mut out = Vec::new();
    for name in param_names(fits) {
        let (vals, shared) = values(fits, &name);
        if vals.is_empty() {
            continue;
        }
        let mut sorted: Vec<f64> = vals.iter().map(|v| v.v).collect();
        sorted.sort_by(f64::total_cmp);
        let lo = vals
            .iter()
            .min_by(|a, b| a.v.total_cmp(&b.v))
            .unwrap_or(&vals[0]);
        let hi = vals
            .iter()
            .max_by(|a, b| a.v.total_cmp(&b.v))
            .unwrap_or(&vals[0]);
        out.push(ParamSummary {
            name,
            shared,
            count: vals.len(),
            min: lo.v,
            median: median(&sorted),
            max: hi.v,
            min_at: lo.at.clone(),
            max_at: hi.at.clone(),
        });
    }
    out
}

/// A number to 4 significant digits, in exponent form when very small or large.
fn sig(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 {
        "0".into()
    } else if !(1e-3..1e5).contains(&a) {
        format!("{v:.3e}")
    } else {
        let digits = (3 - a.log10().floor() as i32).max(0) as usize;
        let s = format!("{v:.digits$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    }
}

/// The checks that flag a value as outside the usual range, for parameter `param` of `model`:
/// each a predicate (true = flagged) and its description.
type Rule = (fn(f64) -> bool, &'static str);

fn rules(model: &str, param: &str) -> Vec<Rule> {
    let mut r: Vec<Rule> = Vec::new();
    let unit: Rule = (
        |v| !(0.0..=1.0).contains(&v),
        "outside [0, 1] (bbm's bounds)",
    );
    let ior: Rule = (
        |v| !(1.0..=5.0).contains(&v),
        "IOR outside [1, 5] (bbm's bounds)",
    );
    let f0: Rule = (|v| !(0.0..=1.0).contains(&v), "F0 outside [0, 1]");
    let rough: Rule = (
        |v| v <= 0.0 || v > 1.0,
        "roughness outside (0, 1] (bbm's bounds)",
    );
    let neg: Rule = (|v| v < 0.0, "negative (bbm's lower bound 0)");
    match (model, param) {
        (_, "Lambertian.albedo") | (_, "albedo") => r.push(unit),
        ("NganLafortune", "sharpness") => {
            r.push(neg);
            r.push((|v| v > 10000.0, "n > 10000 (Table 1)"));
        }
        (_, "sharpness") => r.push(neg),
        ("NganWard" | "NganWardDuer", "roughness") => {
            r.push(rough);
            r.push((
                |v| v > 0.2,
                "alpha > 0.2 (Ward's normalisation is accurate below ~0.2)",
            ));
        }
        ("NganCookTorrance" | "LowCookTorrance", "roughness") => r.push(rough),
        ("NganCookTorrance", "eta") | ("NganAshikhminShirley", "fresnelReflectance") => r.push(f0),
        ("LowCookTorrance" | "LowMicrofacetFit" | "LowSmooth" | "NganHe", "eta")
        | ("LowAshikhminShirley", "fresnelReflectance") => r.push(ior),
        ("NganHe", _) => r.push(neg),
        ("Bagher", "alpha") => r.push(rough),
        ("Bagher", "eta.0") => r.push(f0),
        ("Bagher", "eta.1") => r.push((|v| !(-1.0..=1.0).contains(&v), "outside [-1, 1] (bbm)")),
        ("Bagher", "theta0") => {
            r.push(neg);
            r.push((|v| v > std::f64::consts::FRAC_PI_2, "above pi/2"));
        }
        ("Bagher" | "LowMicrofacetFit" | "LowSmooth", _) => r.push(neg),
        _ => {}
    }
    r.push((|v| v.abs() > 1e6, "magnitude above 1e6"));
    r
}

/// The flagged values of one parameter, as `rule: count (place value, ...)`.
fn flag_text(model: &str, fits: &[PublishedFit], name: &str) -> String {
    let (vals, _) = values(fits, name);
    let mut parts = Vec::new();
    for (test, what) in rules(model, name) {
        let hits: Vec<&Value> = vals.iter().filter(|v| test(v.v)).collect();
        if hits.is_empty() {
            continue;
        }
        const SHOWN: usize = 6;
        let mut s = format!("{what}: {}", hits.len());
        let list: Vec<String> = hits
            .iter()
            .take(SHOWN)
            .map(|v| format!("{} {}", v.at, sig(v.v)))
            .collect();
        let _ = write!(s, " ({}", list.join(", "));
        if hits.len() > SHOWN {
            let _ = write!(s, ", {} more", hits.len() - SHOWN);
        }
        s.push(')');
        parts.push(s);
    }
    if parts.is_empty() {
        "-".into()
    } else {
        parts.join("; ")
    }
}

fn file_table(name: &str, file: &FitFile, out: &mut String) {
    let models: Vec<&str> = file.fits.iter().map(|f| f.model.as_str()).collect();
    let model = models.first().copied().unwrap_or("-");
    let _ = writeln!(
        out,
        "#### `{name}`: `{model}`, {} materials\n",
        file.fits.len()
    );
    if models.iter().any(|m| *m != model) {
        let _ = writeln!(out, "(mixed models)\n");
    }
    let _ = writeln!(
        out,
        "| parameter | per | min | median | max | outside the usual range |\n|---|---|---|---|---|---|"
    );
    for s in summarise(&file.fits) {
        let _ = writeln!(
            out,
            "| `{}` | {} | {} ({}) | {} | {} ({}) | {} |",
            s.name,
            if s.shared { "material" } else { "channel" },
            sig(s.min),
            s.min_at,
            sig(s.median),
            sig(s.max),
            s.max_at,
            flag_text(model, &file.fits, &s.name)
        );
    }
    out.push('\n');
}

fn lafortune_summary(file: &FitFile, out: &mut String) {
    let mut ns: Vec<f64> = Vec::new();
    let mut outside: Vec<String> = Vec::new();
    let mut outside_any: Vec<String> = Vec::new();
    let mut grazing: Vec<String> = Vec::new();
    let mut failed: Vec<String> = Vec::new();
    for f in &file.fits {
        let l = match NganLafortune::from_fit(f) {
            Ok(l) => l,
            Err(e) => {
                failed.push(e.to_string());
                continue;
            }
        };
        ns.push(l.n[1]);
        if l.cz[1].abs() < 0.01 {
            grazing.push(format!("{} (Cz = {})", f.material, sig(l.cz[1])));
        }
        let v = table1_violations(&l.to_params_default());
        if !v.is_empty() {
            let why: Vec<String> = v.iter().map(|b| b.to_string()).collect();
            outside.push(format!("{} ({})", f.material, why.join(", ")));
        }
        let mut bad = Vec::new();
        for (c, ch) in [Channel::Red, Channel::Green, Channel::Blue]
            .into_iter()
            .zip(CHANNELS)
        {
            for b in table1_violations(&l.to_params(c)) {
                if !b.name.ends_with(".n") {
                    bad.push(format!("{ch}: {b}"));
                }
            }
        }
        if !bad.is_empty() {
            outside_any.push(format!("{} ({})", f.material, bad.join(", ")));
        }
    }
    ns.sort_by(f64::total_cmp);
    let count = ns.len();
    let _ = writeln!(out, "#### Lafortune conversion (green channel)\n");
    if count == 0 {
        let _ = writeln!(out, "No convertible fit.\n");
        return;
    }
    let _ = writeln!(
        out,
        "- {count} materials converted ({} failed{}); n from {} to {}, median {}; {} above 1,000.",
        failed.len(),
        if failed.is_empty() {
            String::new()
        } else {
            format!(": {}", failed.join("; "))
        },
        sig(ns[0]),
        sig(ns[count - 1]),
        sig(median(&ns)),
        ns.iter().filter(|&&n| n > 1000.0).count()
    );
    let _ = writeln!(
        out,
        "- Inside the Table 1 box: {} of {count}. Outside: {}.",
        count - outside.len(),
        if outside.is_empty() {
            "none".to_string()
        } else {
            outside.join("; ")
        }
    );
    let _ = writeln!(
        out,
        "- Other than n, outside the box in some channel: {}.",
        if outside_any.is_empty() {
            "none".to_string()
        } else {
            outside_any.join("; ")
        }
    );
    let _ = writeln!(
        out,
        "- Grazing lobes (|Cz| < 0.01): {}.\n",
        if grazing.is_empty() {
            "none".to_string()
        } else {
            grazing.join(", ")
        }
    );
}

/// The value at normal incidence (`u = v = z`) of Ngan's fit of one material in the green
/// channel, as bbm evaluates the model (see `docs/published-fits.md`), or `None` for a model
/// this check does not cover. Lafortune is left out: its lobe is `(Cz / m)^n` below its
/// maximum there (the maximum is reached towards grazing when `|Cxy| > Cz`).
fn peak_at_normal(f: &PublishedFit) -> Option<f64> {
    let g = |name: &str| f.value(name, Channel::Green);
    let pi = std::f64::consts::PI;
    let rho = g("albedo")?;
    Some(match f.model.as_str() {
        "NganWard" | "NganWardDuer" => rho / (4.0 * pi * g("roughness")?.powi(2)),
        "NganBlinnPhong" => rho * (g("sharpness")? + 2.0) / (2.0 * pi),
        "NganAshikhminShirley" => {
            rho * (g("sharpness")? + 1.0) / (8.0 * pi) * g("fresnelReflectance")?
        }
        "NganCookTorrance" => rho * g("eta")? / (pi * pi * g("roughness")?.powi(2)),
        _ => return None,
    })
}

/// Median and quartiles of a list, as table cells.
fn quartile_cells(mut r: Vec<f64>) -> String {
    r.sort_by(f64::total_cmp);
    let q = |p: f64| r[((r.len() - 1) as f64 * p).round() as usize];
    format!(
        "{} | {} | {} to {}",
        r.len(),
        sig(median(&r)),
        sig(q(0.25)),
        sig(q(0.75))
    )
}

/// Two checks of the conventions against Ngan's Ward fits of the same materials (green):
/// `n alpha^2` for each exponent (about 2 for a half-vector lobe `(n.h)^n`, about 0.5 for a
/// mirror lobe `(r.v)^n`, both against Ward's `exp(-tan^2(theta_h) / alpha^2)`), and the ratio
/// of each model's value at normal incidence to Ward's (about 1 when the documented
/// normalisation is the one the fit used).
fn lobe_shape_check(files: &[(&str, FitFile)], out: &mut String) {
    let Some((_, ward)) = files.iter().find(|(n, _)| *n == "ngan_ward.fit") else {
        return;
    };
    let _ = writeln!(
        out,
        "#### Consistency with Ngan's Ward fits (green channel)\n\n\
         `n alpha^2`: about 2 for a half-vector lobe `(n.h)^n`, about 0.5 for a mirror lobe \
         `(r.v)^n`.\n\n\
         | file | materials | median | quartiles |\n|---|---|---|---|"
    );
    for name in [
        "ngan_blinnphong.fit",
        "ngan_ashikhminshirley.fit",
        "ngan_lafortune.fit",
    ] {
        let Some((_, file)) = files.iter().find(|(n, _)| *n == name) else {
            continue;
        };
        let r: Vec<f64> = file
            .fits
            .iter()
            .filter_map(|f| {
                let n = f.value("sharpness", Channel::Green)?;
                let a = ward.get(&f.material)?.value("roughness", Channel::Green)?;
                Some(n * a * a)
            })
            .collect();
        if !r.is_empty() {
            let _ = writeln!(out, "| `{name}` | {} |", quartile_cells(r));
        }
    }
    let _ = writeln!(
        out,
        "\nThe value at normal incidence (`u = v = z`) over Ward's, each model evaluated as \
         documented above (Lafortune left out: at normal incidence its lobe is `(Cz / m)^n` \
         below its maximum).\n\n| file | materials | median | quartiles |\n|---|---|---|---|"
    );
    for (name, file) in files.iter().filter(|(n, _)| n.starts_with("ngan_")) {
        let r: Vec<f64> = file
            .fits
            .iter()
            .filter_map(|f| {
                let w = peak_at_normal(ward.get(&f.material)?)?;
                let p = peak_at_normal(f)?;
                (w > 0.0).then_some(p / w)
            })
            .collect();
        if !r.is_empty() && *name != "ngan_ward.fit" {
            let _ = writeln!(out, "| `{name}` | {} |", quartile_cells(r));
        }
    }
    out.push('\n');
}

/// The generated part of `docs/published-fits.md`: for each file of [`FIT_FILES`] in `dir`, a
/// table of every parameter's min, median and max ([`summarise`]) with the values outside the
/// usual ranges, then the Lafortune conversion's statistics and the lobe-shape check.
pub fn report_markdown(dir: &Path) -> Result<String, FitError> {
    let mut files = Vec::new();
    for name in FIT_FILES {
        files.push((name, read_fits(dir.join(name))?));
    }
    let mut out = String::new();
    for (name, file) in &files {
        file_table(name, file, &mut out);
    }
    if let Some((_, laf)) = files.iter().find(|(n, _)| *n == "ngan_lafortune.fit") {
        lafortune_summary(laf, &mut out);
    }
    lobe_shape_check(&files, &mut out);
    Ok(out.trim_end().to_string() + "\n")
}
