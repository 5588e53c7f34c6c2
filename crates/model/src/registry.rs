//! The families known by name (the built-in ones and those a program registers), and what
//! needs them: the default family, and reading parameter sets, whose JSON names their family.

use crate::family::{DEFAULT_FAMILY, Family, FamilyRef, FieldDef};
use crate::lobes::LobeFamily;
use crate::models::ashikhmin_shirley::AshikhminShirley;
use crate::models::blinn_phong::BlinnPhong;
use crate::models::cook_torrance::CookTorrance;
use crate::models::ggx::Ggx;
use crate::models::ward;
use crate::params::Params;
use serde::de::Error as _;
use serde::{Deserialize, Deserializer};
use std::collections::BTreeMap;
use std::sync::{Arc, OnceLock, RwLock};

/// A family name that is not known, or a registration that cannot be made.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum FamilyError {
    /// No family has this name.
    #[error("unknown model family `{name}`: expected one of {known}")]
    Unknown {
        /// The name given.
        name: String,
        /// The known names, comma-separated.
        known: String,
    },
    /// A family of this name is already registered.
    #[error("a model family named `{0}` is already registered")]
    Duplicate(String),
    /// The name is not a lowercase identifier (`a-z`, `0-9`, `-`, `_`, starting with a letter).
    #[error(
        "model family name `{0}`: expected lowercase letters, digits, `-` or `_`, starting with a letter"
    )]
    BadName(String),
}

fn builtins() -> &'static [FamilyRef] {
    static B: OnceLock<Vec<FamilyRef>> = OnceLock::new();
    B.get_or_init(|| {
        vec![
            FamilyRef(crate::lafortune::family()),
            FamilyRef(Arc::new(LobeFamily::<Ggx>::new())),
            FamilyRef(Arc::new(LobeFamily::<CookTorrance>::new())),
            FamilyRef(Arc::new(LobeFamily::<BlinnPhong>::new())),
            FamilyRef(Arc::new(LobeFamily::<ward::Ward>::new())),
            FamilyRef(Arc::new(LobeFamily::<ward::WardGmd>::new())),
            FamilyRef(Arc::new(LobeFamily::<AshikhminShirley>::new())),
        ]
    })
}

fn registered() -> &'static RwLock<Vec<FamilyRef>> {
    static R: RwLock<Vec<FamilyRef>> = RwLock::new(Vec::new());
    &R
}

impl FamilyRef {
    /// The Lafortune family (the default).
    pub fn lafortune() -> Self {
        FamilyRef(crate::lafortune::family())
    }
}

fn all() -> Vec<FamilyRef> {
    let mut out = builtins().to_vec();
    // A poisoned lock only means a registration panicked; the list itself is intact.
    let extra = registered().read().unwrap_or_else(|e| e.into_inner());
    out.extend(extra.iter().cloned());
    out
}

/// The family called `name` (case-insensitive, surrounding spaces ignored).
///
/// # Errors
/// [`FamilyError::Unknown`], listing the known names.
pub fn family(name: &str) -> Result<FamilyRef, FamilyError> {
    let key = name.trim().to_ascii_lowercase();
    let all = all();
    all.iter()
        .find(|f| f.name() == key)
        .cloned()
        .ok_or_else(|| FamilyError::Unknown {
            name: name.to_string(),
            known: all.iter().map(|f| f.name()).collect::<Vec<_>>().join(", "),
        })
}

/// The names of every known family: the built-in ones first, then the registered ones in
/// registration order.
pub fn family_names() -> Vec<&'static str> {
    all().iter().map(|f| f.name()).collect()
}

/// Makes `f` known by its name to [`family`] (and so to specs and commands).
///
/// # Errors
/// [`FamilyError::Duplicate`] when the name is taken, [`FamilyError::BadName`] when it is not
/// a lowercase identifier.
pub fn register_family(f: Arc<dyn Family>) -> Result<(), FamilyError> {
    let name = f.name();
    let ok = name.starts_with(|c: char| c.is_ascii_lowercase())
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-' || c == '_');
    if !ok {
        return Err(FamilyError::BadName(name.to_string()));
    }
    let mut list = registered().write().unwrap_or_else(|e| e.into_inner());
    if builtins()
        .iter()
        .chain(list.iter())
        .any(|g| g.name() == name)
    {
        return Err(FamilyError::Duplicate(name.to_string()));
    }
    list.push(FamilyRef(f));
    Ok(())
}

/// The JSON form of [`Params`] as read: the family, the shared keys, and the lobes' key-value
/// maps.
#[derive(Deserialize)]
struct RawParams {
    #[serde(default)]
    family: Option<String>,
    lobes: Vec<BTreeMap<String, f64>>,
    #[serde(flatten)]
    shared: BTreeMap<String, f64>,
}

fn keys_list(fields: &[FieldDef]) -> String {
    let keys: Vec<String> = fields.iter().map(|d| format!("`{}`", d.key)).collect();
    keys.join(", ")
}

/// Values of `fields` taken from `map` by key (missing optional ones at their defaults),
/// refusing unknown and missing keys; `others` are the other keys of the object, for the
/// message.
fn take_fields(
    fields: &[FieldDef],
    mut map: BTreeMap<String, f64>,
    others: &str,
) -> Result<Vec<f64>, String> {
    let mut out = Vec::with_capacity(fields.len());
    for d in fields {
        match map.remove(d.key) {
            Some(v) => out.push(v),
            None if d.optional => out.push(d.default),
            None => return Err(format!("missing field `{}`", d.key)),
        }
    }
    if let Some(k) = map.keys().next() {
        return Err(format!(
            "unknown field `{k}`, expected one of {others}{}",
            keys_list(fields)
        ));
    }
    Ok(out)
}

/// Reads the JSON (or TOML) form documented on [`Params`]; the family is looked up by name
/// (Lafortune when `"family"` is left out).
impl<'de> Deserialize<'de> for Params {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let raw = RawParams::deserialize(d)?;
        let name = raw.family.as_deref().unwrap_or(DEFAULT_FAMILY);
        let fam = family(name).map_err(D::Error::custom)?;
        let shared = take_fields(fam.shared_fields(), raw.shared, "`family`, `lobes`, ")
            .map_err(D::Error::custom)?;
        let lobes = raw
            .lobes
            .into_iter()
            .map(|l| take_fields(fam.lobe_fields(), l, ""))
            .collect::<Result<Vec<_>, _>>()
            .map_err(D::Error::custom)?;
        Params::new(fam, shared, lobes).map_err(D::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lookups_and_errors_name_the_families() {
        assert_eq!(family(" Lafortune ").unwrap().name(), "lafortune");
        let e = family("phong3").unwrap_err();
        assert!(e.to_string().contains("lafortune"), "{e}");
        assert!(family_names().contains(&"lafortune"));
        let dup = register_family(crate::lafortune::family()).unwrap_err();
        assert_eq!(dup, FamilyError::Duplicate("lafortune".into()));
    }
}
