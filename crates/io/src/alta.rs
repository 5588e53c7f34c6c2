//! The ALTA text reader (format, parameterisations and conversions in the crate
//! module docs): [`AltaInput`], [`AltaOutput`] and the header and sample parsing behind
//! [`Format::Alta`](super::Format::Alta).

use super::lines::{LineSource, Sample, read_samples, short};
use super::merl::Channel;
use super::{DEFAULT_CHANNEL, DataError, dir_from_angles, normalise};
use brdf_model::{DataSet, FilterReport, Filters};
use std::io::BufRead;

/// Smallest incident cosine `cos(theta_in)` by which an `INV_STERADIAN_COSINE_FACTOR` value is
/// divided: 1e-9 (`theta_in` within 1e-9 rad of grazing; `cos(pi/2)` rounds to 6.1e-17, not
/// 0). A sample below it (also below the horizon, or a NaN cosine) has no BRDF value: it is
/// marked below the horizon, so the default filters drop it and count it there; filters that
/// keep below-horizon samples get a NaN value (see the module docs).
pub const ALTA_MIN_COSINE: f64 = 1e-9;

/// An input parameterisation (`#PARAM_IN`) of ALTA's text format that this reader converts
/// to directions. ALTA (`sources/core/params.h`, enum `params::input`) names more; the others
/// are refused. The names are ALTA's; angles are in radians.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AltaInput {
    /// `ISOTROPIC_TL_TV_PROJ_DPHI`: `[theta_l, theta_v cos(dphi), theta_v sin(dphi)]`, the
    /// parameterisation of ALTA's retro-reflection measurements.
    IsotropicTlTvProjDphi,
    /// `ISOTROPIC_TV_TL_DPHI`: `[theta_v, theta_l, dphi]`.
    IsotropicTvTlDphi,
    /// `RUSIN_TH_TD_PD`: Rusinkiewicz's half/difference angles `[theta_h, theta_d, phi_d]`
    /// (isotropic: `phi_h = 0`).
    RusinThTdPd,
    /// `RUSIN_TH_PH_TD_PD`: `[theta_h, phi_h, theta_d, phi_d]`.
    RusinThPhTdPd,
    /// `SPHERICAL_TL_PL_TV_PV`: `[theta_l, phi_l, theta_v, phi_v]`.
    SphericalTlPlTvPv,
    /// `CARTESIAN`: `[V.x, V.y, V.z, L.x, L.y, L.z]`, the view vector first.
    Cartesian,
}

impl AltaInput {
    /// Every supported input parameterisation.
    pub const ALL: [AltaInput; 6] = [
        AltaInput::IsotropicTlTvProjDphi,
        AltaInput::IsotropicTvTlDphi,
        AltaInput::RusinThTdPd,
        AltaInput::RusinThPhTdPd,
        AltaInput::SphericalTlPlTvPv,
        AltaInput::Cartesian,
    ];

