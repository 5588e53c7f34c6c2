//! The one reader of a BRDF parameter set as people give it, shared by the command line
//! (`--params`), experiment specs (`synthetic.params`) and the Python package (`params=`):
//!
//! - a paper name (`tuning`, `cross`, ...; [`brdf_model::NAMED_PARAMS`]), as text or a TOML
//!   string;
//! - JSON text as printed on the `json:` line of `brdf-sls fit`;
//! - `@FILE`: a file holding such JSON;
//! - a TOML table `{ kd = 0.15, lobes = [{ cx = -1, cy = 0.8, cz = 0.96, n = 20, pan_deg = 45 }] }`.
//!
//! The JSON and TOML forms name their model family with a `family` key (`"ggx"`, ...; left out
//! for Lafortune, the default, and for the paper names, which are Lafortune's): see
//! [`brdf_model::Params`]. Every result is checked against its family's box
//! ([`Params::validate`]). Errors start
//! with the origin the caller names (`--params`, "instance `t`: `synthetic.params`", ...), so
//! they say where the text came from.

use std::io::Read;

use brdf_model::Params;

/// Largest parameter file read (`@FILE`): a parameter set is a few hundred bytes.
pub const MAX_PARAMS_FILE_BYTES: u64 = 1 << 20;

/// A JSON example shown when text is neither a name nor JSON parameters.
const JSON_EXAMPLE: &str =
    r#"{"kd":0.15,"lobes":[{"cx":-1,"cy":0.8,"cz":0.96,"n":20,"pan_deg":45}]}"#;

/// The shape a TOML table must have, shown when it does not.
const TABLE_SHAPE: &str =
    "{ kd, lobes = [{ cx, cy, cz, n, pan_deg }] } or { family = \"ggx\", kd, lobes = [...] }";

