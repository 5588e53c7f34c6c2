//! Readers for measured reflectance data: Cornell, CSV, MERL and ALTA files, read into
//! [`brdf_model::DataSet`]s under the one data policy ([`brdf_model::Filters`]).
//!
//! # One entry point
//! A data format and its options are one value, [`Format`]: `Cornell { wavelength_nm }`,
//! `Csv`, `Merl { channel }` or `Alta { channel, param_out }`, each with documented defaults.
//! [`Format::from_path`] picks one by the file's extension (`.brdf` Cornell, `.csv` CSV,
//! `.binary`/`.merl` MERL, `.alta`/`.dat` ALTA; see [`EXTENSIONS`]) and refuses an unknown
//! or missing extension with [`DataError::UnknownFormat`], which names the file and lists the
//! known extensions: there is no default format. [`Format::from_name`] takes a name,
//! serde takes a name or a `kind`-tagged table. [`Format::validate`] is the one check of the
//! options (a finite, positive wavelength; an ALTA channel only for RGB values), run by
//! [`read`], [`parse`] and deserialisation alike. [`read`] (a file) and [`parse`] (bytes in
//! memory) are the one entry point of every reader; [`read_cornell`], [`read_csv`],
//! [`read_merl`], [`parse_cornell`] and [`parse_csv`] are thin wrappers kept for their
//! callers. The text readers (Cornell, CSV, ALTA) share one line loop: blank lines and `#`
//! comments skipped, the limits below, line numbers in errors.
//!
//! Every reader fails with a [`DataError`] naming the file, the line (text formats) and what
//! was expected; none panics, aborts or loops on bad input. Input is bounded: text files by
//! [`MAX_INPUT_BYTES`] in total and [`MAX_LINE_BYTES`] per line, MERL files by
//! [`MAX_MERL_BYTES`], every reader by [`MAX_SAMPLES`] sample rows (counted before filtering)
//! and Cornell files by [`MAX_WAVELENGTHS`]. Text input is read as a stream (at most
//! the limit plus one byte through [`std::io::Read::take`]), so `/dev/zero` or an endless
//! pipe fails at once (NUL bytes are refused: the text formats are UTF-8 text) or at the
//! limit; declared counts are checked against the limits before anything is allocated.
//!
//! # Non-finite values
//! The text readers accept `nan`, `inf`, `infinity` (any case, optional sign) wherever a
//! number is expected, so that one bad measurement does not make a whole file unreadable;
//! the [`Filters`] then decide: every constructor except [`Filters::none`] drops samples
//! whose value or direction is not finite and counts them in [`FilterReport::non_finite`].
//! A NaN thus reaches a data set only when the caller asked for it (`drop_non_finite:
//! false`). MERL entries are used as stored, through the same filters.
//!
//! # Cornell text format (`*.brdf`)
//! Comment lines start with `#`; blank lines are ignored. The first number is the count of
//! wavelengths `W` (1 to [`MAX_WAVELENGTHS`]), then `W` wavelengths in nm (over any number of
//! lines), then one sample per line: `theta_i phi_i theta_s phi_s` in radians followed by `W`
//! values. Angles become vectors pointing away from the surface,
//! `(sin t cos p, sin t sin p, cos t)`; the files put the specular direction at
//! `phi_s = phi_i + pi`, which is where a lobe with `Cx = Cy < 0` peaks. [`read_cornell`]
//! selects one wavelength (550 nm by default in the CLI).
//!
//! # CSV format
//! A header line names the columns (comma-separated, case-insensitive, surrounding spaces
//! ignored), then one sample per line with as many fields as the header. Either
//! - `ux,uy,uz,vx,vy,vz,value`: direction vectors (normalised on reading; both point away
//!   from the surface, z = normal; a zero vector is an error), or
//! - `theta_i,phi_i,theta_o,phi_o,value`: angles in **degrees** (theta from the normal).
//!
//! **Extra columns are ignored**: they may appear anywhere and hold anything (text, empty
//! fields), only the named columns are parsed. A column name given twice is an error. Lines
//! starting with `#` and blank lines are skipped. [`DataSet::write_csv`] writes the vector
//! form.
//!
//! # MERL binary format
//! Three little-endian `i32` dimensions `(n_theta_h, n_theta_d, n_phi_d)` — `(90, 90, 180)`
//! in every file of the real database (34,992,012 bytes) — then `3 * N` little-endian `f64`
//! (`N` = product of the dims): the red, green and blue blocks. The reader accepts other
//! dimensions (each 1 to [`MAX_MERL_DIM`], total size at most [`MAX_MERL_BYTES`]) so tests
//! can write small files. Index
//! `phi_d_idx + n_phi_d * (theta_d_idx + n_theta_d * theta_h_idx)` with
//! `theta_h_idx = floor(n_theta_h * sqrt(theta_h / (pi/2)))`, `theta_d_idx` linear over
//! `[0, pi/2)`, `phi_d` folded into `[0, pi)` by reciprocity. Channel scales: red 1/1500,
//! green 1.15/1500, blue 1.66/1500. Negative entries mark samples below the horizon: they are
//! counted (and dropped) as [`FilterReport::below_horizon`] when the filters drop
//! below-horizon samples.
//!
//! # ALTA text format (`*.alta`, `*.dat`)
//! The text format of ALTA (<https://github.com/mkae/alta>, documented in its
//! `documents/data-formats.dox`), used by its retro-reflection measurements. A header of
//! `#KEY value` lines (`#` directly followed by a letter; `# ` and other `#` lines are
//! comments), ended by the first data line or `#ALTA END HEADER`, then one sample per line:
//! `N` input numbers, `P` output numbers and, with `#VS 1` or `#VS 2`, one or two
//! confidence-interval numbers (read and ignored), separated by white space. Header keys read:
//! - `#DIM N P` (required): must be the input parameterisation's `N` and the output's `P`;
//! - `#PARAM_IN` (required): one of the input parameterisations below;
//! - `#PARAM_OUT`: `INV_STERADIAN` (the BRDF, `P = 1`), `INV_STERADIAN_COSINE_FACTOR` (the
//!   BRDF times `cos(theta_in)`, `P = 1`) or `RGB_COLOR` (the BRDF per colour, `P = 3`: the
//!   format's `channel` picks one, green by default as for MERL). A file without it is
//!   refused unless the format's `param_out` option says what the values are (one of ALTA's
//!   shipped files, `retro-gray-tape.dat`, has none); when both are present they must agree;
//! - `#VS 0|1|2` (default 0; only 0 with `P = 3`);
//! - `#FORMAT text` (optional; ALTA's binary format is refused).
//!
//! Other keys (`#SAMPLE`, `#ORIGIN`, `#URL`, `#CMD`, ...) are ignored; a key given twice, an
//! unsupported parameterisation, or a `#DIM` that does not match is refused with an error
//! naming the file, the line and the supported values. `ENERGY`, `XYZ_COLOR` and every other
//! input parameterisation are refused, never guessed.
//!
//! **Directions.** ALTA packs a direction pair as `[V, L]` (view first, `params.h`, enum
//! `CARTESIAN`); the light `L` is our incident `u`, the view `V` our exitant `v`, both unit
//! vectors pointing away from the surface, z = normal; angles in radians. As ALTA's
//! `params::to_cartesian`:
//! - `ISOTROPIC_TL_TV_PROJ_DPHI` `[theta_l, a, b]`: `u = (sin theta_l, 0, cos theta_l)`,
//!   `v = (a/t sin t, b/t sin t, cos t)` with `t = hypot(a, b)` (`v = (0, 0, 1)` at `t = 0`);
//! - `ISOTROPIC_TV_TL_DPHI` `[theta_v, theta_l, dphi]`: `v = (sin theta_v, 0, cos theta_v)`,
//!   `u = (sin theta_l cos dphi, sin theta_l sin dphi, cos theta_l)`;
//! - `RUSIN_TH_TD_PD` `[theta_h, theta_d, phi_d]` and `RUSIN_TH_PH_TD_PD`
//!   `[theta_h, phi_h, theta_d, phi_d]`: `v` is the difference vector
//!   `(sin theta_d cos phi_d, sin theta_d sin phi_d, cos theta_d)` turned by `theta_h` about y,
//!   then by `phi_h` about z; `u = 2 (v . h) h - v` with the half vector
//!   `h = (sin theta_h cos phi_h, sin theta_h sin phi_h, cos theta_h)`;
//! - `SPHERICAL_TL_PL_TV_PV` `[theta_l, phi_l, theta_v, phi_v]`: the two directions in
//!   spherical coordinates;
//! - `CARTESIAN` `[V.x, V.y, V.z, L.x, L.y, L.z]`: normalised on reading (a zero vector is an
//!   error).
//!
//! (ALTA's inverse conversion, `params::from_cartesian`, takes `b` with the opposite sign for
//! `ISOTROPIC_TL_TV_PROJ_DPHI`: a mirror image in the incidence plane, the same BRDF for the
//! isotropic materials this parameterisation is for; the reader follows `to_cartesian`, the
//! conversion ALTA applies to data it reads.)
//!
//! For the isotropic parameterisations (the first three) the pair is then rotated about the
//! normal so that the incident direction lies in the x-z plane (`phi_in = 0`, `u.x >= 0`);
//! for `ISOTROPIC_TL_TV_PROJ_DPHI` it already does. Reduced parameterisations (fewer numbers
//! than an isotropic pair needs, e.g. `RUSIN_TH_TD`) are refused: they do not determine a
//! direction pair.
//!
//! **Values.** `INV_STERADIAN_COSINE_FACTOR` values are divided by `cos(theta_in) = u.z`, as
//! ALTA's `nonlinear_fitter_eigen` compares such data with `cos(theta_L) f` (its `params.h`
//! comment says "the output direction"; the fitter's use is what the data were fitted
//! with). Below
//! [`ALTA_MIN_COSINE`] (grazing or below-horizon incidence) there is no BRDF value: the sample
//! is marked below the horizon and counted in [`FilterReport::below_horizon`] by filters that
//! drop such samples; with filters that keep them its value is NaN (then counted in
//! [`FilterReport::non_finite`] unless the filters keep everything).
//!
//! **Data.** ALTA's measurements of three retro-reflective tapes (CEA-CESTA, see
//! <https://hal.inria.fr/hal-01083366/>) live in ALTA's `documents/data/`. ALTA is under
//! MPL-2.0 and its authors ask to be contacted before reuse, so the files are not shipped
//! here; `scripts/fetch-alta-data.sh DIR` downloads them and checks their SHA-256
//! (`docs/model.md` lists them).