    /// ALTA's name, as in `#PARAM_IN`.
    pub fn name(self) -> &'static str {
        match self {
            AltaInput::IsotropicTlTvProjDphi => "ISOTROPIC_TL_TV_PROJ_DPHI",
            AltaInput::IsotropicTvTlDphi => "ISOTROPIC_TV_TL_DPHI",
            AltaInput::RusinThTdPd => "RUSIN_TH_TD_PD",
            AltaInput::RusinThPhTdPd => "RUSIN_TH_PH_TD_PD",
            AltaInput::SphericalTlPlTvPv => "SPHERICAL_TL_PL_TV_PV",
            AltaInput::Cartesian => "CARTESIAN",
        }
    }

    /// The parameterisation named `name` (exact spelling, as ALTA compares), if supported.
    pub fn from_name(name: &str) -> Option<Self> {
        AltaInput::ALL.into_iter().find(|p| p.name() == name)
    }

    /// How many numbers a sample's input has (the `N` of `#DIM N P`).
    pub fn dimension(self) -> usize {
        match self {
            AltaInput::IsotropicTlTvProjDphi
            | AltaInput::IsotropicTvTlDphi
            | AltaInput::RusinThTdPd => 3,
            AltaInput::RusinThPhTdPd | AltaInput::SphericalTlPlTvPv => 4,
            AltaInput::Cartesian => 6,
        }
    }

    /// True when the parameterisation has no absolute azimuth (the material is isotropic):
    /// the reader then rotates each pair about the normal so that the incident direction lies
    /// in the x-z plane (`phi_in = 0`, `u.y = 0`, `u.x >= 0`).
    pub fn is_isotropic(self) -> bool {
        matches!(
            self,
            AltaInput::IsotropicTlTvProjDphi
                | AltaInput::IsotropicTvTlDphi
                | AltaInput::RusinThTdPd
        )
    }

    /// The directions `(u, v)` of one sample's input numbers `x` (at least
    /// [`AltaInput::dimension`] of them): `u` incident (ALTA's light `L`), `v` exitant (ALTA's
    /// view `V`), unit vectors pointing away from the surface, z = normal, rotated into the
    /// incidence plane for an isotropic parameterisation. `None` when `x` is too short or a
    /// `CARTESIAN` vector is zero. Non-finite numbers give non-finite components (the filters
    /// count them).
    pub fn directions(self, x: &[f64]) -> Option<([f64; 3], [f64; 3])> {
        if x.len() < self.dimension() {
            return None;
        }
        // As ALTA's params::to_cartesian: `view` is its first vector, `light` its second.
        let (light, view) = match self {
            AltaInput::IsotropicTlTvProjDphi => {
                let theta = x[1].hypot(x[2]);
                let view = if theta > 0.0 {
                    let s = theta.sin();
                    [x[1] / theta * s, x[2] / theta * s, theta.cos()]
                } else {
                    [0.0, 0.0, theta.cos()]
                };
                (dir_from_angles(x[0], 0.0), view)
            }
            AltaInput::IsotropicTvTlDphi => {
                (dir_from_angles(x[1], x[2]), dir_from_angles(x[0], 0.0))
            }
            AltaInput::RusinThTdPd => half_diff(x[0], 0.0, x[1], x[2]),
            AltaInput::RusinThPhTdPd => half_diff(x[0], x[1], x[2], x[3]),
            AltaInput::SphericalTlPlTvPv => {
                (dir_from_angles(x[0], x[1]), dir_from_angles(x[2], x[3]))
            }
            AltaInput::Cartesian => (
                normalise([x[3], x[4], x[5]])?,
                normalise([x[0], x[1], x[2]])?,
            ),
        };
        Some(if self.is_isotropic() {
            into_incidence_plane(light, view)
        } else {
            (light, view)
        })
    }
}

/// Rusinkiewicz's half/difference angles to `(light, view)`: the difference vector is turned
/// by `theta_h` about y and `phi_h` about z (this is the view vector), the light vector is its
/// mirror image about the half vector.
fn half_diff(theta_h: f64, phi_h: f64, theta_d: f64, phi_d: f64) -> ([f64; 3], [f64; 3]) {
    let half = dir_from_angles(theta_h, phi_h);
    let d = dir_from_angles(theta_d, phi_d);
    let (sh, ch) = theta_h.sin_cos();
    let d = [d[0] * ch + d[2] * sh, d[1], d[2] * ch - d[0] * sh];
    let (sp, cp) = phi_h.sin_cos();
    let view = [d[0] * cp - d[1] * sp, d[0] * sp + d[1] * cp, d[2]];
    let dot = view[0] * half[0] + view[1] * half[1] + view[2] * half[2];
    let light = [
        2.0 * dot * half[0] - view[0],
        2.0 * dot * half[1] - view[1],
        2.0 * dot * half[2] - view[2],
    ];
    (light, view)
}

/// Rotates `u` and `v` about the normal so that `u` lies in the x-z plane with `u.x >= 0`
/// (nothing to do when `u` is the normal or not finite).
fn into_incidence_plane(u: [f64; 3], v: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let r = u[0].hypot(u[1]);
    if !(r > 0.0 && r.is_finite()) {
        return (u, v);
    }
    let (c, s) = (u[0] / r, u[1] / r);
    (
        [r, 0.0, u[2]],
        [c * v[0] + s * v[1], c * v[1] - s * v[0], v[2]],
    )
}

