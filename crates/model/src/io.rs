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

use crate::data::{DataSet, FilterReport, Filters};
use std::f64::consts::{FRAC_PI_2, PI};
use std::io::{BufRead, Read};
use std::path::{Path, PathBuf};

/// Largest text input (Cornell, CSV) read, in bytes: 1 GiB. A longer input is refused with
/// [`DataError::Limit`] after reading `MAX_INPUT_BYTES + 1` bytes.
pub const MAX_INPUT_BYTES: u64 = 1 << 30;

/// Longest line of a text input, in bytes (without the line break): 1 MiB.
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// Most sample rows a reader accepts (counted before filtering; also the largest synthetic
/// instance, see [`crate::data::try_synthetic`]): 10,000,000 (about 560 MB as a [`DataSet`]).
/// The full MERL grid has 1,458,000 cells, the paper's instances 10,000 samples.
pub const MAX_SAMPLES: usize = crate::data::MAX_SAMPLES;

/// Most wavelengths a Cornell file may declare: 10,000 (the real files have 31).
pub const MAX_WAVELENGTHS: usize = 10_000;

/// Largest MERL dimension: 4096 (the real database uses 90, 90, 180).
pub const MAX_MERL_DIM: usize = 4096;

/// Largest MERL file, in bytes: 512 MiB (the real files have 34,992,012 bytes).
pub const MAX_MERL_BYTES: u64 = 512 << 20;

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

/// Streams the content lines of a text input (blank lines and `#` comments skipped), enforcing
/// [`MAX_INPUT_BYTES`], [`MAX_LINE_BYTES`], no NUL bytes and UTF-8.
struct LineSource<'p, R> {
    reader: R,
    path: &'p Path,
    buf: Vec<u8>,
    total: u64,
    line: usize,
}

impl<'p, R: BufRead> LineSource<'p, R> {
    fn new(reader: R, path: &'p Path) -> Self {
        LineSource {
            reader,
            path,
            buf: Vec::new(),
            total: 0,
            line: 0,
        }
    }

    fn limit(&self, message: String) -> DataError {
        DataError::Limit {
            path: self.path.to_path_buf(),
            line: self.line,
            message,
        }
    }

    /// The next non-blank, non-comment line, trimmed, with its number (from 1).
    fn next_line(&mut self) -> Result<Option<(usize, &str)>, DataError> {
        loop {
            self.buf.clear();
            let left = MAX_INPUT_BYTES + 1 - self.total;
            let cap = left.min(MAX_LINE_BYTES as u64 + 2);
            let n = (&mut self.reader)
                .take(cap)
                .read_until(b'\n', &mut self.buf)
                .map_err(|e| io_err(self.path, e))?;
            if n == 0 {
                return Ok(None);
            }
            self.total += n as u64;
            self.line += 1;
            if self.total > MAX_INPUT_BYTES {
                return Err(self.limit(format!(
                    "expected at most {MAX_INPUT_BYTES} bytes of text (MAX_INPUT_BYTES), found more"
                )));
            }
            if self.buf.last() == Some(&b'\n') {
                self.buf.pop();
                if self.buf.last() == Some(&b'\r') {
                    self.buf.pop();
                }
            }
            if self.buf.len() > MAX_LINE_BYTES {
                return Err(self.limit(format!(
                    "expected lines of at most {MAX_LINE_BYTES} bytes (MAX_LINE_BYTES), found a longer one"
                )));
            }
            if let Some(k) = self.buf.iter().position(|&b| b == 0) {
                return Err(DataError::Parse {
                    path: self.path.to_path_buf(),
                    line: self.line,
                    expected: "text".into(),
                    found: format!("a NUL byte at column {} (binary data?)", k + 1),
                });
            }
            let text = match std::str::from_utf8(&self.buf) {
                Ok(t) => t.trim(),
                Err(e) => {
                    return Err(DataError::Parse {
                        path: self.path.to_path_buf(),
                        line: self.line,
                        expected: "UTF-8 text".into(),
                        found: format!("an invalid byte at column {}", e.valid_up_to() + 1),
                    });
                }
            };
            if text.is_empty() || text.starts_with('#') {
                continue;
            }
            let line = self.line;
            // Re-borrow so the returned slice ties to `self.buf` only.
            let text = std::str::from_utf8(&self.buf).unwrap_or_default().trim();
            return Ok(Some((line, text)));
        }
    }
}

