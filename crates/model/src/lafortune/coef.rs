//! The plain types the Lafortune kernels share: per-lobe coefficients at one point, what each
//! Jacobian column differentiates, the Jacobian's inputs, and the layout of kept powers.

use super::samples::View;
use crate::family::Coord;

/// What a Lafortune parameter is (from the family's parameter names).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Field {
    Kd,
    Cx,
    Cy,
    Cxy,
    Cz,
    N,
    Pan,
}

impl Field {
    pub(crate) fn of(name: &str) -> Field {
        match name {
            "kd" => Field::Kd,
            "cx" => Field::Cx,
            "cy" => Field::Cy,
            "cxy" => Field::Cxy,
            "cz" => Field::Cz,
            "n" => Field::N,
            "pan" => Field::Pan,
            other => unreachable!("not a Lafortune parameter: {other}"),
        }
    }
}

/// Per-lobe coefficients for one parameter vector.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Coef {
    pub(crate) ap: f64,
    pub(crate) aq: f64,
    pub(crate) ar: f64,
    pub(crate) cz: f64,
    pub(crate) n: f64,
    pub(crate) c2: f64,
    pub(crate) s2: f64,
    pub(crate) cs: f64,
    pub(crate) cx: f64,
    pub(crate) cy: f64,
    pub(crate) sin2: f64,
    pub(crate) cos2: f64,
    pub(crate) no_r: bool,
    /// The exponent's coordinate (for the chain-rule factor of its column).
    pub(crate) n_coord: Coord,
}

/// What one Jacobian column differentiates.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Col {
    Kd,
    Lobe(usize, Field),
}

pub(crate) struct JacWork<'a> {
    pub(crate) coefs: &'a [Coef],
    pub(crate) cols: &'a [Col],
    pub(crate) kd: f64,
    pub(crate) data: View<'a>,
    /// `d^n` and `ln d` of every lobe and sample at this point, when a residual evaluation
    /// at the same point and data left them (every kernel but scalar).
    pub(crate) powers: Option<&'a [f64]>,
}

pub(crate) const GENERIC: u8 = 0;
pub(crate) const AVX512: u8 = 2;

/// Samples per block in the generic Jacobian: the block's directions, `g` and `h` stay in L1
/// while the lobe's columns are written.
pub(crate) const BLOCK: usize = 512;

/// Lobe `lobe`'s `(d^n, ln d)` columns in a powers buffer laid out `[f_0, l_0, f_1, l_1, ...]`,
/// each `m` long.
pub(crate) fn lobe_powers_mut(p: &mut [f64], m: usize, lobe: usize) -> (&mut [f64], &mut [f64]) {
    p[2 * lobe * m..(2 * lobe + 2) * m].split_at_mut(m)
}

/// Read-only [`lobe_powers_mut`].
pub(crate) fn lobe_powers(p: &[f64], m: usize, lobe: usize) -> (&[f64], &[f64]) {
    p[2 * lobe * m..(2 * lobe + 2) * m].split_at(m)
}

impl Default for Coef {
    fn default() -> Self {
        Coef {
            ap: 0.0,
            aq: 0.0,
            ar: 0.0,
            cz: 0.0,
            n: 0.0,
            c2: 0.0,
            s2: 0.0,
            cs: 0.0,
            cx: 0.0,
            cy: 0.0,
            sin2: 0.0,
            cos2: 0.0,
            no_r: false,
            n_coord: Coord::Identity,
        }
    }
}