/// An output parameterisation (`#PARAM_OUT`) of ALTA's text format that this reader accepts
/// (ALTA's enum `params::output`; `ENERGY`, `XYZ_COLOR` and unknown outputs are refused). In
/// specs its name is written as in the header, e.g. `param_out = "INV_STERADIAN"`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "SCREAMING_SNAKE_CASE")]
pub enum AltaOutput {
    /// `INV_STERADIAN`: the BRDF in 1/sr, one number.
    InvSteradian,
    /// `INV_STERADIAN_COSINE_FACTOR`: the BRDF times `cos(theta_in)`, one number; the reader
    /// divides by `cos(theta_in) = u.z`.
    InvSteradianCosineFactor,
    /// `RGB_COLOR`: the BRDF in 1/sr for red, green and blue, three numbers; the format's
    /// `channel` option picks one.
    RgbColor,
}

impl AltaOutput {
    /// Every supported output parameterisation.
    pub const ALL: [AltaOutput; 3] = [
        AltaOutput::InvSteradian,
        AltaOutput::InvSteradianCosineFactor,
        AltaOutput::RgbColor,
    ];

    /// ALTA's name, as in `#PARAM_OUT`.
    pub fn name(self) -> &'static str {
        match self {
            AltaOutput::InvSteradian => "INV_STERADIAN",
            AltaOutput::InvSteradianCosineFactor => "INV_STERADIAN_COSINE_FACTOR",
            AltaOutput::RgbColor => "RGB_COLOR",
        }
    }

    /// The parameterisation named `name` (exact spelling), if supported.
    pub fn from_name(name: &str) -> Option<Self> {
        AltaOutput::ALL.into_iter().find(|p| p.name() == name)
    }

    /// How many numbers a sample's output has (the `P` of `#DIM N P`).
    pub fn dimension(self) -> usize {
        match self {
            AltaOutput::InvSteradian | AltaOutput::InvSteradianCosineFactor => 1,
            AltaOutput::RgbColor => 3,
        }
    }

    /// True when the values are the BRDF times `cos(theta_in)`.
    pub fn is_cosine_weighted(self) -> bool {
        self == AltaOutput::InvSteradianCosineFactor
    }
}