fn check_text_len(text: &str, path: &Path) -> Result<(), DataError> {
    if text.len() as u64 > MAX_INPUT_BYTES {
        return Err(DataError::Limit {
            path: path.to_path_buf(),
            line: 0,
            message: format!(
                "expected at most {MAX_INPUT_BYTES} bytes of text (MAX_INPUT_BYTES), found {}",
                text.len()
            ),
        });
    }
    Ok(())
}

fn sample_limit(path: &Path, line: usize) -> DataError {
    DataError::Limit {
        path: path.to_path_buf(),
        line,
        message: format!("expected at most {MAX_SAMPLES} sample rows (MAX_SAMPLES), found more"),
    }
}

fn dir_from_angles(theta: f64, phi: f64) -> [f64; 3] {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    [st * cp, st * sp, ct]
}

fn short(s: &str) -> String {
    let t: String = s.chars().take(40).collect();
    if t.len() < s.len() {
        format!("`{t}...`")
    } else {
        format!("`{t}`")
    }
}

/// Reads a Cornell `.brdf` file at wavelength `wavelength_nm` (must match one listed in the
/// file within 1e-6 nm), applying `filters`. The file is streamed (see the module docs for
/// the limits).
pub fn read_cornell(
    path: impl AsRef<Path>,
    wavelength_nm: f64,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    let path = path.as_ref();
    let file = std::io::BufReader::new(open(path)?);
    cornell_from(LineSource::new(file, path), path, wavelength_nm, filters)
}

/// Parses Cornell text already in memory; `path` is only used in errors.
pub fn parse_cornell(
    text: &str,
    path: &Path,
    wavelength_nm: f64,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    check_text_len(text, path)?;
    cornell_from(
        LineSource::new(text.as_bytes(), path),
        path,
        wavelength_nm,
        filters,
    )
}

fn cornell_from<R: BufRead>(
    mut lines: LineSource<'_, R>,
    path: &Path,
    wavelength_nm: f64,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    let perr = |line: usize, expected: String, found: String| DataError::Parse {
        path: path.to_path_buf(),
        line,
        expected,
        found,
    };
    let (ln, first) = lines
        .next_line()?
        .ok_or_else(|| perr(0, "the number of wavelengths".into(), "end of file".into()))?;
    let mut toks = first.split_whitespace();
    let nwl: usize = match (toks.next(), toks.next()) {
        (Some(tok), None) => tok.parse().ok().filter(|&n: &usize| n > 0),
        _ => None,
    }
    .ok_or_else(|| {
        perr(
            ln,
            "the number of wavelengths (a positive integer alone on its line)".into(),
            short(first),
        )
    })?;
    if nwl > MAX_WAVELENGTHS {
        return Err(DataError::Limit {
            path: path.to_path_buf(),
            line: ln,
            message: format!(
                "expected at most {MAX_WAVELENGTHS} wavelengths (MAX_WAVELENGTHS), the file declares {nwl}"
            ),
        });
    }
    let mut wls: Vec<f64> = Vec::with_capacity(nwl);
    while wls.len() < nwl {
        let (ln, l) = lines.next_line()?.ok_or_else(|| {
            perr(
                0,
                format!("{nwl} wavelengths"),
                format!("end of file after {}", wls.len()),
            )
        })?;
        for tok in l.split_whitespace() {
            if wls.len() == nwl {
                return Err(perr(
                    ln,
                    format!("{nwl} wavelengths"),
                    format!("more numbers (`{}` is extra)", short(tok)),
                ));
            }
            let w: f64 = tok
                .parse()
                .ok()
                .filter(|w: &f64| w.is_finite())
                .ok_or_else(|| perr(ln, "a finite wavelength in nm".into(), short(tok)))?;
            wls.push(w);
        }
    }
    let col = wls
        .iter()
        .position(|w| (w - wavelength_nm).abs() < 1e-6)
        .ok_or_else(|| DataError::NoWavelength {
            path: path.to_path_buf(),
            wavelength_nm,
            available: wls.clone(),
        })?;
    let mut data = DataSet::new();
    let mut rep = FilterReport::default();
    let width = 4 + nwl;
    let mut row = [0.0f64; 5];
    let mut rows = 0usize;
    while let Some((ln, l)) = lines.next_line()? {
        rows += 1;
        if rows > MAX_SAMPLES {
            return Err(sample_limit(path, ln));
        }
        let mut count = 0usize;
        for tok in l.split_whitespace() {
            let v: f64 = tok.parse().map_err(|_| {
                perr(
                    ln,
                    format!("a number (sample row: 4 angles in radians and {nwl} values)"),
                    short(tok),
                )
            })?;
            if count < 4 {
                row[count] = v;
            } else if count == 4 + col {
                row[4] = v;
            }
            count += 1;
        }
        if count != width {
            return Err(perr(
                ln,
                format!("{width} numbers (4 angles in radians and {nwl} values)"),
                format!("{count} numbers"),
            ));
        }
        let u = dir_from_angles(row[0], row[1]);
        let v = dir_from_angles(row[2], row[3]);
        let y = row[4];
        if filters.admit(u, v, y, &mut rep) {
            data.push(u, v, y);
        }
    }
    Ok((data, rep))
}

