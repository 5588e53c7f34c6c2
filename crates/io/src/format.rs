//! [`Format`]: every data format with its own options as one tagged enum, picked by name, by
//! extension or from a spec (serde), and validated in one place ([`Format::validate`]);
//! [`read`] and [`parse`], the one entry point of every reader.

use super::alta::{AltaOutput, alta_from};
use super::cornell::cornell_from;
use super::csv::csv_from;
use super::limits::check_text_len;
use super::lines::LineSource;
use super::merl::{Channel, MerlBrdf};
use super::{DataError, FormatError, open};
use brdf_model::{DataSet, FilterReport, Filters};
use serde::de::{self, Deserializer, MapAccess, Visitor};
use serde::{Deserialize, Serialize};
use std::io::BufRead;
use std::path::Path;

/// The MERL channel used when none is given (also for ALTA `RGB_COLOR` files): green.
pub const DEFAULT_CHANNEL: Channel = Channel::Green;

/// The format names, as [`Format::from_name`] and specs spell them.
pub const FORMAT_NAMES: [&str; 4] = ["cornell", "csv", "merl", "alta"];

/// The file extensions [`Format::from_path`] knows (lower case, compared in any case) and the
/// format each picks. `.dat` is what ALTA's shipped measurements use, `.alta` its test files.
pub const EXTENSIONS: [(&str, &str); 6] = [
    ("brdf", "cornell"),
    ("csv", "csv"),
    ("binary", "merl"),
    ("merl", "merl"),
    ("alta", "alta"),
    ("dat", "alta"),
];

/// A data format and its reader options. Each variant carries its own options; the defaults
/// are those of [`Format::from_name`] and [`Format::from_path`].
///
/// In a spec (serde) a format is either its name alone (`format = "cornell"`: the defaults)
/// or a table tagged by `kind` (`format = { kind = "cornell", wavelength_nm = 600 }`;
/// unknown keys are refused). Deserialising validates ([`Format::validate`]), so a bad option
/// is refused with the same message wherever it comes from. Serialisation always writes the
/// table.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Format {
    /// Cornell `.brdf` text.
    Cornell {
        /// The wavelength to read, in nm (default [`crate::DEFAULT_WAVELENGTH_NM`], 550); must
        /// be finite and positive, and the file must list it (within 1e-6 nm).
        wavelength_nm: f64,
    },
    /// CSV text with vector or angle columns (no options).
    Csv,
    /// MERL binary table, sampled on its own grid.
    Merl {
        /// The colour channel (default [`DEFAULT_CHANNEL`], green).
        channel: Channel,
    },
    /// ALTA text (`#DIM`, `#PARAM_IN`, `#PARAM_OUT` header).
    Alta {
        /// For `RGB_COLOR` files: the channel to read (default `None`: [`DEFAULT_CHANNEL`],
        /// green). Giving one for a one-channel file is an error.
        #[serde(skip_serializing_if = "Option::is_none")]
        channel: Option<Channel>,
        /// What the values are when the file has no `#PARAM_OUT` line (default `None`: such a
        /// file is refused). When the file has one, it must agree.
        #[serde(skip_serializing_if = "Option::is_none")]
        param_out: Option<AltaOutput>,
    },
}

impl Format {
    /// The format named `name` (one of [`FORMAT_NAMES`], any case, surrounding spaces
    /// ignored) with its default options.
    pub fn from_name(name: &str) -> Result<Format, FormatError> {
        Ok(match name.trim().to_ascii_lowercase().as_str() {
            "cornell" => Format::Cornell {
                wavelength_nm: crate::DEFAULT_WAVELENGTH_NM,
            },
            "csv" => Format::Csv,
            "merl" => Format::Merl {
                channel: DEFAULT_CHANNEL,
            },
            "alta" => Format::Alta {
                channel: None,
                param_out: None,
            },
            _ => {
                return Err(FormatError::UnknownName {
                    found: name.to_string(),
                });
            }
        })
    }

    /// The format of `path` by its extension (see [`EXTENSIONS`]), with default options. An
    /// unknown or missing extension is [`DataError::UnknownFormat`], naming the file and
    /// listing the known extensions: there is no fallback format.
    pub fn from_path(path: &Path) -> Result<Format, DataError> {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        let name = ext
            .as_deref()
            .and_then(|e| EXTENSIONS.iter().find(|(x, _)| *x == e))
            .map(|(_, n)| *n);
        match name {
            Some(n) => Format::from_name(n).map_err(|e| invalid(path, e)),
            None => Err(DataError::UnknownFormat {
                path: path.to_path_buf(),
                extension: ext,
            }),
        }
    }