#![warn(missing_docs)]

mod alta;
mod cornell;
mod csv;
mod format;
mod limits;
mod lines;
mod merl;
#[cfg(test)]
mod reader_tests;

pub use alta::{ALTA_MIN_COSINE, AltaInput, AltaOutput};

pub use format::{
    DEFAULT_CHANNEL, EXTENSIONS, FORMAT_NAMES, Format, parse, parse_cornell, parse_csv, read,
    read_cornell, read_csv, read_merl,
};
pub use limits::{
    MAX_INPUT_BYTES, MAX_LINE_BYTES, MAX_MERL_BYTES, MAX_MERL_DIM, MAX_SAMPLES, MAX_WAVELENGTHS,
};
pub use merl::{Channel, MerlBrdf};

#[cfg(doc)]
use brdf_model::{DataSet, FilterReport, Filters};
use std::path::{Path, PathBuf};

/// Errors reading a data file. Each names the file; parse errors also name the line (from 1)
/// and what was expected.
#[derive(Debug, thiserror::Error)]
pub enum DataError {
    /// The file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// File.
        path: PathBuf,
        /// Underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A line did not have the expected content.
    #[error("{path}:{line}: expected {expected}, found {found}")]
    Parse {
        /// File.
        path: PathBuf,
        /// Line number, from 1 (0 when the problem is the end of the file).
        line: usize,
        /// What was expected.
        expected: String,
        /// What was found.
        found: String,
    },
    /// The requested wavelength is not in the file.
    #[error("{path}: no wavelength {wavelength_nm} nm (the file has {available:?})")]
    NoWavelength {
        /// File.
        path: PathBuf,
        /// Requested wavelength.
        wavelength_nm: f64,
        /// Wavelengths in the file.
        available: Vec<f64>,
    },
    /// A binary file is malformed (size or header).
    #[error("{path}: {message}")]
    Binary {
        /// File.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// The format cannot be told from the file's extension ([`Format::from_path`]).
    #[error(
        "{path}: cannot tell the format from {}; expected one of the extensions {} or a \
         format named explicitly ({})",
        extension.as_ref().map_or_else(|| "a file name without an extension".to_string(), |e| format!("the extension `.{e}`")),
        known_extensions(),
        FORMAT_NAMES.join(", ")
    )]
    UnknownFormat {
        /// File.
        path: PathBuf,
        /// Its extension (lower case), if it has one.
        extension: Option<String>,
    },
    /// The format's options are not valid ([`Format::validate`]).
    #[error("{path}: {source}")]
    Format {
        /// File.
        path: PathBuf,
        /// What is wrong.
        #[source]
        source: FormatError,
    },
    /// The input exceeds one of the stated limits ([`MAX_INPUT_BYTES`], [`MAX_LINE_BYTES`],
    /// [`MAX_SAMPLES`], [`MAX_WAVELENGTHS`], [`MAX_MERL_BYTES`]).
    #[error("{path}:{line}: {message}")]
    Limit {
        /// File.
        path: PathBuf,
        /// Line number, from 1 (0 when not tied to a line).
        line: usize,
        /// Which limit, its value and what was found.
        message: String,
    },
}