impl std::fmt::Display for AltaOutput {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

fn names<T: Copy>(all: &[T], name: fn(T) -> &'static str) -> String {
    all.iter().map(|&p| name(p)).collect::<Vec<_>>().join(", ")
}

/// The header keys the reader interprets; any other `#KEY` line (`#SAMPLE`, `#URL`, `#CMD`,
/// ...) is kept as a comment.
const KEYS: [&str; 5] = ["DIM", "PARAM_IN", "PARAM_OUT", "VS", "FORMAT"];

/// What the header says, each with the line it was on.
#[derive(Default)]
struct Header {
    dim: Option<(usize, usize, usize)>,
    param_in: Option<(usize, AltaInput)>,
    param_out: Option<(usize, AltaOutput)>,
    vs: Option<(usize, usize)>,
    format: Option<usize>,
}

/// Reads the header up to the first data line (pushed back), `#ALTA END HEADER` or the end.
fn read_header<R: BufRead>(lines: &mut LineSource<'_, R>) -> Result<Header, DataError> {
    let path = lines.path();
    let perr = |line: usize, expected: String, found: String| DataError::Parse {
        path: path.to_path_buf(),
        line,
        expected,
        found,
    };
    let mut h = Header::default();
    let mut seen: [usize; 5] = [0; 5];
    while let Some((ln, l)) = lines.next_line_with_comments()? {
        let Some(rest) = l.strip_prefix('#') else {
            lines.push_back();
            break;
        };
        // `#` followed by a letter is a header line, anything else a comment (ALTA's rule).
        if !rest.starts_with(|c: char| c.is_ascii_alphabetic()) {
            continue;
        }
        let (key, value) = rest.split_once(char::is_whitespace).unwrap_or((rest, ""));
        let value = value.trim();
        if key == "ALTA" {
            if value.split_whitespace().eq(["END", "HEADER"]) {
                break;
            }
            continue;
        }
        let Some(k) = KEYS.iter().position(|&x| x == key) else {
            continue;
        };
        if seen[k] > 0 {
            return Err(perr(
                ln,
                format!(
                    "each header key once (`#{key}` is already on line {})",
                    seen[k]
                ),
                short(l),
            ));
        }
        seen[k] = ln;
        let one_word = {
            let mut w = value.split_whitespace();
            match (w.next(), w.next()) {
                (Some(a), None) => Some(a),
                _ => None,
            }
        };
        match key {
            "DIM" => {
                let mut w = value.split_whitespace().map(|t| t.parse::<usize>().ok());
                match (w.next(), w.next(), w.next()) {
                    (Some(Some(n)), Some(Some(p)), None) if n > 0 && p > 0 => {
                        h.dim = Some((ln, n, p));
                    }
                    _ => {
                        return Err(perr(
                            ln,
                            "`#DIM N P`: two positive integers (N input and P output numbers \
                             per sample)"
                                .into(),
                            short(l),
                        ));
                    }
                }
            }
            "PARAM_IN" => {
                let p = one_word.and_then(AltaInput::from_name).ok_or_else(|| {
                    perr(
                        ln,
                        format!(
                            "`#PARAM_IN` naming a supported input parameterisation ({})",
                            names(&AltaInput::ALL, AltaInput::name)
                        ),
                        short(l),
                    )
                })?;
                h.param_in = Some((ln, p));
            }
            "PARAM_OUT" => {
                let p = one_word.and_then(AltaOutput::from_name).ok_or_else(|| {
                    perr(
                        ln,
                        format!(
                            "`#PARAM_OUT` naming a supported output parameterisation ({})",
                            names(&AltaOutput::ALL, AltaOutput::name)
                        ),
                        short(l),
                    )
                })?;
                h.param_out = Some((ln, p));
            }
            "VS" => {
                let vs = one_word
                    .and_then(|w| w.parse::<usize>().ok())
                    .filter(|&v| v <= 2)
                    .ok_or_else(|| {
                        perr(
                            ln,
                            "`#VS 0`, `#VS 1` or `#VS 2` (no, one or two confidence-interval \
                             numbers after the values)"
                                .into(),
                            short(l),
                        )
                    })?;
                h.vs = Some((ln, vs));
            }
            _ => {
                // FORMAT
                if !one_word.is_some_and(|w| w.eq_ignore_ascii_case("text")) {
                    return Err(perr(
                        ln,
                        "ALTA's text format (`#FORMAT text` or no `#FORMAT` line; the binary \
                         format is not supported)"
                            .into(),
                        short(l),
                    ));
                }
                h.format = Some(ln);
            }
        }
    }
    Ok(h)
}

/// Reads an ALTA text file (header, then one sample per line) with the [`Format::Alta`]
/// options `channel` and `param_out` (see the module docs).
///
/// [`Format::Alta`]: super::Format::Alta
pub(super) fn alta_from<R: BufRead>(
    mut lines: LineSource<'_, R>,
    channel: Option<Channel>,
    param_out: Option<AltaOutput>,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    let path = lines.path();
    let perr = |line: usize, expected: String, found: String| DataError::Parse {
        path: path.to_path_buf(),
        line,
        expected,
        found,
    };
    let h = read_header(&mut lines)?;
    // Where a missing header line is reported: the first data line, or 0 at the end of file.
    let (at, at_found) = match lines.next_line()? {
        Some((ln, _)) => {
            lines.push_back();
            (ln, "the first data line".to_string())
        }
        None => (0, "end of file".to_string()),
    };
    let (dim_ln, n, p) = h
        .dim
        .ok_or_else(|| perr(at, "a `#DIM N P` header line".into(), at_found.clone()))?;
    let (in_ln, input) = h.param_in.ok_or_else(|| {
        perr(
            at,
            format!(
                "a `#PARAM_IN` header line ({})",
                names(&AltaInput::ALL, AltaInput::name)
            ),
            at_found.clone(),
        )
    })?;
    let (out_ln, output) = match (h.param_out, param_out) {
        (Some((ln, o)), Some(want)) if o != want => {
            return Err(perr(
                ln,
                format!("`#PARAM_OUT {want}` (the format option `param_out`)"),
                format!("`#PARAM_OUT {o}`"),
            ));
        }
        (Some((ln, o)), _) => (ln, o),
        (None, Some(want)) => (at, want),
        (None, None) => {
            return Err(perr(
                at,
                format!(
                    "a `#PARAM_OUT` header line ({}), or the format option `param_out` \
                     saying what the values are",
                    names(&AltaOutput::ALL, AltaOutput::name)
                ),
                at_found,
            ));
        }
    };
    if (n, p) != (input.dimension(), output.dimension()) {
        return Err(perr(
            dim_ln,
            format!(
                "`#DIM {} {}` for `#PARAM_IN {}` (line {in_ln}) and `#PARAM_OUT {output}`",
                input.dimension(),
                output.dimension(),
                input.name(),
            ),
            format!("`#DIM {n} {p}`"),
        ));
    }
    let vs = h.vs.map_or(0, |(_, v)| v);
    if let Some((vs_ln, v)) = h.vs
        && v > 0
        && p > 1
    {
        // ALTA's documentation gives one #VS per output, its reader reads the interval of the
        // first output only: the column count would be a guess.
        return Err(perr(
            vs_ln,
            format!(
                "`#VS 0` for a file with {p} outputs (confidence intervals of multi-channel files are not supported)"
            ),
            format!("`#VS {v}`"),
        ));
    }
    let col = match (output, channel) {
        (AltaOutput::RgbColor, c) => n + c.unwrap_or(DEFAULT_CHANNEL).index(),
        (_, None) => n,
        (_, Some(c)) => {
            return Err(perr(
                out_ln,
                format!(
                    "`#PARAM_OUT RGB_COLOR` for the format option `channel = \"{c}\"` (a \
                     one-channel file takes no channel)"
                ),
                format!("`#PARAM_OUT {output}`"),
            ));
        }
    };
    let width = n + p + vs;
    let cosine = output.is_cosine_weighted();
    let mut x = [0.0f64; 11];
    read_samples(&mut lines, filters, |ln, l| {
        let mut count = 0usize;
        for tok in l.split_whitespace() {
            if count < width {
                x[count] = tok.parse().map_err(|_| {
                    perr(
                        ln,
                        format!(
                            "a number (sample row: {n} input, {p} output and {vs} interval numbers)"
                        ),
                        short(tok),
                    )
                })?;
            }
            count += 1;
        }
        if count != width {
            return Err(perr(
                ln,
                format!(
                    "{width} numbers ({n} input numbers of {}, {p} output and {vs} interval numbers)",
                    input.name()
                ),
                format!("{count} numbers"),
            ));
        }
        let (u, v) = input.directions(&x[..n]).ok_or_else(|| {
            perr(
                ln,
                "non-zero CARTESIAN vectors".into(),
                format!("{:?}", &x[..n]),
            )
        })?;
        let raw = x[col];
        if !cosine {
            return Ok(Sample::new(u, v, raw));
        }
        if u[2] >= ALTA_MIN_COSINE {
            return Ok(Sample::new(u, v, raw / u[2]));
        }
        // No BRDF value at grazing incidence: marked below the horizon. When the filters drop
        // such samples a finite placeholder lets them count it there (it is never stored);
        // otherwise the value is NaN, which only `Filters::none`-like filters keep.
        let value = if filters.drop_below_horizon {
            0.0
        } else {
            f64::NAN
        };
        Ok(Sample {
            u,
            v,
            value,
            below_mark: true,
        })
    })
}

#[cfg(test)]
mod tests;