    /// The format's name (one of [`FORMAT_NAMES`]).
    pub fn name(&self) -> &'static str {
        match self {
            Format::Cornell { .. } => "cornell",
            Format::Csv => "csv",
            Format::Merl { .. } => "merl",
            Format::Alta { .. } => "alta",
        }
    }

    /// Checks the options (the one validation every reader and spec goes through): a Cornell
    /// wavelength must be finite and positive; an ALTA `channel` needs `RGB_COLOR` values when
    /// `param_out` says what they are. Channels are valid by construction (names are checked
    /// when parsed, [`Channel`]'s `FromStr`).
    pub fn validate(&self) -> Result<(), FormatError> {
        match *self {
            Format::Cornell { wavelength_nm }
                if !(wavelength_nm.is_finite() && wavelength_nm > 0.0) =>
            {
                Err(FormatError::Option {
                    format: "cornell",
                    option: "wavelength_nm",
                    expected: "a finite wavelength in nm greater than 0".into(),
                    found: wavelength_nm.to_string(),
                })
            }
            Format::Alta {
                channel: Some(c),
                param_out: Some(o),
            } if o != AltaOutput::RgbColor => Err(FormatError::Option {
                format: "alta",
                option: "channel",
                expected: format!("no channel for one-channel values (`param_out = \"{o}\"`)"),
                found: format!("\"{c}\""),
            }),
            _ => Ok(()),
        }
    }
}

impl std::str::FromStr for Format {
    type Err = FormatError;

    /// [`Format::from_name`].
    fn from_str(s: &str) -> Result<Self, FormatError> {
        Format::from_name(s)
    }
}

impl std::fmt::Display for Format {
    /// The name and the options, e.g. `cornell (550 nm)`, `merl (green)`, `csv`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Format::Cornell { wavelength_nm } => write!(f, "cornell ({wavelength_nm} nm)"),
            Format::Csv => f.write_str("csv"),
            Format::Merl { channel } => write!(f, "merl ({channel})"),
            Format::Alta { channel, param_out } => {
                f.write_str("alta")?;
                let opts: Vec<String> = channel
                    .map(|c| c.to_string())
                    .into_iter()
                    .chain(param_out.map(|o| format!("PARAM_OUT {o}")))
                    .collect();
                if !opts.is_empty() {
                    write!(f, " ({})", opts.join(", "))?;
                }
                Ok(())
            }
        }
    }
}

/// The table form of [`Format`] with its defaults (deserialisation only).
#[derive(Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
enum FormatTable {
    Cornell {
        #[serde(default = "default_wavelength")]
        wavelength_nm: f64,
    },
    // A struct variant so that unknown keys are refused (a unit variant ignores them).
    Csv {},
    Merl {
        #[serde(default = "default_channel")]
        channel: Channel,
    },
    Alta {
        #[serde(default)]
        channel: Option<Channel>,
        #[serde(default)]
        param_out: Option<AltaOutput>,
    },
}

fn default_wavelength() -> f64 {
    crate::DEFAULT_WAVELENGTH_NM
}

fn default_channel() -> Channel {
    DEFAULT_CHANNEL
}

impl From<FormatTable> for Format {
    fn from(t: FormatTable) -> Self {
        match t {
            FormatTable::Cornell { wavelength_nm } => Format::Cornell { wavelength_nm },
            FormatTable::Csv {} => Format::Csv,
            FormatTable::Merl { channel } => Format::Merl { channel },
            FormatTable::Alta { channel, param_out } => Format::Alta { channel, param_out },
        }
    }
}

impl<'de> Deserialize<'de> for Format {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Format;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                write!(
                    f,
                    "a format name ({}) or a table with `kind` and the format's options",
                    FORMAT_NAMES.join(", ")
                )
            }
            fn visit_str<E: de::Error>(self, s: &str) -> Result<Format, E> {
                Format::from_name(s).map_err(E::custom)
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Format, A::Error> {
                let f: Format =
                    FormatTable::deserialize(de::value::MapAccessDeserializer::new(map))?.into();
                f.validate().map_err(de::Error::custom)?;
                Ok(f)
            }
        }
        d.deserialize_any(V)
    }
}

fn invalid(path: &Path, source: FormatError) -> DataError {
    DataError::Format {
        path: path.to_path_buf(),
        source,
    }
}

