//! The Lafortune family's per-sample columns: their layout, their preparation from a data
//! set and the borrowed view the kernels read; and the factors of the Jacobian's `g` shared by
//! the generic and AVX-512 kernels.

use crate::data::DataSet;
use crate::samples::Samples;

/// The family's name in specs and commands.
pub const NAME: &str = "lafortune";

/// Column indices of the family's [`Samples`]: the directions, then the products every lobe
/// needs, `P = ux vx`, `Q = uy vy`, `R = ux vy + uy vx` (one rounding, as a fused multiply-add
/// gives) and `S = uz vz`: the same for every parameter vector, so the kernels read four
/// columns instead of six and skip recomputing them for each lobe, evaluation and Jacobian
/// column.
const UX: usize = 0;
const PXX: usize = 6;
const COLUMNS: usize = 10;

/// Borrowed columns of a range of samples (what the evaluation kernels read).
#[derive(Clone, Copy, Debug)]
pub(crate) struct View<'a> {
    pub(crate) ux: &'a [f64],
    pub(crate) uy: &'a [f64],
    pub(crate) uz: &'a [f64],
    pub(crate) vx: &'a [f64],
    pub(crate) vy: &'a [f64],
    pub(crate) vz: &'a [f64],
    pub(crate) value: &'a [f64],
    pub(crate) pxx: &'a [f64],
    pub(crate) pyy: &'a [f64],
    pub(crate) pxy: &'a [f64],
    pub(crate) pzz: &'a [f64],
}

/// Samples `lo..hi` of Lafortune samples as borrowed columns.
pub(crate) fn view(s: &Samples, lo: usize, hi: usize) -> View<'_> {
    let c = |k: usize| &s.column(k)[lo..hi];
    View {
        ux: c(UX),
        uy: c(UX + 1),
        uz: c(UX + 2),
        vx: c(UX + 3),
        vy: c(UX + 4),
        vz: c(UX + 5),
        value: &s.values()[lo..hi],
        pxx: c(PXX),
        pyy: c(PXX + 1),
        pxy: c(PXX + 2),
        pzz: c(PXX + 3),
    }
}

/// The family's columns of `data` (see [`COLUMNS`]).
pub(crate) fn prepare(data: &DataSet) -> Samples {
    let n = data.len();
    let mut cols: Vec<Vec<f64>> = (0..COLUMNS).map(|_| Vec::with_capacity(n)).collect();
    for (k, c) in [
        data.u_x(),
        data.u_y(),
        data.u_z(),
        data.v_x(),
        data.v_y(),
        data.v_z(),
    ]
    .into_iter()
    .enumerate()
    {
        cols[UX + k].extend_from_slice(c);
    }
    for i in 0..n {
        let (u, v) = (data.u(i), data.v(i));
        let products = [
            u[0] * v[0],
            u[1] * v[1],
            u[0].mul_add(v[1], u[1] * v[0]),
            u[2] * v[2],
        ];
        for (k, p) in products.into_iter().enumerate() {
            cols[PXX + k].push(p);
        }
    }
    Samples::new(NAME, cols, data.values().to_vec())
}

/// Factors `(a, b)` with `g = n d^n / d = (d^n a / d) b` computed without a spurious overflow:
/// `(1, n)` for `n >= 1` (then `d^n / d = d^(n-1)` is at most `max(1, d^n)`, so `n (d^n / d)`
/// overflows only when `g` does) and `(n, 1)` for `n < 1` (then `n d^n <= d^n`). Multiplying by
/// 1 is exact, so each case rounds exactly as `n (d^n / d)` or `(n d^n) / d`. Computing
/// `n d^n / d` left to right overflowed for large `n` with `d > 1` (e.g. `d = 1.5`,
/// `n = 1732.55`: `d^n = 1.2e305` but `n d^n = 2.1e308`, while `g = 1.41e308`).
#[inline(always)]
pub(crate) fn g_factors(n: f64) -> (f64, f64) {
    if n >= 1.0 { (1.0, n) } else { (n, 1.0) }
}
