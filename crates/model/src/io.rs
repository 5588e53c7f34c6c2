//! Readers for measured data.
//!
//! # Cornell text format (`*.brdf`)
//! Comment lines start with `#`; blank lines are ignored. The first number is the count of
//! wavelengths `W`, then `W` wavelengths in nm (over any number of lines), then one sample per
//! line: `theta_i phi_i theta_s phi_s` in radians followed by `W` values. Angles become
//! vectors pointing away from the surface, `(sin t cos p, sin t sin p, cos t)`; the files put
//! the specular direction at `phi_s = phi_i + pi`, which is where a lobe with `Cx = Cy < 0`
//! peaks. [`read_cornell`] selects one wavelength (550 nm by default in the CLI).
//!
//! # CSV format
//! A header line names the columns (comma-separated, case-insensitive, surrounding spaces
//! ignored, extra columns ignored), then one sample per line. Either
//! - `ux,uy,uz,vx,vy,vz,value`: direction vectors (normalised on reading; both point away
//!   from the surface, z = normal), or
//! - `theta_i,phi_i,theta_o,phi_o,value`: angles in **degrees** (theta from the normal).
//!
//! Lines starting with `#` and blank lines are skipped. `nan`/`inf` values parse and are then
//! handled by the [`Filters`]. [`DataSet::write_csv`] writes the vector form.
//!
//! # MERL binary format
//! Three little-endian `i32` dimensions `(n_theta_h, n_theta_d, n_phi_d)` — `(90, 90, 180)`
//! in every file of the real database (34,992,012 bytes) — then `3 * N` little-endian `f64`
//! (`N` = product of the dims): the red, green and blue blocks. The reader accepts other
//! dimensions so tests can write small files. Index
//! `phi_d_idx + n_phi_d * (theta_d_idx + n_theta_d * theta_h_idx)` with
//! `theta_h_idx = floor(n_theta_h * sqrt(theta_h / (pi/2)))`, `theta_d_idx` linear over
//! `[0, pi/2)`, `phi_d` folded into `[0, pi)` by reciprocity. Channel scales: red 1/1500,
//! green 1.15/1500, blue 1.66/1500. Negative entries mark samples below the horizon.

use crate::data::{DataSet, FilterReport, Filters};
use std::f64::consts::{FRAC_PI_2, PI};
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
}