/// Parameters as given, before reading.
#[derive(Clone, Copy, Debug)]
pub enum ParamsInput<'a> {
    /// Text: a name, JSON, or `@FILE` (command-line flags, Python strings).
    Text(&'a str),
    /// A TOML value: a name (string) or a table (experiment specs).
    Toml(&'a toml::Value),
}

/// A parameter set read from its input.
#[derive(Clone, Debug, PartialEq)]
pub struct GivenParams {
    /// The paper name, when given by name.
    pub name: Option<String>,
    /// The parameters, inside their family's box.
    pub params: Params,
}

/// Why parameters could not be read: `origin` (where they came from) and what is wrong.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{origin}: {message}")]
pub struct ParamsError {
    /// Where the parameters came from, as the caller named it.
    pub origin: String,
    /// What is wrong.
    pub message: String,
}

/// Reads a parameter set (see the module docs); `origin` starts every error.
pub fn parse_params(origin: &str, input: ParamsInput<'_>) -> Result<GivenParams, ParamsError> {
    parse_params_within(origin, input, &Default::default())
}

/// [`parse_params`], checking the values against the family's box with some bounds widened:
/// `bounds` maps parameter names (`lobe1.n`) to the bounds to use instead (a spec's
/// `model.bounds`). A value beyond its family's box is refused unless such a bound admits it,
/// and the error then says how to widen it.
pub fn parse_params_within(
    origin: &str,
    input: ParamsInput<'_>,
    bounds: &std::collections::BTreeMap<String, [f64; 2]>,
) -> Result<GivenParams, ParamsError> {
    let fail = |message: String| ParamsError {
        origin: origin.to_string(),
        message,
    };
    let (given, shown) = match input {
        ParamsInput::Text(s) => (
            from_text(s.trim()).map_err(fail)?,
            format!("`{}`: ", s.trim()),
        ),
        ParamsInput::Toml(v) => (from_toml(v).map_err(fail)?, String::new()),
    };
    given
        .params
        .validate_within(|name| bounds.get(name).map(|b| (b[0], b[1])))
        .map_err(|e| {
            let hint = match &e {
                // Only an exponent's box may be widened (brdf_model::MAX_EXPONENT).
                brdf_model::ParamError::OutOfRange {
                    name, value, hi, ..
                } if name.ends_with(".n")
                    && *value > *hi
                    && *value <= brdf_model::MAX_EXPONENT
                    && !bounds.contains_key(name) =>
                {
                    " (a spec's `model.bounds` or `fit --bounds` widens an exponent's bounds)"
                }
                _ => "",
            };
            fail(format!("{shown}{e}{hint}"))
        })?;
    Ok(given)
}

/// A name, `@FILE` or JSON text.
fn from_text(s: &str) -> Result<GivenParams, String> {
    if let Some(p) = brdf_model::named_params(s) {
        return Ok(GivenParams {
            name: Some(s.to_string()),
            params: p.into(),
        });
    }
    let params = if let Some(file) = s.strip_prefix('@') {
        let text = read_small_file(file)?;
        serde_json::from_str::<Params>(text.trim()).map_err(|e| {
            format!("{file}: not JSON parameters as printed by `brdf-sls fit` ({e})")
        })?
    } else {
        serde_json::from_str::<Params>(s).map_err(|e| {
            format!(
                "`{s}`: not a known name ({}) nor JSON parameters such as {JSON_EXAMPLE} ({e})",
                brdf_model::NAMED_PARAMS.join(", ")
            )
        })?
    };
    Ok(GivenParams { name: None, params })
}

/// A TOML string (a name) or table.
fn from_toml(v: &toml::Value) -> Result<GivenParams, String> {
    match v {
        toml::Value::String(n) => match brdf_model::named_params(n) {
            Some(params) => Ok(GivenParams {
                name: Some(n.clone()),
                params: params.into(),
            }),
            None => Err(format!(
                "unknown name `{n}` (expected one of {})",
                brdf_model::NAMED_PARAMS.join(", ")
            )),
        },
        toml::Value::Table(_) => {
            let params: Params = v.clone().try_into().map_err(|e: toml::de::Error| {
                format!("{} (expected {TABLE_SHAPE})", e.message())
            })?;
            Ok(GivenParams { name: None, params })
        }
        other => Err(format!(
            "expected a name or a table, found {}",
            other.type_str()
        )),
    }
}

/// Reads a parameter file, refusing anything larger than a parameter set could be.
fn read_small_file(file: &str) -> Result<String, String> {
    let f = std::fs::File::open(file).map_err(|e| format!("{file}: {e}"))?;
    let mut text = String::new();
    f.take(MAX_PARAMS_FILE_BYTES + 1)
        .read_to_string(&mut text)
        .map_err(|e| format!("{file}: {e}"))?;
    if text.len() as u64 > MAX_PARAMS_FILE_BYTES {
        return Err(format!(
            "{file}: larger than {MAX_PARAMS_FILE_BYTES} bytes; not a parameter file"
        ));
    }
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text(s: &str) -> Result<GivenParams, String> {
        parse_params("--params", ParamsInput::Text(s)).map_err(|e| e.to_string())
    }

    fn table(s: &str) -> Result<GivenParams, String> {
        let v: toml::Table = toml::from_str(&format!("params = {s}")).unwrap();
        parse_params(
            "instance `t`: `synthetic.params`",
            ParamsInput::Toml(&v["params"]),
        )
        .map_err(|e| e.to_string())
    }

    const TUNING_JSON: &str =
        r#"{"kd":0.15,"lobes":[{"cx":-1,"cy":0.8,"cz":0.96,"n":20,"pan_deg":45}]}"#;

    #[test]
    fn every_form_reads_the_same_parameters() {
        let named = Params::from(brdf_model::named_params("tuning").unwrap());
        let by_name = text(" tuning ").unwrap();
        assert_eq!(by_name.name.as_deref(), Some("tuning"));
        assert_eq!(by_name.params, named);
        assert_eq!(table("\"tuning\"").unwrap().params, named);
        let json = text(TUNING_JSON).unwrap();
        assert_eq!(json.name, None);
        assert_eq!(json.params, named);
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("p.json");
        std::fs::write(&file, format!("{TUNING_JSON}\n")).unwrap();
        assert_eq!(text(&format!("@{}", file.display())).unwrap().params, named);
        let toml = table(
            "{ kd = 0.15, lobes = [{ cx = -1, cy = 0.8, cz = 0.96, n = 20, pan_deg = 45 }] }",
        );
        assert_eq!(toml.unwrap().params, named);
    }

    #[test]
    fn errors_name_the_origin_and_what_was_expected() {
        let e = text("tunning").unwrap_err();
        assert!(
            e.starts_with("--params: `tunning`: not a known name (tuning, cross,")
                && e.contains("nor JSON parameters such as {\"kd\""),
            "{e}"
        );
        let e = text("@/no/such/file.json").unwrap_err();
        assert!(e.starts_with("--params: /no/such/file.json: "), "{e}");
        let dir = tempfile::tempdir().unwrap();
        let bad = dir.path().join("bad.json");
        std::fs::write(&bad, "kd = 1").unwrap();
        let e = text(&format!("@{}", bad.display())).unwrap_err();
        assert!(
            e.contains("not JSON parameters as printed by `brdf-sls fit`"),
            "{e}"
        );
        let e = text(r#"{"kd":2,"lobes":[]}"#).unwrap_err();
        assert!(
            e.starts_with("--params: `{\"kd\":2,\"lobes\":[]}`: kd = 2"),
            "{e}"
        );
        let spec = "instance `t`: `synthetic.params`: ";
        let e = table("\"tunning\"").unwrap_err();
        assert_eq!(
            e,
            format!(
                "{spec}unknown name `tunning` (expected one of {})",
                brdf_model::NAMED_PARAMS.join(", ")
            )
        );
        let e = table("{ kd = 0.1 }").unwrap_err();
        assert!(
            e.starts_with(spec)
                && e.contains("lobes")
                && e.ends_with(&format!("(expected {TABLE_SHAPE})")),
            "{e}"
        );
        let e = table("{ kd = 0.1, lobes = [{ cx = 1, cy = 0.8, cz = 5, n = 20, pan_deg = 45 }] }")
            .unwrap_err();
        assert!(e.starts_with(spec) && e.contains("cz"), "{e}");
        assert_eq!(
            table("3").unwrap_err(),
            format!("{spec}expected a name or a table, found integer")
        );
    }

    #[test]
    fn oversized_files_are_refused_unread() {
        let dir = tempfile::tempdir().unwrap();
        let big = dir.path().join("big.json");
        std::fs::write(&big, vec![b' '; MAX_PARAMS_FILE_BYTES as usize + 1]).unwrap();
        let e = text(&format!("@{}", big.display())).unwrap_err();
        assert!(e.contains("not a parameter file"), "{e}");
    }
}