/// Reads a CSV file (format in the module docs), applying `filters`. The file is streamed
/// (see the module docs for the limits).
pub fn read_csv(
    path: impl AsRef<Path>,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    let path = path.as_ref();
    let file = std::io::BufReader::new(open(path)?);
    csv_from(LineSource::new(file, path), path, filters)
}

/// Parses CSV already in memory; `path` is only used in errors.
pub fn parse_csv(
    text: &str,
    path: &Path,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    check_text_len(text, path)?;
    csv_from(LineSource::new(text.as_bytes(), path), path, filters)
}

/// Normalises a direction given by finite or non-finite components: `Ok(None)` for a zero
/// vector, non-finite components are passed through (the filters count them).
fn normalise(a: [f64; 3]) -> Option<[f64; 3]> {
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

fn csv_from<R: BufRead>(
    mut lines: LineSource<'_, R>,
    path: &Path,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    let perr = |line: usize, expected: String, found: String| DataError::Parse {
        path: path.to_path_buf(),
        line,
        expected,
        found,
    };
    const HEADER: &str = "a header naming ux,uy,uz,vx,vy,vz,value or theta_i,phi_i,theta_o,phi_o,value (extra columns are ignored)";
    let (hl, header) = lines
        .next_line()?
        .ok_or_else(|| perr(0, HEADER.into(), "end of file".into()))?;
    let names: Vec<String> = header
        .split(',')
        .map(|s| s.trim().to_ascii_lowercase())
        .collect();
    let header_short = short(header);
    let find = |n: &str| names.iter().position(|h| h == n);
    const VEC: [&str; 7] = ["ux", "uy", "uz", "vx", "vy", "vz", "value"];
    const ANG: [&str; 5] = ["theta_i", "phi_i", "theta_o", "phi_o", "value"];
    let vec_cols: Option<Vec<usize>> = VEC.iter().map(|n| find(n)).collect();
    let ang_cols: Option<Vec<usize>> = ANG.iter().map(|n| find(n)).collect();
    let (cols, angles) = match (vec_cols, ang_cols) {
        (Some(c), _) => (c, false),
        (None, Some(c)) => (c, true),
        (None, None) => return Err(perr(hl, HEADER.into(), header_short)),
    };
    let wanted: &[&str] = if angles { &ANG } else { &VEC };
    for n in wanted {
        if names.iter().filter(|h| h == n).count() > 1 {
            return Err(perr(
                hl,
                format!("each column name once in the header (`{n}` is repeated)"),
                header_short,
            ));
        }
    }
    let ncols = names.len();
    // slot[k] = Some(j): field k is column j of the wanted list.
    let mut slot: Vec<Option<usize>> = vec![None; ncols];
    for (j, &c) in cols.iter().enumerate() {
        slot[c] = Some(j);
    }
    let mut data = DataSet::new();
    let mut rep = FilterReport::default();
    let mut vals = [0.0f64; 7];
    let mut rows = 0usize;
    while let Some((ln, l)) = lines.next_line()? {
        rows += 1;
        if rows > MAX_SAMPLES {
            return Err(sample_limit(path, ln));
        }
        let mut count = 0usize;
        for (k, tok) in l.split(',').enumerate() {
            count += 1;
            let Some(j) = slot.get(k).copied().flatten() else {
                continue;
            };
            let tok = tok.trim();
            vals[j] = tok.parse().map_err(|_| {
                perr(
                    ln,
                    format!("a number in column `{}`", wanted[j]),
                    short(tok),
                )
            })?;
        }
        if count != ncols {
            return Err(perr(
                ln,
                format!("{ncols} comma-separated fields as in the header"),
                format!("{count} fields"),
            ));
        }
        let (u, v, y) = if angles {
            (
                dir_from_angles(vals[0].to_radians(), vals[1].to_radians()),
                dir_from_angles(vals[2].to_radians(), vals[3].to_radians()),
                vals[4],
            )
        } else {
            let norm = |a: [f64; 3], what: &str| {
                normalise(a).ok_or_else(|| {
                    perr(ln, format!("a non-zero direction {what}"), format!("{a:?}"))
                })
            };
            (
                norm([vals[0], vals[1], vals[2]], "u")?,
                norm([vals[3], vals[4], vals[5]], "v")?,
                vals[6],
            )
        };
        if filters.admit(u, v, y, &mut rep) {
            data.push(u, v, y);
        }
    }
    Ok((data, rep))
}

/// A colour channel of a MERL file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Channel {
    /// Red (scale 1/1500).
    Red,
    /// Green (scale 1.15/1500).
    Green,
    /// Blue (scale 1.66/1500).
    Blue,
}