fn read_text(path: &Path) -> Result<String, DataError> {
    std::fs::read_to_string(path).map_err(|source| DataError::Io {
        path: path.to_path_buf(),
        source,
    })
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
/// file within 1e-6 nm), applying `filters`.
pub fn read_cornell(
    path: impl AsRef<Path>,
    wavelength_nm: f64,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    let path = path.as_ref();
    let text = read_text(path)?;
    parse_cornell(&text, path, wavelength_nm, filters)
}

/// Parses Cornell text already in memory; `path` is only used in errors.
pub fn parse_cornell(
    text: &str,
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
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let (ln, first) = lines
        .next()
        .ok_or_else(|| perr(0, "the number of wavelengths".into(), "end of file".into()))?;
    let nwl: usize = match first.split_whitespace().collect::<Vec<_>>()[..] {
        [tok] => tok.parse().ok().filter(|&n: &usize| n > 0),
        _ => None,
    }
    .ok_or_else(|| {
        perr(
            ln,
            "the number of wavelengths (a positive integer alone on its line)".into(),
            short(first),
        )
    })?;
    let mut wls = Vec::with_capacity(nwl);
    while wls.len() < nwl {
        let (ln, l) = lines.next().ok_or_else(|| {
            perr(
                0,
                format!("{nwl} wavelengths"),
                format!("end of file after {}", wls.len()),
            )
        })?;
        for tok in l.split_whitespace() {
            let w: f64 = tok
                .parse()
                .map_err(|_| perr(ln, "a wavelength in nm".into(), short(tok)))?;
            wls.push(w);
        }
        if wls.len() > nwl {
            return Err(perr(
                ln,
                format!("{nwl} wavelengths"),
                format!("{} numbers", wls.len()),
            ));
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
    let mut row = Vec::with_capacity(width);
    for (ln, l) in lines {
        row.clear();
        for tok in l.split_whitespace() {
            let v: f64 = tok.parse().map_err(|_| {
                perr(
                    ln,
                    format!("a number (sample row: 4 angles in radians and {nwl} values)"),
                    short(tok),
                )
            })?;
            row.push(v);
        }
        if row.len() != width {
            return Err(perr(
                ln,
                format!("{width} numbers (4 angles in radians and {nwl} values)"),
                format!("{} numbers", row.len()),
            ));
        }
        let u = dir_from_angles(row[0], row[1]);
        let v = dir_from_angles(row[2], row[3]);
        let y = row[4 + col];
        if filters.admit(u, v, y, &mut rep) {
            data.push(u, v, y);
        }
    }
    Ok((data, rep))
}

/// Reads a CSV file (format in the module docs), applying `filters`.
pub fn read_csv(
    path: impl AsRef<Path>,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    let path = path.as_ref();
    let text = read_text(path)?;
    parse_csv(&text, path, filters)
}

/// Parses CSV already in memory; `path` is only used in errors.
pub fn parse_csv(
    text: &str,
    path: &Path,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    let perr = |line: usize, expected: String, found: String| DataError::Parse {
        path: path.to_path_buf(),
        line,
        expected,
        found,
    };
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    const HEADER: &str =
        "a header naming ux,uy,uz,vx,vy,vz,value or theta_i,phi_i,theta_o,phi_o,value";
    let (hl, header) = lines
        .next()
        .ok_or_else(|| perr(0, HEADER.into(), "end of file".into()))?;
    let names: Vec<String> = header
        .split(',')
        .map(|s| s.trim().to_ascii_lowercase())
        .collect();
    let find = |n: &str| names.iter().position(|h| h == n);
    let vec_cols: Option<Vec<usize>> = ["ux", "uy", "uz", "vx", "vy", "vz", "value"]
        .iter()
        .map(|n| find(n))
        .collect();
    let ang_cols: Option<Vec<usize>> = ["theta_i", "phi_i", "theta_o", "phi_o", "value"]
        .iter()
        .map(|n| find(n))
        .collect();
    let (cols, angles) = match (vec_cols, ang_cols) {
        (Some(c), _) => (c, false),
        (None, Some(c)) => (c, true),
        (None, None) => return Err(perr(hl, HEADER.into(), short(header))),
    };
    let mut data = DataSet::new();
    let mut rep = FilterReport::default();
    let mut fields: Vec<f64> = Vec::with_capacity(names.len());
    for (ln, l) in lines {
        fields.clear();
        for (k, tok) in l.split(',').enumerate() {
            let tok = tok.trim();
            let v: f64 = tok.parse().map_err(|_| {
                perr(
                    ln,
                    format!("a number in column `{}`", names.get(k).map_or("?", |s| s)),
                    short(tok),
                )
            })?;
            fields.push(v);
        }
        if fields.len() != names.len() {
            return Err(perr(
                ln,
                format!("{} comma-separated fields as in the header", names.len()),
                format!("{} fields", fields.len()),
            ));
        }
        let get = |k: usize| fields[cols[k]];
        let (u, v, y) = if angles {
            (
                dir_from_angles(get(0).to_radians(), get(1).to_radians()),
                dir_from_angles(get(2).to_radians(), get(3).to_radians()),
                get(4),
            )
        } else {
            let norm = |a: [f64; 3], what: &str| -> Result<[f64; 3], DataError> {
                let len = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
                if len > 0.0 && len.is_finite() {
                    Ok([a[0] / len, a[1] / len, a[2] / len])
                } else {
                    Err(perr(
                        ln,
                        format!("a non-zero finite direction {what}"),
                        format!("{a:?}"),
                    ))
                }
            };
            (
                norm([get(0), get(1), get(2)], "u")?,
                norm([get(3), get(4), get(5)], "v")?,
                get(6),
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

impl MerlBrdf {
    /// Reads a MERL binary file (format in the module docs).
    pub fn read(path: impl AsRef<Path>) -> Result<Self, DataError> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|source| DataError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::from_bytes(&bytes, path)
    }

    /// Parses a MERL table already in memory; `path` is only used in errors.
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<Self, DataError> {
        let berr = |message: String| DataError::Binary {
            path: path.to_path_buf(),
            message,
        };
        if bytes.len() < 12 {
            return Err(berr(format!(
                "expected a 12-byte header of three int32 dims, found {} bytes",
                bytes.len()
            )));
        }
        let dim =
            |k: usize| i32::from_le_bytes(bytes[4 * k..4 * k + 4].try_into().unwrap_or([0; 4]));
        let (a, b, c) = (dim(0), dim(1), dim(2));
        if a <= 0 || b <= 0 || c <= 0 || a > 4096 || b > 4096 || c > 4096 {
            return Err(berr(format!(
                "expected positive dims (90, 90, 180 in the real database), found ({a}, {b}, {c})"
            )));
        }
        let n = a as usize * b as usize * c as usize;
        let want = 12 + 3 * n * 8;
        if bytes.len() != want {
            return Err(berr(format!(
                "expected {want} bytes for dims ({a}, {b}, {c}), found {}",
                bytes.len()
            )));
        }
        let table = bytes[12..]
            .chunks_exact(8)
            .map(|ch| f64::from_le_bytes(ch.try_into().unwrap_or([0; 8])))
            .collect();
        Ok(MerlBrdf {
            dims: (a as usize, b as usize, c as usize),
            table,
        })
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

    /// Samples `channel` at the given direction pairs, applying `filters`.
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
            if filters.admit(u, v, y, &mut rep) {
                data.push(u, v, y);
            }
        }
        (data, rep)
    }

    /// Samples `channel` on the table's own grid: one sample per cell, at the cell's centre
    /// in `(theta_h, theta_d, phi_d)` with `phi_h = 0`, applying `filters` (cells whose
    /// directions fall below the horizon or hold negative entries are dropped by default).
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
                    if filters.admit(u, v, y, &mut rep) {
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
        assert!(e.to_string().contains("non-zero finite direction u"), "{e}");
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
