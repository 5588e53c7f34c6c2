//! Parsers of flag values, shared by every command: one for `NAME=VALUE` assignments, one for
//! parameter sets (`tuning`, JSON or `@FILE`; the library's reader), one for lobes, and one for the library's enums
//! (by their serde names, so no enum is mirrored here), and [`choice`] for the library's
//! named choices.

use std::str::FromStr;

use brdf_model::{FamilyRef, Params};
use clap::builder::{PossibleValuesParser, TypedValueParser};
use serde::de::DeserializeOwned;

/// A library enum by its serde name (`anisotropic`, `log1p`, `green`, ...).
pub fn enum_value<T: DeserializeOwned>(s: &str) -> Result<T, String> {
    use serde::de::IntoDeserializer;
    let de: serde::de::value::StrDeserializer<'_, serde::de::value::Error> =
        s.trim().into_deserializer();
    T::deserialize(de).map_err(|e| e.to_string())
}

/// A library enum chosen by name from `names` (listed in the help and in the error of any
/// other value), parsed with its `FromStr`: the clap glue of [`brdf_experiment::choice`].
pub fn choice<T>(names: &'static [&'static str]) -> impl TypedValueParser<Value = T>
where
    T: FromStr + Clone + Send + Sync + 'static,
    T::Err: std::error::Error + Send + Sync + 'static,
{
    PossibleValuesParser::new(names).try_map(|s| s.parse::<T>())
}

/// Splits `NAME=VALUE` at the first `=`; both sides trimmed, the name non-empty.
pub fn assignment(s: &str) -> Result<(String, String), String> {
    match s.split_once('=') {
        Some((k, v)) if !k.trim().is_empty() => Ok((k.trim().to_string(), v.trim().to_string())),
        _ => Err(format!("`{s}`: expected NAME=VALUE")),
    }
}

/// A finite number.
pub fn finite(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(v) => Err(format!("`{s}`: expected a finite number, found {v}")),
        Err(_) => Err(format!("`{s}`: expected a number")),
    }
}

/// `NAME=NUMBER`, e.g. `lobe1.pan=45` (for `--fix`).
pub fn named_number(s: &str) -> Result<(String, f64), String> {
    let (k, v) = assignment(s)?;
    Ok((k, finite(&v)?))
}

/// `NAME=LO,HI`, e.g. `lobe1.n=0,20000` (for `--bounds`): two finite numbers, `LO <= HI`.
pub fn named_bounds(s: &str) -> Result<(String, [f64; 2]), String> {
    let (k, v) = assignment(s)?;
    let parts: Vec<&str> = v.split(',').collect();
    let [lo, hi] = parts[..] else {
        return Err(format!("`{s}`: expected NAME=LO,HI (two numbers)"));
    };
    let (lo, hi) = (finite(lo)?, finite(hi)?);
    if lo > hi {
        return Err(format!(
            "`{s}`: the lower bound {lo} is above the upper {hi}"
        ));
    }
    Ok((k, [lo, hi]))
}

/// `NAME=VALUE` with a TOML value (`phi=1.2`, `on_failure=restart`; a bare word is a string),
/// for `--set`.
pub fn named_toml(s: &str) -> Result<(String, toml::Value), String> {
    let (k, v) = assignment(s)?;
    let doc: toml::Table = toml::from_str(&format!("v = {v}"))
        .or_else(|_| toml::from_str(&format!("v = {}", toml::Value::String(v.clone()))))
        .map_err(|_| format!("`{s}`: `{v}` is not a TOML value"))?;
    let value = doc
        .get("v")
        .cloned()
        .ok_or_else(|| format!("`{s}`: no value"))?;
    if let toml::Value::Float(f) = value
        && !f.is_finite()
    {
        return Err(format!("`{s}`: expected a finite number, found {f}"));
    }
    Ok((k, value))
}

/// A parameter set: a paper name (`tuning`, `cross`, ...), JSON as printed on the `json:` line
/// of `brdf-sls fit` (of any family: `"family"` names it), or `@FILE` holding such JSON, read
/// by [`brdf_experiment::params`] (checked against its family's box).
pub fn params(s: &str) -> Result<Params, String> {
    brdf_experiment::params::parse_params("--params", brdf_experiment::params::ParamsInput::Text(s))
        .map(|g| g.params)
        .map_err(|e| e.to_string())
}

/// A model family by name (`lafortune`, `ggx`, ...; the error lists them).
pub fn family(s: &str) -> Result<FamilyRef, String> {
    brdf_model::family(s).map_err(|e| e.to_string())
}

