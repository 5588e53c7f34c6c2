//! Readers for measured data.
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

mod cornell;
mod csv;
mod limits;
mod lines;
mod merl;

pub use cornell::{parse_cornell, read_cornell};
pub use csv::{parse_csv, read_csv};
pub use limits::{
    MAX_INPUT_BYTES, MAX_LINE_BYTES, MAX_MERL_BYTES, MAX_MERL_DIM, MAX_SAMPLES, MAX_WAVELENGTHS,
};
pub use merl::{Channel, MerlBrdf, read_merl};

#[cfg(doc)]
use crate::data::{DataSet, FilterReport, Filters};
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