impl Channel {
    fn index(self) -> usize {
        self as usize
    }
    fn scale(self) -> f64 {
        match self {
            Channel::Red => 1.0 / 1500.0,
            Channel::Green => 1.15 / 1500.0,
            Channel::Blue => 1.66 / 1500.0,
        }
    }
}

/// A MERL BRDF table in memory (unscaled entries, as in the file).
#[derive(Clone, Debug, PartialEq)]
pub struct MerlBrdf {
    /// `(n_theta_h, n_theta_d, n_phi_d)`; `(90, 90, 180)` for the real database.
    pub dims: (usize, usize, usize),
    /// `3 * N` entries: red, green, blue blocks.
    pub table: Vec<f64>,
}

fn rotate(v: [f64; 3], axis: [f64; 3], angle: f64) -> [f64; 3] {
    let (s, c) = angle.sin_cos();
    let dot = axis[0] * v[0] + axis[1] * v[1] + axis[2] * v[2];
    let cross = [
        axis[1] * v[2] - axis[2] * v[1],
        axis[2] * v[0] - axis[0] * v[2],
        axis[0] * v[1] - axis[1] * v[0],
    ];
    [
        v[0] * c + axis[0] * dot * (1.0 - c) + cross[0] * s,
        v[1] * c + axis[1] * dot * (1.0 - c) + cross[1] * s,
        v[2] * c + axis[2] * dot * (1.0 - c) + cross[2] * s,
    ]
}