/// One lobe of `family` as `--lobe` gives it: the lobe's fields in the family's order
/// (Lafortune: `CX,CY,CZ,N[,PAN]`; trailing optional fields may be left out), or
/// `NAME=VALUE` pairs (`ks=0.5,ax=0.1,ay=0.2`; optional fields left out take their default).
pub fn lobe_of(family: &FamilyRef, s: &str) -> Result<Vec<f64>, String> {
    let fields = family.lobe_fields();
    let names = || fields.iter().map(|f| f.name).collect::<Vec<_>>().join(",");
    let mut out: Vec<Option<f64>> = vec![None; fields.len()];
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.iter().any(|p| p.contains('=')) {
        for part in parts {
            let (k, v) = assignment(part).map_err(|e| format!("`{s}`: {e}"))?;
            let i = fields.iter().position(|f| f.name == k).ok_or_else(|| {
                format!(
                    "`{s}`: `{k}` is not a lobe field of {} ({})",
                    family.name(),
                    names()
                )
            })?;
            if out[i].replace(finite(&v)?).is_some() {
                return Err(format!("`{s}`: `{k}` given twice"));
            }
        }
    } else {
        if parts.len() > fields.len() {
            return Err(format!(
                "`{s}`: {} numbers; a {} lobe has {} fields ({})",
                parts.len(),
                family.name(),
                fields.len(),
                names()
            ));
        }
        for (o, p) in out.iter_mut().zip(&parts) {
            *o = Some(finite(p)?);
        }
    }
    fields
        .iter()
        .zip(out)
        .map(|(f, v)| match v {
            Some(v) => Ok(v),
            None if f.optional => Ok(f.default),
            None => Err(format!(
                "`{s}`: no value for `{}`; a {} lobe is {} (NAME=VALUE pairs or numbers in this order)",
                f.name,
                family.name(),
                names()
            )),
        })
        .collect()
}

/// Three comma-separated numbers (a point or a colour) as a command-line value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triple(pub [f64; 3]);

impl std::str::FromStr for Triple {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let parts: Vec<&str> = s.split(',').collect();
        if parts.len() != 3 {
            return Err(format!(
                "expected three comma-separated numbers X,Y,Z, got `{s}`"
            ));
        }
        let mut v = [0.0; 3];
        for (slot, p) in v.iter_mut().zip(&parts) {
            *slot = finite(p)?;
        }
        Ok(Triple(v))
    }
}

impl std::fmt::Display for Triple {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{},{},{}", self.0[0], self.0[1], self.0[2])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn assignments_and_numbers() {
        assert_eq!(
            named_number("lobe1.pan = 45").unwrap(),
            ("lobe1.pan".into(), 45.0)
        );
        assert!(named_number("lobe1.pan").is_err());
        assert!(named_number("=3").is_err());
        assert!(named_number("kd=nan").unwrap_err().contains("finite"));
        assert_eq!(
            named_toml("on_failure=restart").unwrap().1,
            toml::Value::String("restart".into())
        );
        assert_eq!(named_toml("phi=1.5").unwrap().1, toml::Value::Float(1.5));
        assert!(named_toml("phi=inf").is_err());
    }

    #[test]
    fn params_lobes_and_enums() {
        assert!(params("tuning").is_ok());
        assert!(params("{\"kd\":0.1,\"lobes\":[]}").is_ok());
        assert!(
            params("{\"kd\":2,\"lobes\":[]}").is_err(),
            "kd outside the box"
        );
        assert!(params("tunning").unwrap_err().contains("tuning"));
        let laf = FamilyRef::lafortune();
        assert_eq!(lobe_of(&laf, "-1,0.8,0.96,20,45").unwrap()[4], 45.0);
        assert_eq!(lobe_of(&laf, "-1,0.8,0.96,20").unwrap()[4], 0.0);
        assert_eq!(
            lobe_of(&laf, "cz=0.96,cx=-1,cy=0.8,n=20").unwrap(),
            vec![-1.0, 0.8, 0.96, 20.0, 0.0]
        );
        assert!(
            lobe_of(&laf, "1,2,3")
                .unwrap_err()
                .contains("no value for `n`")
        );
        assert!(lobe_of(&laf, "1,2,3,nan").is_err());
        assert!(
            lobe_of(&laf, "cx=1,q=2")
                .unwrap_err()
                .contains("not a lobe field")
        );
        let ggx = family("ggx").unwrap();
        assert_eq!(
            lobe_of(&ggx, "ks=0.5,ax=0.1,ay=0.2").unwrap(),
            vec![0.5, 0.1, 0.2, 1.0, 0.0]
        );
        assert_eq!(
            enum_value::<brdf_model::LobeKind>("isotropic").unwrap(),
            brdf_model::LobeKind::Isotropic
        );
        assert!(enum_value::<brdf_model::LobeKind>("round").is_err());
        assert!("1,2".parse::<Triple>().is_err());
        let cmd =
            clap::Command::new("t").arg(clap::Arg::new("p").long("p").value_parser(choice::<
                brdf_experiment::progress::ProgressMode,
            >(
                brdf_experiment::progress::ProgressMode::NAMES,
            )));
        let m = cmd
            .clone()
            .try_get_matches_from(["t", "--p", "plain"])
            .unwrap();
        assert_eq!(
            m.get_one::<brdf_experiment::progress::ProgressMode>("p"),
            Some(&brdf_experiment::progress::ProgressMode::Plain)
        );
        let e = cmd.try_get_matches_from(["t", "--p", "loud"]).unwrap_err();
        assert!(
            e.to_string()
                .contains("[possible values: auto, bars, plain, quiet]"),
            "{e}"
        );
        assert_eq!("1,2,3".parse::<Triple>().unwrap(), Triple([1.0, 2.0, 3.0]));
    }
}