/// `.brdf (cornell), .csv (csv), ...`, from [`EXTENSIONS`].
fn known_extensions() -> String {
    EXTENSIONS
        .iter()
        .map(|(e, n)| format!(".{e} ({n})"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A format name or option that is not valid.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FormatError {
    /// No format has this name.
    #[error("expected a format name ({}), found `{found}`", format::FORMAT_NAMES.join(", "))]
    UnknownName {
        /// The name given.
        found: String,
    },
    /// No channel has this name.
    #[error("expected a channel name (red, green, blue), found `{found}`")]
    UnknownChannel {
        /// The name given.
        found: String,
    },
    /// An option out of its range.
    #[error("format `{format}`, option `{option}`: expected {expected}, found {found}")]
    Option {
        /// The format's name.
        format: &'static str,
        /// The option's name.
        option: &'static str,
        /// What the option must be.
        expected: String,
        /// What it was.
        found: String,
    },
}

/// Normalises a direction given by finite or non-finite components: `Ok(None)` for a zero
/// vector, non-finite components are passed through (the filters count them).
pub(crate) fn normalise(a: [f64; 3]) -> Option<[f64; 3]> {
    if a.iter().any(|c| !c.is_finite()) {
        return Some(a);
    }
    // Scale first so that huge or tiny components neither overflow nor underflow.
    let m = a.iter().fold(0.0f64, |m, c| m.max(c.abs()));
    if m == 0.0 {
        return None;
    }
    let b = [a[0] / m, a[1] / m, a[2] / m];
    let len = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt();
    Some([b[0] / len, b[1] / len, b[2] / len])
}

fn io_err(path: &Path, source: std::io::Error) -> DataError {
    DataError::Io {
        path: path.to_path_buf(),
        source,
    }
}

fn open(path: &Path) -> Result<std::fs::File, DataError> {
    std::fs::File::open(path).map_err(|e| io_err(path, e))
}

fn dir_from_angles(theta: f64, phi: f64) -> [f64; 3] {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    [st * cp, st * sp, ct]
}

/// Default wavelength (nm) for Cornell files, as in the paper.
pub const DEFAULT_WAVELENGTH_NM: f64 = 550.0;