/// Reads the data file `path` in `format`, applying `filters`: the one entry point of every
/// reader ([`super::read_cornell`], [`super::read_csv`] and [`super::read_merl`] call it).
/// The options are validated first ([`Format::validate`]); text files are streamed and every
/// input is bounded (see the module docs). Errors name the file, and for text the line and
/// what was expected.
pub fn read(
    path: &Path,
    format: &Format,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    format.validate().map_err(|e| invalid(path, e))?;
    dispatch(
        format,
        filters,
        || Ok(LineSource::new(std::io::BufReader::new(open(path)?), path)),
        || MerlBrdf::read(path),
    )
}

/// [`read`] for a file already in memory (`bytes`: UTF-8 text, or a MERL table); `path` is
/// only used in errors.
pub fn parse(
    bytes: &[u8],
    path: &Path,
    format: &Format,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    format.validate().map_err(|e| invalid(path, e))?;
    dispatch(
        format,
        filters,
        || {
            check_text_len(bytes, path)?;
            Ok(LineSource::new(bytes, path))
        },
        || MerlBrdf::from_bytes(bytes, path),
    )
}

/// Runs the reader of `format` on the input that `text` (text formats) or `merl` opens.
fn dispatch<'p, R: BufRead>(
    format: &Format,
    filters: &Filters,
    text: impl FnOnce() -> Result<LineSource<'p, R>, DataError>,
    merl: impl FnOnce() -> Result<MerlBrdf, DataError>,
) -> Result<(DataSet, FilterReport), DataError> {
    match *format {
        Format::Cornell { wavelength_nm } => cornell_from(text()?, wavelength_nm, filters),
        Format::Csv => csv_from(text()?, filters),
        Format::Alta { channel, param_out } => alta_from(text()?, channel, param_out, filters),
        Format::Merl { channel } => Ok(merl()?.sample_grid(channel, filters)),
    }
}

// The readers' own entry points, kept for their callers: each is `read` or `parse` with
// its format.

/// Reads a CSV file (format in the module docs), applying `filters`: [`read`] with
/// [`Format::Csv`]. The file is streamed (see the module docs for the limits).
pub fn read_csv(
    path: impl AsRef<Path>,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    read(path.as_ref(), &Format::Csv, filters)
}

/// Parses CSV already in memory; `path` is only used in errors: [`parse`] with
/// [`Format::Csv`].
pub fn parse_csv(
    text: &str,
    path: &Path,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    parse(text.as_bytes(), path, &Format::Csv, filters)
}

/// Reads a Cornell `.brdf` file at wavelength `wavelength_nm` (must match one listed in the
/// file within 1e-6 nm), applying `filters`: [`read`] with [`Format::Cornell`]. The
/// file is streamed (see the module docs for the limits).
pub fn read_cornell(
    path: impl AsRef<Path>,
    wavelength_nm: f64,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    read(path.as_ref(), &Format::Cornell { wavelength_nm }, filters)
}

/// Parses Cornell text already in memory; `path` is only used in errors: [`parse`]
/// with [`Format::Cornell`].
pub fn parse_cornell(
    text: &str,
    path: &Path,
    wavelength_nm: f64,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    parse(
        text.as_bytes(),
        path,
        &Format::Cornell { wavelength_nm },
        filters,
    )
}