/// Checks a MERL header and returns the dims and the file size they imply.
fn merl_header(head: &[u8], path: &Path) -> Result<((usize, usize, usize), u64), DataError> {
    let berr = |message: String| DataError::Binary {
        path: path.to_path_buf(),
        message,
    };
    if head.len() < 12 {
        return Err(berr(format!(
            "expected a 12-byte header of three int32 dims, found {} bytes",
            head.len()
        )));
    }
    let dim = |k: usize| {
        let mut b = [0u8; 4];
        b.copy_from_slice(&head[4 * k..4 * k + 4]);
        i32::from_le_bytes(b)
    };
    let (a, b, c) = (dim(0), dim(1), dim(2));
    let ok = |d: i32| d > 0 && d as usize <= MAX_MERL_DIM;
    if !(ok(a) && ok(b) && ok(c)) {
        return Err(berr(format!(
            "expected three dims in [1, {MAX_MERL_DIM}] (MAX_MERL_DIM; 90, 90, 180 in the real \
             database), found ({a}, {b}, {c})"
        )));
    }
    // At most 4096^3 * 24 + 12 bytes: no overflow in u64.
    let n = a as u64 * b as u64 * c as u64;
    let want = 12 + 3 * n * 8;
    if want > MAX_MERL_BYTES {
        return Err(DataError::Limit {
            path: path.to_path_buf(),
            line: 0,
            message: format!(
                "dims ({a}, {b}, {c}) imply {want} bytes; expected at most {MAX_MERL_BYTES} \
                 (MAX_MERL_BYTES)"
            ),
        });
    }
    Ok(((a as usize, b as usize, c as usize), want))
}

impl MerlBrdf {
    /// Reads a MERL binary file (format in the module docs). The header is checked before the
    /// table is read, and at most the size it implies plus one byte is read.
    pub fn read(path: impl AsRef<Path>) -> Result<Self, DataError> {
        let path = path.as_ref();
        let mut file = open(path)?;
        let mut head = Vec::with_capacity(12);
        (&mut file)
            .take(12)
            .read_to_end(&mut head)
            .map_err(|e| io_err(path, e))?;
        let (_, want) = merl_header(&head, path)?;
        let mut bytes = Vec::with_capacity(want as usize);
        bytes.extend_from_slice(&head);
        file.take(want - 12 + 1)
            .read_to_end(&mut bytes)
            .map_err(|e| io_err(path, e))?;
        if bytes.len() as u64 > want {
            return Err(DataError::Binary {
                path: path.to_path_buf(),
                message: format!("expected {want} bytes for the dims in the header, found more"),
            });
        }
        Self::from_bytes(&bytes, path)
    }

    /// Parses a MERL table already in memory; `path` is only used in errors.
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<Self, DataError> {
        let (dims, want) = merl_header(bytes, path)?;
        if bytes.len() as u64 != want {
            return Err(DataError::Binary {
                path: path.to_path_buf(),
                message: format!(
                    "expected {want} bytes for dims ({}, {}, {}), found {}",
                    dims.0,
                    dims.1,
                    dims.2,
                    bytes.len()
                ),
            });
        }
        let table = bytes[12..]
            .chunks_exact(8)
            .map(|ch| {
                let mut b = [0u8; 8];
                b.copy_from_slice(ch);
                f64::from_le_bytes(b)
            })
            .collect();
        Ok(MerlBrdf { dims, table })
    }

