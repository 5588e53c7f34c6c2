//! The MERL binary table: reading, writing, lookup and sampling ([`MerlBrdf`], [`Channel`]).

use super::FormatError;
use super::limits::{MAX_MERL_BYTES, MAX_MERL_DIM};
use super::{DataError, dir_from_angles, io_err, open};
use brdf_model::{DataSet, FilterReport, Filters};
use std::f64::consts::{FRAC_PI_2, PI};
use std::io::Read;
use std::path::Path;

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
    /// Every channel, in file order.
    pub const ALL: [Channel; 3] = [Channel::Red, Channel::Green, Channel::Blue];

    /// The channel's name as in specs and on the command line: `red`, `green` or `blue`.
    pub fn name(self) -> &'static str {
        match self {
            Channel::Red => "red",
            Channel::Green => "green",
            Channel::Blue => "blue",
        }
    }

    /// Position of the channel in a file's channel order (red 0, green 1, blue 2).
    pub(super) fn index(self) -> usize {
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

impl std::fmt::Display for Channel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Channel {
    type Err = FormatError;

    /// A channel by name (`red`, `green`, `blue`; any case, surrounding spaces ignored); an
    /// unknown name is an error listing the names.
    fn from_str(s: &str) -> Result<Self, FormatError> {
        let t = s.trim();
        Channel::ALL
            .into_iter()
            .find(|c| c.name().eq_ignore_ascii_case(t))
            .ok_or_else(|| FormatError::UnknownChannel {
                found: s.to_string(),
            })
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