/// Reads a MERL file and samples `channel` on its own grid (see [`MerlBrdf::sample_grid`]):
/// [`read`] with [`Format::Merl`].
pub fn read_merl(
    path: impl AsRef<Path>,
    channel: Channel,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    read(path.as_ref(), &Format::Merl { channel }, filters)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{read_cornell, read_merl};

    fn alta() -> Format {
        Format::Alta {
            channel: None,
            param_out: None,
        }
    }

    #[test]
    fn from_path_picks_by_extension() {
        let cases = [
            ("a/x.brdf", "cornell"),
            ("x.BRDF", "cornell"),
            ("x.csv", "csv"),
            ("x.binary", "merl"),
            ("x.merl", "merl"),
            ("x.alta", "alta"),
            ("retro-3M-jaune.dat", "alta"),
        ];
        for (p, name) in cases {
            let f = Format::from_path(Path::new(p)).unwrap();
            assert_eq!(f.name(), name, "{p}");
            assert_eq!(f, Format::from_name(name).unwrap());
        }
        assert_eq!(
            Format::from_path(Path::new("k.brdf")).unwrap(),
            Format::Cornell {
                wavelength_nm: 550.0
            }
        );
    }

    #[test]
    fn unknown_or_missing_extension_is_an_error_listing_the_known_ones() {
        let e = Format::from_path(Path::new("data/x.txt")).unwrap_err();
        assert!(
            matches!(&e, DataError::UnknownFormat { extension: Some(x), .. } if x == "txt"),
            "{e:?}"
        );
        assert_eq!(
            e.to_string(),
            "data/x.txt: cannot tell the format from the extension `.txt`; expected one of \
             the extensions .brdf (cornell), .csv (csv), .binary (merl), .merl (merl), .alta \
             (alta), .dat (alta) or a format named explicitly (cornell, csv, merl, alta)"
        );
        let e = Format::from_path(Path::new("data/README")).unwrap_err();
        assert!(
            e.to_string().starts_with(
                "data/README: cannot tell the format from a file name without an \
                 extension; expected one of the extensions .brdf (cornell),"
            ),
            "{e}"
        );
    }

    #[test]
    fn names_and_channels() {
        assert_eq!(" CSV ".parse::<Format>().unwrap(), Format::Csv);
        assert_eq!(
            Format::from_name("merl").unwrap(),
            Format::Merl {
                channel: Channel::Green
            }
        );
        assert_eq!(Format::from_name("Alta").unwrap(), alta());
        let e = Format::from_name("xml").unwrap_err();
        assert_eq!(
            e.to_string(),
            "expected a format name (cornell, csv, merl, alta), found `xml`"
        );
        assert_eq!("Blue".parse::<Channel>().unwrap(), Channel::Blue);
        let e = "purple".parse::<Channel>().unwrap_err();
        assert_eq!(
            e.to_string(),
            "expected a channel name (red, green, blue), found `purple`"
        );
        for f in [
            Format::from_name("cornell").unwrap(),
            Format::Csv,
            Format::from_name("merl").unwrap(),
            alta(),
            Format::Alta {
                channel: Some(Channel::Red),
                param_out: Some(AltaOutput::RgbColor),
            },
        ] {
            assert!(FORMAT_NAMES.contains(&f.name()));
            assert!(f.to_string().starts_with(f.name()));
        }
        assert_eq!(
            Format::Alta {
                channel: Some(Channel::Red),
                param_out: Some(AltaOutput::RgbColor),
            }
            .to_string(),
            "alta (red, PARAM_OUT RGB_COLOR)"
        );
    }

    #[test]
    fn validate_checks_each_rule() {
        for wl in [f64::NAN, f64::INFINITY, 0.0, -550.0] {
            let e = Format::Cornell { wavelength_nm: wl }
                .validate()
                .unwrap_err();
            assert_eq!(
                e.to_string(),
                format!(
                    "format `cornell`, option `wavelength_nm`: expected a finite wavelength in \
                     nm greater than 0, found {wl}"
                )
            );
        }
        assert!(Format::Cornell { wavelength_nm: 0.5 }.validate().is_ok());
        let f = Format::Alta {
            channel: Some(Channel::Red),
            param_out: Some(AltaOutput::InvSteradian),
        };
        assert_eq!(
            f.validate().unwrap_err().to_string(),
            "format `alta`, option `channel`: expected no channel for one-channel values \
             (`param_out = \"INV_STERADIAN\"`), found \"red\""
        );
        for f in [
            Format::Csv,
            alta(),
            Format::Alta {
                channel: Some(Channel::Red),
                param_out: Some(AltaOutput::RgbColor),
            },
            Format::Alta {
                channel: Some(Channel::Red),
                param_out: None,
            },
        ] {
            assert!(f.validate().is_ok(), "{f}");
        }
    }

    #[test]
    fn serde_takes_a_name_or_a_table_and_validates() {
        let de = |s: &str| serde_json::from_str::<Format>(s);
        assert_eq!(
            de("\"cornell\"").unwrap(),
            Format::from_name("cornell").unwrap()
        );
        assert_eq!(
            de(r#"{"kind": "cornell", "wavelength_nm": 600}"#).unwrap(),
            Format::Cornell {
                wavelength_nm: 600.0
            }
        );
        assert_eq!(
            de(r#"{"kind": "merl", "channel": "red"}"#).unwrap(),
            Format::Merl {
                channel: Channel::Red
            }
        );
        assert_eq!(de(r#"{"kind": "csv"}"#).unwrap(), Format::Csv);
        assert_eq!(
            de(r#"{"kind": "alta", "param_out": "INV_STERADIAN_COSINE_FACTOR"}"#).unwrap(),
            Format::Alta {
                channel: None,
                param_out: Some(AltaOutput::InvSteradianCosineFactor)
            }
        );
        let e = de(r#"{"kind": "cornell", "wavelength_nm": -1}"#).unwrap_err();
        assert!(
            e.to_string()
                .contains("option `wavelength_nm`: expected a finite"),
            "{e}"
        );
        for bad in [
            r#"{"kind": "csv", "wavelength_nm": 550}"#,
            r#"{"kind": "merl", "channel": "purple"}"#,
            r#"{"kind": "xml"}"#,
            r#""xml""#,
            r#"{"kind": "alta", "param_out": "ENERGY"}"#,
            "3",
        ] {
            assert!(de(bad).is_err(), "{bad}");
        }
        for f in [
            Format::Cornell {
                wavelength_nm: 600.0,
            },
            Format::Csv,
            Format::Merl {
                channel: Channel::Blue,
            },
            alta(),
            Format::Alta {
                channel: Some(Channel::Red),
                param_out: Some(AltaOutput::RgbColor),
            },
        ] {
            let s = serde_json::to_string(&f).unwrap();
            assert_eq!(de(&s).unwrap(), f, "{s}");
        }
        assert_eq!(
            serde_json::to_string(&Format::Cornell {
                wavelength_nm: 550.0
            })
            .unwrap(),
            r#"{"kind":"cornell","wavelength_nm":550.0}"#
        );
    }

    /// The form a spec file will use: `format` under a file table, a name or an inline table.
    #[test]
    fn toml_spec_forms() {
        #[derive(Deserialize)]
        struct FileSpec {
            #[allow(dead_code)]
            path: String,
            format: Option<Format>,
        }
        let de = |s: &str| toml::from_str::<FileSpec>(s).map(|f| f.format);
        assert_eq!(de("path = \"x.brdf\"").unwrap(), None);
        assert_eq!(
            de("path = \"x\"\nformat = \"merl\"").unwrap(),
            Some(Format::from_name("merl").unwrap())
        );
        assert_eq!(
            de("path = \"x\"\nformat = { kind = \"cornell\", wavelength_nm = 600 }").unwrap(),
            Some(Format::Cornell {
                wavelength_nm: 600.0
            })
        );
        let e = de("path = \"x\"\n[format]\nkind = \"cornell\"\nwavelength_nm = -5\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 2") && e.contains("option `wavelength_nm`: expected a finite"),
            "{e}"
        );
        let e = de("path = \"x\"\nformat = \"xml\"")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("expected a format name (cornell, csv, merl, alta)"),
            "{e}"
        );
    }

    #[test]
    fn every_reader_goes_through_read_and_its_validation() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("k.brdf");
        std::fs::write(&p, "1\n550\n0.1 0 0.1 3.14 2\n").unwrap();
        let f = Format::from_path(&p).unwrap();
        let (d, rep) = read(&p, &f, &Filters::default()).unwrap();
        assert_eq!((d.len(), rep.read, d.value(0)), (1, 1, 2.0));
        assert_eq!(read_cornell(&p, 550.0, &Filters::default()).unwrap().0, d);
        // The wrappers validate too: the error names the file and the rule.
        let e = read_cornell(&p, f64::NAN, &Filters::default()).unwrap_err();
        assert!(matches!(e, DataError::Format { .. }), "{e:?}");
        assert!(
            e.to_string()
                .starts_with(&format!("{}: format `cornell`", p.display())),
            "{e}"
        );
        // MERL through `read` and `parse` gives the grid sample of `read_merl`.
        let m = MerlBrdf {
            dims: (1, 1, 2),
            table: vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
        };
        let mp = dir.path().join("m.binary");
        std::fs::write(&mp, m.to_bytes()).unwrap();
        let f = Format::from_path(&mp).unwrap();
        let a = read(&mp, &f, &Filters::none()).unwrap();
        let b = parse(&m.to_bytes(), &mp, &f, &Filters::none()).unwrap();
        let c = read_merl(&mp, Channel::Green, &Filters::none()).unwrap();
        assert_eq!(a.0, b.0);
        assert_eq!(a.0, c.0);
        assert_eq!(a.0.value(0), 3.0 * 1.15 / 1500.0);
        // A missing file is an I/O error naming it.
        let e = read(
            &dir.path().join("none.csv"),
            &Format::Csv,
            &Filters::default(),
        )
        .unwrap_err();
        assert!(matches!(e, DataError::Io { .. }), "{e}");
    }
}