    /// Serialises the table in the MERL binary format.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(12 + 8 * self.table.len());
        for d in [self.dims.0, self.dims.1, self.dims.2] {
            out.extend_from_slice(&(d as i32).to_le_bytes());
        }
        for v in &self.table {
            out.extend_from_slice(&v.to_le_bytes());
        }
        out
    }

    fn cells(&self) -> usize {
        self.dims.0 * self.dims.1 * self.dims.2
    }

    /// Table index of directions `u` (incident), `v` (exitant), unit vectors, z = normal.
    ///
    /// # Panics
    /// When a dim is 0 or the table is shorter than `3 *` the product of the dims (possible
    /// only for a value built by hand: [`MerlBrdf::read`] and [`MerlBrdf::from_bytes`] check).
    pub fn index(&self, u: [f64; 3], v: [f64; 3]) -> usize {
        let (nth, ntd, npd) = self.dims;
        let h = [u[0] + v[0], u[1] + v[1], u[2] + v[2]];
        let hl = (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]).sqrt();
        let h = if hl > 0.0 {
            [h[0] / hl, h[1] / hl, h[2] / hl]
        } else {
            [0.0, 0.0, 1.0]
        };
        let theta_h = h[2].clamp(-1.0, 1.0).acos();
        let phi_h = h[1].atan2(h[0]);
        let t = rotate(u, [0.0, 0.0, 1.0], -phi_h);
        let diff = rotate(t, [0.0, 1.0, 0.0], -theta_h);
        let theta_d = diff[2].clamp(-1.0, 1.0).acos();
        let mut phi_d = diff[1].atan2(diff[0]);
        if phi_d < 0.0 {
            phi_d += PI;
        }
        let th = if theta_h <= 0.0 {
            0
        } else {
            ((theta_h / FRAC_PI_2).sqrt() * nth as f64) as usize
        };
        let td = (theta_d / FRAC_PI_2 * ntd as f64) as usize;
        let pd = (phi_d / PI * npd as f64) as usize;
        pd.min(npd - 1) + npd * (td.min(ntd - 1) + ntd * th.min(nth - 1))
    }

    /// The scaled value of `channel` at directions `u`, `v`; negative means below the horizon.
    pub fn lookup(&self, channel: Channel, u: [f64; 3], v: [f64; 3]) -> f64 {
        self.table[channel.index() * self.cells() + self.index(u, v)] * channel.scale()
    }

    /// Samples `channel` at the given direction pairs, applying `filters` (negative entries
    /// count as below the horizon).
    pub fn sample_at(
        &self,
        channel: Channel,
        dirs: &[([f64; 3], [f64; 3])],
        filters: &Filters,
    ) -> (DataSet, FilterReport) {
        let mut data = DataSet::with_capacity(dirs.len());
        let mut rep = FilterReport::default();
        for &(u, v) in dirs {
            let y = self.lookup(channel, u, v);
            if filters.admit_marked(u, v, y, y < 0.0, &mut rep) {
                data.push(u, v, y);
            }
        }
        (data, rep)
    }

    /// Samples `channel` on the table's own grid: one sample per cell, at the cell's centre
    /// in `(theta_h, theta_d, phi_d)` with `phi_h = 0`, applying `filters` (cells whose
    /// directions fall below the horizon or hold negative entries, which mark samples below the
    /// horizon, are dropped when `filters.drop_below_horizon`).
    pub fn sample_grid(&self, channel: Channel, filters: &Filters) -> (DataSet, FilterReport) {
        let (nth, ntd, npd) = self.dims;
        let mut data = DataSet::with_capacity(self.cells());
        let mut rep = FilterReport::default();
        let base = channel.index() * self.cells();
        for ih in 0..nth {
            let s = (ih as f64 + 0.5) / nth as f64;
            let theta_h = s * s * FRAC_PI_2;
            for id in 0..ntd {
                let theta_d = (id as f64 + 0.5) / ntd as f64 * FRAC_PI_2;
                for ip in 0..npd {
                    let phi_d = (ip as f64 + 0.5) / npd as f64 * PI;
                    let diff = dir_from_angles(theta_d, phi_d);
                    let u = rotate(diff, [0.0, 1.0, 0.0], theta_h);
                    let h = dir_from_angles(theta_h, 0.0);
                    let dot = u[0] * h[0] + u[1] * h[1] + u[2] * h[2];
                    let v = [
                        2.0 * dot * h[0] - u[0],
                        2.0 * dot * h[1] - u[1],
                        2.0 * dot * h[2] - u[2],
                    ];
                    let idx = ip + npd * (id + ntd * ih);
                    let y = self.table[base + idx] * channel.scale();
                    if filters.admit_marked(u, v, y, y < 0.0, &mut rep) {
                        data.push(u, v, y);
                    }
                }
            }
        }
        (data, rep)
    }
}

/// Reads a MERL file and samples `channel` on its own grid (see [`MerlBrdf::sample_grid`]).
pub fn read_merl(
    path: impl AsRef<Path>,
    channel: Channel,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    Ok(MerlBrdf::read(path)?.sample_grid(channel, filters))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p() -> &'static Path {
        Path::new("t.csv")
    }

    #[test]
    fn csv_vectors_and_angles() {
        let text = "# comment\nux, uy, uz, vx, vy, vz, value\n0,0,2,0,0,1,0.5\n0,0,1,0,0,-1,0.2\n";
        let (d, rep) = parse_csv(text, p(), &Filters::default()).unwrap();
        assert_eq!(d.len(), 1);
        assert_eq!(d.u(0), [0.0, 0.0, 1.0]);
        assert_eq!(rep.below_horizon, 1);
        let text = "theta_i,phi_i,theta_o,phi_o,value,extra\n90,0,0,0,0.25,1\n";
        let (d, _) = parse_csv(text, p(), &Filters::default()).unwrap();
        assert!((d.u(0)[0] - 1.0).abs() < 1e-15 && d.u(0)[2].abs() < 1e-15);
        assert_eq!(d.value(0), 0.25);
    }

    #[test]
    fn csv_errors_name_line_and_expectation() {
        let e = parse_csv("a,b\n1,2\n", p(), &Filters::default()).unwrap_err();
        assert!(matches!(e, DataError::Parse { line: 1, .. }), "{e}");
        let e = parse_csv(
            "ux,uy,uz,vx,vy,vz,value\n0,0,1,0,0,1,x\n",
            p(),
            &Filters::default(),
        )
        .unwrap_err();
        let msg = e.to_string();
        assert!(
            msg.contains("t.csv:2") && msg.contains("column `value`"),
            "{msg}"
        );
        let e = parse_csv(
            "ux,uy,uz,vx,vy,vz,value\n0,0,1,0,0,1\n",
            p(),
            &Filters::default(),
        )
        .unwrap_err();
        assert!(e.to_string().contains("7 comma-separated fields"), "{e}");
        let e = parse_csv(
            "ux,uy,uz,vx,vy,vz,value\n0,0,0,0,0,1,1\n",
            p(),
            &Filters::default(),
        )
        .unwrap_err();
        assert!(e.to_string().contains("non-zero direction u"), "{e}");
        assert!(matches!(
            parse_csv("", p(), &Filters::default()),
            Err(DataError::Parse { line: 0, .. })
        ));
    }

    #[test]
    fn csv_round_trip() {
        let params = crate::named_params("cross").unwrap();
        let d = crate::synthetic(&params, 50, 0.1, 9);
        let mut buf = Vec::new();
        d.write_csv(&mut buf).unwrap();
        let (back, _) =
            parse_csv(std::str::from_utf8(&buf).unwrap(), p(), &Filters::none()).unwrap();
        assert_eq!(back.len(), 50);
        for i in 0..50 {
            assert_eq!(back.value(i), d.value(i));
            for k in 0..3 {
                assert!((back.u(i)[k] - d.u(i)[k]).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn cornell_errors() {
        let path = Path::new("x.brdf");
        let f = Filters::default();
        let e = parse_cornell("# only comments\n", path, 550.0, &f).unwrap_err();
        assert!(matches!(e, DataError::Parse { line: 0, .. }), "{e}");
        let e = parse_cornell("two\n", path, 550.0, &f).unwrap_err();
        assert!(matches!(e, DataError::Parse { line: 1, .. }), "{e}");
        let e = parse_cornell("2\n500 550\n0 0 0 0 1\n", path, 550.0, &f).unwrap_err();
        assert!(
            e.to_string().contains("x.brdf:3: expected 6 numbers"),
            "{e}"
        );
        let e = parse_cornell("2\n500 550\n0 0 0 0 1 q\n", path, 550.0, &f).unwrap_err();
        assert!(matches!(e, DataError::Parse { line: 3, .. }), "{e}");
        let e = parse_cornell("2\n500 600\n", path, 550.0, &f).unwrap_err();
        assert!(matches!(e, DataError::NoWavelength { .. }), "{e}");
        let e = parse_cornell("2\n500\n", path, 550.0, &f).unwrap_err();
        assert!(e.to_string().contains("end of file after 1"), "{e}");
        let (d, rep) = parse_cornell("2\n500\n550\n0.1 0 0.1 3.14 1 2\n", path, 550.0, &f).unwrap();
        assert_eq!((d.len(), rep.read), (1, 1));
        assert_eq!(d.value(0), 2.0);
    }
}
